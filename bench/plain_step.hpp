#pragma once
/// @file plain_step.hpp
/// The baseline the CPU backend is measured against: the paper's per-block loop on a byte per
/// cell (gather 8 cells, build the key, look the transition up, scatter by the permutation), with
/// the same boundary handling, threaded over block layers like the backend.

#include <cstdint>

#include "granular/block.hpp"
#include "granular/geometry.hpp"

namespace granular::bench {

/// One tick of the plain loop over the whole grid, split over `threads` std::threads.
void plain_step(std::uint8_t* cells, Int3 size, const Transition* lut, std::uint64_t tick, int threads);

}  // namespace granular::bench
