#pragma once
/// @file cell_checks.hpp
/// The checks of cells a World is given (an initial grid, a snapshot, load, restore, an undo's
/// bricks): each throws InvalidArgument naming the cell and the value it holds.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "granular/errors.hpp"
#include "granular/geometry.hpp"

namespace granular {

struct RuleSet;

/// "cell (x, y, z)" of cell `i` (x fastest) of a grid of `size`.
std::string cell_text(std::size_t i, Int3 size);

/// Throws InvalidArgument starting with `what` naming the first of `cells` (a grid of `size`) that
/// is not a material value (0..7).
void check_cells(std::span<const std::uint8_t> cells, Int3 size, const char* what);

/// For each of the 256 cell bytes, what keeps a world under `rules` from holding it ("" when
/// nothing): the motion state (bits 3..7) belongs to granular and liquid cells under a motion model,
/// at a level up to MotionParams::max_level(), and to wakes under MotionParams::columns.
std::array<std::string, 256> cell_byte_problems(const RuleSet& rules);

/// Throws InvalidArgument starting with `what` when one of `cells` is a byte a world under `rules`
/// cannot hold (cell_byte_problems), naming the byte and, through where(i), cell i.
template <class Where>
void check_cell_bytes(std::span<const std::uint8_t> cells, const RuleSet& rules, const std::string& what,
                      Where&& where) {
  const std::array<std::string, 256> problems = cell_byte_problems(rules);
  std::array<bool, 256> bad{};
  for (unsigned b = 0; b < 256; ++b) bad[b] = !problems[b].empty();
  const auto first = std::find_if(cells.begin(), cells.end(), [&](std::uint8_t c) { return bad[c]; });
  if (first == cells.end()) return;
  const auto i = std::size_t(first - cells.begin());
  throw InvalidArgument(what + ": " + where(i) + " holds the byte " + std::to_string(unsigned(*first)) + ": " +
                        problems[*first]);
}

/// Throws InvalidArgument starting with `what` when `side` (WorldSnapshot::side of `cells`, a grid
/// of `size`) cannot be a side plane under `rules`: it is neither empty nor one byte per cell, it
/// holds a velocity under rules without MotionParams::momentum, on a cell that is not a liquid, or
/// with a component of -8 (momentum.hpp: each lies in -7..7); names the cell and the byte.
void check_side_bytes(std::span<const std::uint8_t> side, std::span<const std::uint8_t> cells, Int3 size,
                      const RuleSet& rules, const std::string& what);

/// Throws InvalidArgument starting with `what` when `faces` (WorldSnapshot::faces of a grid of
/// `size`) cannot be a face plane under `rules`: it is neither empty nor 4 values per column, it holds
/// a non-zero value under rules without MotionParams::shallow, a velocity beyond shallow::kMaxSpeed,
/// a fraction of a whole cell or more, or a non-zero value on a face at the grid's edge (a wall);
/// names the column, the field and the value.
void check_face_plane(std::span<const std::int32_t> faces, Int3 size, const RuleSet& rules, const std::string& what);

}  // namespace granular
