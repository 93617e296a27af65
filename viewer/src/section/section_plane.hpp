#pragma once
/// @file section_plane.hpp
/// The section plane of the sandbox: a plane across one axis of the grid at a fraction of its
/// extent, which removes the half of the cells between the camera and the plane so that the cut
/// face shows what lies inside (`--section y:0.5`; keys V, comma and period).

#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "granular/geometry.hpp"

namespace viewer {

/// Where the plane cuts for one eye position: the cells it keeps on one side of a cell boundary.
struct SectionCut {
  int axis = 0;             ///< 0, 1, 2: x, y, z
  int plane = 0;            ///< the boundary between cells plane - 1 and plane along `axis` (0..extent)
  bool keeps_high = false;  ///< kept: cells at or above `plane` (true) or below it (false)

  /// True when cell `p` lies on the removed side.
  bool removes(granular::Int3 p) const;
};

/// A section plane across `axis` at `fraction` of the grid's extent, or none (axis < 0).
struct SectionPlane {
  /// The step of `,` and `.`: 1/32 of the axis.
  static constexpr double kStep = 1.0 / 32.0;

  int axis = -1;          ///< 0, 1, 2 for x, y, z; -1: no section
  double fraction = 0.5;  ///< where along the axis, 0..1 (kept while the section is off)

  /// True while the plane cuts.
  bool on() const { return axis >= 0; }
  /// The next state of V: off -> x -> y -> z -> off, at the same fraction.
  SectionPlane cycled() const;
  /// The plane moved by `steps` kSteps (negative: towards lower coordinates), within 0..1; unchanged
  /// while off.
  SectionPlane moved(int steps) const;
  /// Where it cuts a grid of `size` seen from `eye` (cells): the plane at the cell boundary nearest
  /// to fraction x extent, keeping the half away from the eye. Nothing while off.
  std::optional<SectionCut> cut(granular::Int3 size, glm::vec3 eye) const;
  /// "y 0.50", or "off".
  std::string describe() const;
};

/// Parses `--section` values "AXIS:FRACTION" (AXIS x, y or z; FRACTION a number in 0..1); throws
/// std::invalid_argument naming the option and the value otherwise.
SectionPlane parse_section(const std::string& text);

}  // namespace viewer
