#pragma once
/// @file change_report.hpp
/// What a tool (dig, pour, paint, shake) did to the world.

#include <cstdint>

#include "granular/geometry.hpp"
#include "granular/material.hpp"

namespace granular {

/// The result of a tool: which cells changed and how.
struct ChangeReport {
  std::int64_t cells_changed = 0;  ///< number of cells whose material changed
  MaterialCounts added{};          ///< cells that became each material
  MaterialCounts removed{};        ///< cells that stopped being each material
  Box region{};                    ///< the in-grid box the tool covered (may be smaller than asked: see clipped)
  bool clipped = false;            ///< true when part of the tool's region lay outside the grid
  std::int64_t cells_shaken = 0;   ///< cells the tool set moving (World::shake; no material changes)
};

}  // namespace granular
