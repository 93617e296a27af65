#pragma once
/// @file cell_classes.hpp
/// A byte per cell from a 32-entry table, indexed by a mark (0..3) and a cell's material: what the
/// stamp's searches ask of each cell of a body's region (body_stamp.cpp).

#include <array>
#include <cstdint>
#include <span>

#include "granular/material.hpp"
#include "granular/motion.hpp"

namespace granular {

/// The table: per mark, per material, the cell's class byte.
using CellClassTable = std::array<std::array<std::uint8_t, kMaterialCount>, 4>;

/// out[i] = table[marks[i]][bytes[i] & kMaterialMask] for every i of `out` (`marks` and `bytes` as
/// long, each mark below 4); sixteen cells a step where the CPU has a byte shuffle (SSSE3), the same
/// bytes either way.
void classify_cells(const CellClassTable& table, std::span<const std::uint8_t> marks,
                    std::span<const std::uint8_t> bytes, std::span<std::uint8_t> out);

}  // namespace granular
