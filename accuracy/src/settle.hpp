#pragma once
/// @file settle.hpp
/// Running a world until it comes to rest.

#include <cstdint>

#include "granular/world.hpp"

namespace granular::accuracy {

/// How a settle run ended.
struct SettleResult {
  std::uint64_t ticks = 0;  ///< ticks stepped until the last changing cycle ended (the stop time)
  bool settled = false;     ///< true when an 8-tick cycle left the grid unchanged within the limit
};

/// Steps `world` in 8-tick cycles (a full offset cycle) until a cycle ends with the hash it
/// started with, or `max_ticks` have passed. The stop time excludes that last, unchanged cycle.
SettleResult settle(World& world, std::uint64_t max_ticks);

}  // namespace granular::accuracy
