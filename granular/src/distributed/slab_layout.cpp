#include "granular/distributed/slab_layout.hpp"

#include <algorithm>
#include <cstdint>
#include <string>

#include "granular/errors.hpp"
#include "granular/grid.hpp"
#include "granular/rule_set.hpp"

namespace granular {

namespace {

/// The lower boundary of slab `r`: r / ranks of the height, rounded to the nearest even layer (the
/// top of the last slab is the grid's top, which may be odd).
int boundary(int height, int ranks, int r) {
  if (r >= ranks) return height;
  return int(2 * ((std::int64_t(height) * r + ranks) / (2 * std::int64_t(ranks))));
}

}  // namespace

SlabLayout::SlabLayout(Int3 size, int ranks, int halo) : size_(size), ranks_(ranks), halo_(halo) {
  if (ranks < 1) throw InvalidArgument("SlabLayout: ranks = " + std::to_string(ranks) + "; use 1 or more");
  if (halo < 2 || halo % 2 != 0)
    throw InvalidArgument("SlabLayout: halo = " + std::to_string(halo) + "; use an even number of layers, 2 or more");
  if (size.x < 1 || size.y < 1 || size.z < 1)
    throw InvalidArgument("SlabLayout: size = " + to_string(size) + "; every extent must be 1 or more");
  if (ranks > 1 && std::int64_t(size.x) * size.y < 4)
    throw InvalidArgument("SlabLayout: a layer of the " + to_string(size) + " grid holds " +
                          std::to_string(std::int64_t(size.x) * size.y) +
                          " cells; a grid split into slabs needs at least 4 per layer");
  for (int r = 0; r < ranks; ++r) {
    const Slab s = slab(r);
    if (ranks > 1 && s.z1 - s.z0 < halo)
      throw InvalidArgument("SlabLayout: the " + to_string(size) + " grid split into ranks = " + std::to_string(ranks) +
                            " slabs gives rank " + std::to_string(r) + " " + std::to_string(s.z1 - s.z0) +
                            " layers, fewer than its halo of " + std::to_string(halo) +
                            " (the layers a tick can carry a change across); use at most " +
                            std::to_string(std::max(1, size.z / (halo + 2))) + " ranks or a taller grid");
  }
}

int SlabLayout::halo_for(const RuleSet& rules) {
  validate_rule_set(rules);  // bounds the sub-step count (at most 32) before it is rounded up
  const int substeps = std::max(1, rules.motion.substeps);
  return std::max(2, substeps + substeps % 2);
}

Slab SlabLayout::slab(int r) const {
  if (r < 0 || r >= ranks_)
    throw InvalidArgument("SlabLayout::slab: r = " + std::to_string(r) + " is outside 0.." + std::to_string(ranks_ - 1));
  Slab s;
  s.z0 = boundary(size_.z, ranks_, r);
  s.z1 = boundary(size_.z, ranks_, r + 1);
  s.local_z0 = std::max(0, s.z0 - halo_);
  s.local_z1 = std::min(size_.z, s.z1 + halo_);
  return s;
}

}  // namespace granular
