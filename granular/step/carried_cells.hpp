#pragma once
/// @file carried_cells.hpp
/// Carried trains (MotionParams::trains): the cells of a body in free fall that the trains pass moves
/// as a unit, and that the block step therefore reads as a static obstacle. Shared by the block step
/// (block_step.hpp: MotionRule), the trains pass (column_trains.hpp) and the snapshot checks.
///
/// A *carried* grain is a granular grain whose motion level bits hold kCarriedLevel: it belongs to an
/// airborne train whose grains fall together. The cells right under the train that it falls through
/// in the current tick are its *sweep*: voids whose level bits hold kCarriedLevel too (*swept*), as
/// many as the train falls in the tick, motion_window(L) at its level L, which the sweep's length
/// therefore gives (sweep_level). No other byte has those level bits (they are above every level of
/// a rule set with trains, and a wake's level is a grain's), so a block's hidden cells are found
/// from its bytes alone. Nothing else may enter a swept cell in the tick: to the block step both
/// read as a static material, so a body in free fall costs the block step nothing and its bricks
/// sleep; after the tick's last sub-step the trains pass moves every carried train down through its
/// sweep in one move (column_trains.hpp). A swept cell, or a carried grain over a cell that is
/// neither carried nor swept (a train whose sweep a tool or a file took away), keeps its block from
/// being quiet (carried_unsettled), so sparse stepping keeps the bricks at a falling body's front
/// awake and the pass, which walks the columns of awake bricks, finds every carried train.

#include <cstdint>

#include "granular/motion.hpp"
#include "step/block_bytes.hpp"
#include "step/step_materials.hpp"

namespace granular::carried {

/// True when `cell` holds kCarriedLevel in its level bits: a carried grain or a swept void.
constexpr bool is_hidden(std::uint8_t cell) { return cell_motion(cell) == kCarriedLevel; }

/// True when `cell` is a carried grain.
constexpr bool is_carried(const StepMaterials& m, std::uint8_t cell) {
  return is_hidden(cell) && m.is_granular(cell & kMaterialMask);
}

/// True when `cell` is a swept void.
constexpr bool is_swept(const StepMaterials& m, std::uint8_t cell) { return is_hidden(cell) && m.is_void(cell & kMaterialMask); }

/// `cell` hidden: its material with kCarriedLevel in its level bits and no phase bit; a granular
/// grain carried, a void swept. A carried grain takes part in no sub-step and sub-step 0 notes a
/// grain's phase anew once it lands, so its phase is dropped, and a train of one material moved down
/// is the same bytes but at its ends.
constexpr std::uint8_t hidden_cell(std::uint8_t cell) {
  return std::uint8_t((cell & kMaterialMask) | (kCarriedLevel << kMotionShift));
}

/// The level of a train whose sweep is `length` cells long: the level L with motion_window(L) =
/// length (the longest such level when a tool shortened the sweep).
constexpr int sweep_level(int length) { return (length + 1) / 2; }

/// 0xFF in each byte of a block's `bytes` that is hidden (is_hidden), 0 in the others.
constexpr std::uint64_t hidden_mask(std::uint64_t bytes) {
  const std::uint64_t level = (bytes >> kMotionShift) & (kEveryByte * kMotionLevelMask);
  return (((level + kEveryByte) >> 4) & kEveryByte) * 0xFFu;
}

/// `bytes` with each byte of `mask` (0xFF or 0 per byte) replaced by the static material m.outside:
/// what the block step sees of a block holding hidden cells, for its quiet test and reach.
constexpr std::uint64_t hide(std::uint64_t bytes, std::uint64_t mask, const StepMaterials& m) {
  return (bytes & ~mask) | (mask & (kEveryByte * m.outside));
}

/// A carried grain as the block step reads it: the static material m.outside falling at
/// kFallingLevel, which no other byte is (a static material has no motion level), so that a grain
/// slipping over it keeps its level as one slipping past a falling grain does
/// (motion::in_falling_body) while nothing moves it.
constexpr std::uint8_t falling_static(const StepMaterials& m) {
  return std::uint8_t(m.outside | (std::uint32_t(kFallingLevel) << kMotionShift));
}

/// `bytes` with each hidden byte of `mask` replaced as the block step reads it: a swept void by the
/// static material m.outside, a carried grain by falling_static.
constexpr std::uint64_t hide_for_step(std::uint64_t bytes, std::uint64_t mask, const StepMaterials& m) {
  std::uint64_t out = bytes & ~mask;
  for (int p = 0; p < 8; ++p)
    if (((mask >> (8 * p)) & 1u) != 0)
      out |= std::uint64_t(m.is_granular(byte_at(bytes, p) & kMaterialMask) ? falling_static(m) : m.outside) << (8 * p);
  return out;
}

/// True when a block's `bytes`, whose hidden cells are `mask` (hidden_mask), hold a swept void, or a
/// carried grain over a cell of its block column that is not hidden (the lowest grain of a train
/// whose sweep is gone): the trains pass has work there at the tick's end, so the block is not quiet
/// and its brick stays awake.
constexpr bool carried_unsettled(std::uint64_t bytes, std::uint64_t mask, const StepMaterials& m) {
  for (int p = 0; p < 8; ++p) {
    if (((mask >> (8 * p)) & 1u) == 0) continue;
    if (!m.is_granular(byte_at(bytes, p) & kMaterialMask)) return true;       // a swept void
    if (p >= 4 && ((mask >> (8 * (p - 4))) & 1u) == 0) return true;           // a train's lowest grain, unswept
  }
  return false;
}

}  // namespace granular::carried
