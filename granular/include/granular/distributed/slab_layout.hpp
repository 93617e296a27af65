#pragma once
/// @file distributed/slab_layout.hpp
/// How a DistributedWorld splits its grid: into z-slabs, one per rank, each kept with `halo` layers
/// of its neighbours' cells on either side (distributed_world.hpp has why that many).

#include "granular/geometry.hpp"

namespace granular {

struct RuleSet;

/// One rank's part of the grid, in the whole grid's z.
struct Slab {
  int z0 = 0, z1 = 0;              ///< the layers this rank owns and steps: [z0, z1)
  int local_z0 = 0, local_z1 = 0;  ///< the layers it keeps: the owned ones and its halo, [local_z0, local_z1)
  /// The owned layers as a box of the whole grid.
  Box owned(Int3 size) const { return {{0, 0, z0}, {size.x, size.y, z1}}; }
  /// The kept layers as a box of the whole grid.
  Box kept(Int3 size) const { return {{0, 0, local_z0}, {size.x, size.y, local_z1}}; }
};

/// The split of a grid of `size` into `ranks` z-slabs of nearly equal height, each boundary at an
/// even z (the block partition's parity), with `halo` layers kept beyond each inner boundary.
class SlabLayout {
 public:
  /// Throws InvalidArgument naming the value for ranks < 1, a halo that is odd or below 2, a layer
  /// of fewer than 4 cells (x * y), or a slab thinner than the halo (a rank's halo must come from its
  /// neighbour alone): use fewer ranks or a taller grid.
  SlabLayout(Int3 size, int ranks, int halo);
  /// The halo a tick of `rules` needs: one layer per sub-step (a change travels at most one layer
  /// per Margolus sub-step), rounded up to even. Throws RuleError (validate_rule_set) for rules
  /// that are not valid, so a sub-step count out of range is named before it is used.
  static int halo_for(const RuleSet& rules);
  /// The whole grid's extent.
  Int3 size() const { return size_; }
  /// Ranks (slabs).
  int ranks() const { return ranks_; }
  /// Layers kept beyond each inner boundary.
  int halo() const { return halo_; }
  /// The slab of rank `r` (0 .. ranks() - 1; rank 0 holds the bottom).
  Slab slab(int r) const;

 private:
  Int3 size_{};
  int ranks_ = 1;
  int halo_ = 2;
};

}  // namespace granular
