#pragma once
/// @file scene_shapes.hpp
/// Private: the scene rounding rule (fractions of N to cells), and parsing and drawing of scene
/// shapes. All geometry is evaluated in integer sixteenths of a cell, so a given N always gives
/// the same cells on every platform.

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "granular/grid.hpp"
#include "granular/scene.hpp"

namespace granular::scene_detail {

/// Sub-cell resolution of scaled positions: values are rounded to 1/kSubcell of a cell.
inline constexpr std::int64_t kSubcell = 16;

/// Largest magnitude of a scaled position or length, in cells.
inline constexpr double kMaxScaledCells = 16777216.0;

/// Floor division for a positive divisor.
constexpr std::int64_t floor_div(std::int64_t a, std::int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

/// round(fraction * n * 16): a fraction of N as sixteenths of a cell, halves away from zero.
/// Throws InvalidArgument (naming `what`) when the result exceeds kMaxScaledCells.
std::int64_t to_sixteenths(double fraction, int n, const std::string& what);

/// The whole-cell boundary nearest to a value in sixteenths, halves up: floor(v / 16 + 1/2).
constexpr std::int64_t cell_boundary(std::int64_t sixteenths) { return floor_div(sixteenths + kSubcell / 2, kSubcell); }

/// Parses the shape object `value` found at `path` ("shapes[2]") of the scene `source`.
ShapeDef parse_shape(const nlohmann::json& value, const std::string& path, const std::string& source);

/// Draws `shape` at size parameter `n` into `grid` (cells outside the grid are ignored). Throws
/// InvalidArgument when a scaled value is out of range or a bowl's wall is thicker than its radius.
void draw_shape(Grid& grid, const ShapeDef& shape, int n, const std::string& source);

}  // namespace granular::scene_detail
