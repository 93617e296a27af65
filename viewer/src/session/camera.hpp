#pragma once
/// @file camera.hpp
/// The orbit camera of the sandbox (cell units, z up) and the rays it casts through pixels.

#include <glm/glm.hpp>
#include <string>

#include "granular/geometry.hpp"

namespace viewer {

/// A camera orbiting `target` at `distance`, turned by yaw (around z) and pitch (above the xy plane).
struct OrbitCamera {
  glm::vec3 target{0.0f};    ///< the point looked at (cells)
  float yaw_degrees = 35;    ///< angle around z from +x
  float pitch_degrees = 30;  ///< elevation, in (-89, 89)
  float distance = 100;      ///< from target to eye (cells)
  float fov_degrees = 45;    ///< vertical field of view

  /// A view of a whole grid of `size` cells from above one corner (the target a little below the
  /// grid's centre, at 1.9 times its largest extent).
  static OrbitCamera framing(granular::Int3 size);
  /// A view of the cells of `box` from the default angles, looking at its centre from the
  /// distance at which its eight corners fill `fill` (0..1) of an image of `aspect` (width /
  /// height) along its tighter axis.
  static OrbitCamera framing(const granular::Box& box, float aspect, float fill = 0.9f);
  /// Parses "yaw,pitch,distance[,tx,ty,tz]" (degrees; distance and target as fractions of the
  /// grid's largest extent and extents) over framing(size); throws std::invalid_argument naming the value.
  static OrbitCamera parse(const std::string& text, granular::Int3 size);

  /// The eye position.
  glm::vec3 eye() const;
  /// World to view.
  glm::mat4 view() const;
  /// View to Vulkan clip space (depth 0..1, y down) for `aspect` = width / height.
  glm::mat4 projection(float aspect) const;

  /// Turns by pixel deltas (drag).
  void orbit(float dx, float dy);
  /// Moves the target in the view plane by pixel deltas (drag), scaled by distance.
  void pan(float dx, float dy);
  /// Multiplies the distance by `factor` (> 0).
  void zoom(float factor);
  /// Moves eye and target together: `forward` along the view direction, `right`, `up` (cells).
  void fly(float forward, float right, float up);
};

/// A ray in cell units.
struct Ray {
  glm::vec3 origin{0.0f};     ///< start
  glm::vec3 direction{0.0f};  ///< unit direction
};

/// The ray from the eye through pixel (x, y) (top-left origin) of a `width` x `height` image.
Ray ray_through_pixel(const OrbitCamera& camera, float x, float y, float width, float height);

}  // namespace viewer
