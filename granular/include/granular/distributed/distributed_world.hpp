#pragma once
/// @file distributed/distributed_world.hpp
/// A world split into z-slabs, one per rank of a Communicator (ranks that are MPI processes, or
/// threads of one process: local_group.hpp), each rank stepping its slab with a World of its own
/// (any backend) and exchanging halo layers with its neighbours: the same cells, tick for tick, as
/// one World of the whole grid (the same hash for every rule set, material, backend and tool).
///
/// Why it equals one World: a slab's World is a World of its kept layers (its own and `halo` of
/// each neighbour's) whose domain origin (WorldDef::domain_origin) is where they lie in the whole
/// grid, so its random draws are the whole world's. Its cells outside the kept layers read as an
/// obstacle, which is wrong for an inner boundary, but a Margolus sub-step carries a change at most
/// one layer, so after one tick of S sub-steps only the S layers next to that boundary can differ
/// from the whole world's: the halo (S layers, rounded up to even) absorbs them. Before each tick
/// every rank sends its lowest and highest `halo` owned layers to the neighbour below and above and
/// writes what it receives over its halo, waking only the bricks whose cells differ, so a settled
/// boundary costs its exchange and nothing else.
///
/// Every member except the accessors is collective: every rank calls it, in the same order, with the
/// same arguments. A tool changes only the cells a rank owns; the halo catches up before the next
/// tick.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <utility>

#include "granular/distributed/communicator.hpp"
#include "granular/grid.hpp"
#include "granular/distributed/slab_layout.hpp"
#include "granular/change_report.hpp"
#include "granular/world.hpp"
#include "granular/world_def.hpp"

namespace granular {

class ReadableFile;
struct SnapshotHeader;

/// What a rank's halo exchanges cost (DistributedWorld::last_exchange).
struct HaloExchangeStats {
  double seconds = 0;          ///< in all
  double read_seconds = 0;     ///< reading the layers to send out of the slab's World (its backend)
  double message_seconds = 0;  ///< in the Communicator: moving bytes, and waiting for the neighbours
  double write_seconds = 0;    ///< writing the layers received over the halo (compare, write, wake)
  std::uint64_t bytes_sent = 0;  ///< layers sent to the neighbours
};

/// One rank's share of a world split into z-slabs.
class DistributedWorld {
 public:
  /// The world `def` describes (def.size is the whole grid; def.domain_origin must be (0, 0, 0)),
  /// all void, split over the ranks of `comm`, which must outlive this world. Throws what World
  /// throws for `def`, and InvalidArgument from SlabLayout when the grid cannot be split so. Every
  /// constructor first gathers every rank's size, seed and rule fingerprint: ranks given different
  /// worlds (collective misuse) all throw InvalidArgument naming both ranks' worlds, and a rank
  /// that cannot make its layout fails every rank.
  DistributedWorld(const WorldDef& def, Communicator& comm);
  /// The same, starting from `whole` (the whole grid, the same on every rank; each keeps its slab).
  DistributedWorld(const WorldDef& def, Communicator& comm, const Grid& whole);
  /// The same, continuing `snapshot` (the whole world's, the same on every rank) bit-identically.
  DistributedWorld(const WorldDef& def, Communicator& comm, const WorldSnapshot& snapshot);
  /// The same, continuing the snapshot file at `path` (written by World or by save()), which every
  /// rank reads, keeping its slab's cells only (memory for the slab, not the whole grid). Each rank
  /// checks, in order, a regular file (a FIFO cannot hang it), the header, the sizes against the
  /// file, zstd's expansion and the memory budget (its slab's), each zstd frame's stated size, and
  /// only then decompresses. Throws load_snapshot's errors, on every rank.
  DistributedWorld(const WorldDef& def, Communicator& comm, const std::filesystem::path& path);
  ~DistributedWorld();
  DistributedWorld(const DistributedWorld&) = delete;
  DistributedWorld& operator=(const DistributedWorld&) = delete;

  /// Runs `ticks` ticks (>= 0): before each one the halos are brought up to date. Collective.
  void step(int ticks = 1);
  /// Ticks run so far.
  std::uint64_t tick() const { return slab_->tick(); }
  /// The whole grid's extent.
  Int3 size() const { return layout_.size(); }
  /// The rule set.
  const RuleSet& rules() const { return slab_->rules(); }
  /// The split.
  const SlabLayout& layout() const { return layout_; }
  /// This rank's slab.
  const Slab& slab_range() const { return slab_range_; }
  /// This rank.
  int rank() const { return comm_.rank(); }
  /// This rank's World: its kept layers (owned and halo) at domain origin (0, 0, slab_range().local_z0).
  /// Its halo is up to date right before a tick; read only the owned layers between ticks.
  const World& slab() const { return *slab_; }
  /// What bringing the halos up to date cost this rank in the last step().
  const HaloExchangeStats& last_exchange() const { return exchange_; }

  /// The whole world's hash (World::hash of one World of the whole grid), on every rank. Collective.
  std::uint64_t hash();
  /// The whole world's cells per material, on every rank. Collective.
  MaterialCounts count();
  /// The whole grid (cell bytes with their motion state, as World::read_region of the whole grid) on
  /// rank `root`; an empty grid on the others. Collective; for grids that fit one rank's memory.
  Grid gather(int root = 0);
  /// The whole world's snapshot (World::capture) on rank `root`; one with no cells on the others.
  /// Collective.
  WorldSnapshot capture(int root = 0);
  /// Writes the whole world's snapshot file (docs/FORMATS.md, version kSnapshotVersion): each
  /// rank compresses its slab into a zstd frame of its own, rank `root` writes the header and the
  /// frames in rank order, atomically. World(def, load_snapshot(path)) and a DistributedWorld over
  /// any number of ranks continue it bit-identically. Throws save_snapshot's errors, on every rank.
  /// Collective.
  void save(const std::filesystem::path& path, int root = 0);

  /// World::dig of the whole world; the report (cells changed, added, removed) sums every rank's.
  /// Collective.
  ChangeReport dig(const Sphere& sphere);
  /// World::shake of the whole world. Collective.
  ChangeReport shake(const Sphere& sphere, int level);
  /// World::pour of the whole world: the same cells as one World of the whole grid fills (the
  /// `amount` void cells of the smallest keys over every slab). Collective.
  ChangeReport pour(Vec3 center, double radius, Material material, std::int64_t amount);
  /// World::paint of a box of the whole world. Collective.
  ChangeReport paint(const Box& box, Material material);
  /// World::paint of a sphere of the whole world. Collective.
  ChangeReport paint(const Sphere& sphere, Material material);

 private:
  // Continues the snapshot file at `path`, open and its header read (`opened`).
  DistributedWorld(const WorldDef& def, Communicator& comm, const std::filesystem::path& path,
                   const std::pair<std::unique_ptr<ReadableFile>, SnapshotHeader>& opened);
  // Makes rank comm.rank()'s slab World of a world of `size` with make_slab(local def, slab).
  DistributedWorld(const WorldDef& def, Communicator& comm, Int3 size,
                   const std::function<std::unique_ptr<World>(const WorldDef&, const Slab&)>& make_slab);
  // The whole world's snapshot without its cells.
  WorldSnapshot meta() const;
  // Sends the owned boundary layers to the neighbours and writes what they send over the halo.
  void exchange_halos();
  // Writes `bytes` (the whole grid's layers [z0, z0 + bytes / layer)) over this slab's copy, only the
  // cells that differ, waking their bricks (none when none differs).
  void write_halo(int z0, std::span<const std::uint8_t> bytes);
  // True when a brick holding one of the whole grid's layers [z0, z1) changed since the last exchange.
  bool changed_since_exchange(int z0, int z1) const;
  // Reads the whole grid's layers [z0, z1) (owned or halo) of this slab into `out`.
  void read_layers(int z0, int z1, std::span<std::uint8_t> out) const;
  // Calls fn(z0, z1, bytes) over the owned layers in chunks of at most 64 MiB.
  void for_each_owned_chunk(const std::function<void(int, int, std::span<const std::uint8_t>)>& fn) const;
  // A tool over `region` (the whole grid's box it covers, checked): runs `local` (the tool on this
  // slab's World, which takes the whole world's shapes) when `here`, else counts the call; sums the
  // ranks' reports.
  template <class Local>
  ChangeReport tool(const Box& region, bool clipped, bool here, Local&& local);
  // True when `region` (of the whole grid) meets the owned layers.
  bool owns_part_of(const Box& region) const;

  Communicator& comm_;
  SlabLayout layout_;
  Slab slab_range_;
  std::unique_ptr<World> slab_;
  std::vector<std::uint8_t> send_down_, send_up_, from_above_, from_below_;  ///< exchange buffers, reused
  std::uint64_t exchange_version_ = 0;  ///< the slab World's change_version() after the last exchange
  HaloExchangeStats exchange_;
};

}  // namespace granular
