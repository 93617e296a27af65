#pragma once
/// @file all_bricks.hpp
/// The list of every brick of a grid, as World passes it to a backend write that wakes every brick.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "granular/bricks.hpp"
#include "granular/geometry.hpp"

namespace granular {

/// Every brick of a grid of `size`, ascending.
inline std::vector<std::uint32_t> all_bricks(Int3 size) {
  const Int3 n = brick_counts(size);
  std::vector<std::uint32_t> bricks(std::size_t(n.x) * std::size_t(n.y) * std::size_t(n.z));
  for (std::size_t i = 0; i < bricks.size(); ++i) bricks[i] = std::uint32_t(i);
  return bricks;
}

}  // namespace granular
