#pragma once
/// @file motion_table.hpp
/// The motion entries (motion_block.hpp, MotionEntry) derived from a motion rule set's full
/// transition table: what the CPU and the CUDA backend look up when stepping the motion model.

#include <span>
#include <vector>

#include "granular/extend/block.hpp"
#include "step/motion_block.hpp"

namespace granular {

/// The motion entries of `lut`, the transition table of a motion rule set (kBlockKeyCount entries):
/// entry (symmetry << 16) | k is motion_entry of the motion table's transition at the key k seen
/// under that symmetry, lut[full_code_key(viewed_motion_key(k, symmetry))] (kMotionEntries
/// entries, 2 MiB).
std::vector<motion::MotionEntry> derive_motion_table(std::span<const Transition> lut);

}  // namespace granular
