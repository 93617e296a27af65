#pragma once
/// @file motion_table.hpp
/// The motion table (motion_block.hpp, kMotionTableKeys) derived from a motion rule set's full
/// transition table: what the CPU and the CUDA backend look up when stepping the motion model.

#include <span>
#include <vector>

#include "granular/block.hpp"

namespace granular {

/// The motion table of `lut`, the transition table of a motion rule set (kBlockKeyCount entries):
/// entry k is lut[full_code_key(k)].
std::vector<Transition> derive_motion_table(std::span<const Transition> lut);

}  // namespace granular
