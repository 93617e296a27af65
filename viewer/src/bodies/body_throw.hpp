#pragma once
/// @file body_throw.hpp
/// A body the sandbox throws (key T): what the HUD chooses (shape, size, density), where the body
/// starts (just in front of the camera, inside the grid, on the ray through the cursor) and how fast
/// it flies (along that ray, at a speed scaled to the grid). Pure functions, no Bullet and no window.

#include <cstddef>
#include <optional>
#include <string>

#include "granular/body.hpp"
#include "granular/geometry.hpp"

namespace viewer {

/// The smallest half size of a thrown body, in cells (a box's half edge, a ball's radius).
inline constexpr double kMinThrowHalfSize = 3;
/// The largest half size of a thrown body, in cells.
inline constexpr double kMaxThrowHalfSize = 6;
/// The lightest density the HUD offers, kg/m^3 (cork; floats high in water and sand).
inline constexpr double kMinThrowDensity = 300;
/// The densest the HUD offers, kg/m^3 (steel; sinks in everything).
inline constexpr double kMaxThrowDensity = 8000;
/// The most bodies the sandbox holds: each one costs a region read and write every tick it moves
/// (docs/design/bodies.md, "Cost"), so a throw past this is refused with a message.
inline constexpr std::size_t kMaxSandboxBodies = 16;

/// What the HUD chooses for the next throw.
struct ThrowChoice {
  granular::BodyShape shape = granular::BodyShape::Sphere;  ///< Box (a cube) or Sphere (a ball)
  double half_size = 4;                                     ///< cells, kMinThrowHalfSize..kMaxThrowHalfSize
  double density = 800;                                     ///< kg/m^3, kMinThrowDensity..kMaxThrowDensity
};

/// The half size that suits a grid of `size`: its smallest extent / 32, within kMinThrowHalfSize..
/// kMaxThrowHalfSize (4 cells, a body 8 cells across, at N = 128).
double default_half_size(granular::Int3 size);

/// The speed of a throw, in m/s: the grid's narrower horizontal width in the time a body falls
/// freely from its top to its floor, so a throw from one side crosses the grid as it falls (1.77 m/s
/// for N = 128 and 5 mm cells). Throws std::invalid_argument for an empty grid or a cell_metres that
/// is not finite and > 0.
double throw_speed(granular::Int3 size, double cell_metres);

/// What a density does in the presets' sand (1,600 kg/m^3) and water (1,000): "floats in water and
/// sand", "sinks in water, floats in sand" or "sinks in water and sand".
std::string density_effect(double density);

/// The body `choice` describes thrown from `origin` along `direction` (cells, z up; any length > 0)
/// at `speed_mps` into a grid of `size` with cells of `cell_metres` and ticks of `tick_seconds`. It
/// starts at the first point of the ray at least its bounding radius + 1 cell from `origin` (so it
/// does not cover the eye) where its bounding sphere lies a cell or more inside the grid, and flies
/// along the ray (velocity in cells per tick; no spin). Nullopt when the ray passes no such point: it
/// misses the grid, or the grid is too small for the body. Throws std::invalid_argument for a choice
/// out of range (shape, size, density), a direction that is zero or not finite, an origin that is
/// not finite, a speed or a unit that is not finite and > 0.
std::optional<granular::BodyDef> aim_throw(const ThrowChoice& choice, granular::Vec3 origin, granular::Vec3 direction,
                                           granular::Int3 size, double speed_mps, double cell_metres,
                                           double tick_seconds);

/// The radius of the sphere around the centre that holds `choice`'s body whatever its orientation.
double bounding_radius(const ThrowChoice& choice);

/// "ball", "box" or "capsule".
const char* shape_name(granular::BodyShape shape);

}  // namespace viewer
