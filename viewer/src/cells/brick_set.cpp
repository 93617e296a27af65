#include "cells/brick_set.hpp"

#include <cstdint>
#include <algorithm>

namespace viewer {
namespace {

/// The bricks marked non-zero in `marked`, in index order.
std::vector<std::uint32_t> marked_bricks(const std::vector<std::uint8_t>& marked) {
  std::vector<std::uint32_t> result;
  for (std::uint32_t brick = 0; brick < marked.size(); ++brick)
    if (marked[brick]) result.push_back(brick);
  return result;
}

}  // namespace

std::vector<std::uint32_t> with_neighbours(std::span<const std::uint32_t> changed, granular::Int3 counts) {
  const std::uint32_t total = std::uint32_t(counts.x) * counts.y * counts.z;
  if (changed.size() * 4 >= total) return all_bricks(counts);
  std::vector<std::uint8_t> marked(total, 0);
  const std::uint32_t nx = std::uint32_t(counts.x), ny = std::uint32_t(counts.y);
  for (std::uint32_t brick : changed) {
    const int x = int(brick % nx), y = int(brick / nx % ny), z = int(brick / (nx * ny));
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int px = x + dx, py = y + dy, pz = z + dz;
          if (px < 0 || py < 0 || pz < 0 || px >= counts.x || py >= counts.y || pz >= counts.z) continue;
          marked[std::size_t(px) + nx * (std::size_t(py) + ny * std::size_t(pz))] = 1;
        }
  }
  return marked_bricks(marked);
}

std::vector<std::uint32_t> united(std::span<const std::uint32_t> a, std::span<const std::uint32_t> b,
                                  granular::Int3 counts) {
  std::vector<std::uint8_t> marked(std::size_t(counts.x) * counts.y * counts.z, 0);
  for (std::uint32_t brick : a) marked[brick] = 1;
  for (std::uint32_t brick : b) marked[brick] = 1;
  return marked_bricks(marked);
}

}  // namespace viewer
