/// @file distributed_snapshot.cpp
/// DistributedWorld's snapshot files: each rank compresses its slab into a frame of its own and
/// rank `root` writes them after the header (version kSnapshotVersion); each rank reads a snapshot
/// file of any version keeping only its slab's cells, checking in this order: a regular file (no
/// FIFO can hang it), the header, the sizes against the file, zstd's expansion and the memory
/// budget, each frame's stated size, and only then decompressing.

#include <algorithm>
#include <exception>
#include <numeric>

#include "io/file_names.hpp"
#include "granular/distributed/distributed_world.hpp"
#include "granular/errors.hpp"
#include "granular/grid_io.hpp"
#include "io/regular_file.hpp"
#include "io/snapshot_header.hpp"
#include "io/zstd_bytes.hpp"

namespace granular {

namespace {

/// Runs `fn` on every rank and throws on every rank when it threw on any: the thrower's own error,
/// and a CommunicatorError naming `what` on the others.
template <class Fn>
void on_every_rank(Communicator& comm, const char* what, Fn&& fn) {
  std::exception_ptr failure;
  try {
    fn();
  } catch (...) {
    failure = std::current_exception();
  }
  if (!all_true(comm, !failure)) {
    if (failure) std::rethrow_exception(failure);
    throw CommunicatorError(std::string(what) + " failed on another rank");
  }
}

/// The snapshot file at `path` open and its header checked, on every rank (or an error on every rank).
std::pair<std::unique_ptr<ReadableFile>, SnapshotHeader> open_snapshot(Communicator& comm, const std::filesystem::path& path) {
  std::pair<std::unique_ptr<ReadableFile>, SnapshotHeader> opened;
  on_every_rank(comm, "reading the snapshot's header", [&] {
    opened.first = std::make_unique<ReadableFile>(path);
    opened.second = read_snapshot_header(*opened.first);
  });
  return opened;
}

}  // namespace

DistributedWorld::DistributedWorld(const WorldDef& def, Communicator& comm, const std::filesystem::path& path)
    : DistributedWorld(def, comm, path, open_snapshot(comm, path)) {}

DistributedWorld::DistributedWorld(const WorldDef& def, Communicator& comm, const std::filesystem::path& path,
                                   const std::pair<std::unique_ptr<ReadableFile>, SnapshotHeader>& opened)
    : DistributedWorld(def, comm, opened.second.meta.size, [&](const WorldDef& local, const Slab& slab) {
        const SnapshotHeader& h = opened.second;
        const Int3 size = h.meta.size;
        const std::string src = path.string();
        if (h.version == kBodiesSnapshotVersion)
          throw ParseError(src + ": snapshot version " + std::to_string(h.version) + " holds bodies (" +
                           std::to_string(h.body_count) + "), which a DistributedWorld cannot hold");
        if (h.version == kSideSnapshotVersion)
          throw ParseError(src + ": snapshot version " + std::to_string(h.version) +
                           " holds a side plane (MotionParams::momentum), which a DistributedWorld cannot step");
        if (h.version == kFacesSnapshotVersion)
          throw ParseError(src + ": snapshot version " + std::to_string(h.version) +
                           " holds a face plane (MotionParams::shallow), which a DistributedWorld cannot step");
        // The slab's cells are checked against the memory budget before they are allocated.
        check_grid_size(local.size, src + ": header fields nx, ny, nz (" + to_string(size) + "): this rank's slab");
        WorldSnapshot part = h.meta;
        part.size = local.size;
        const std::size_t layer = std::size_t(size.x) * std::size_t(size.y);
        try {
          part.cells.resize(std::size_t(slab.local_z1 - slab.local_z0) * layer);
        } catch (const std::exception&) {
          throw OutOfMemory(src + ": could not allocate the " + std::to_string(slab.local_z1 - slab.local_z0) +
                            " layers of this rank's slab of the " + to_string(size) + " grid");
        }
        const std::uint64_t cells = std::uint64_t(layer) * std::uint64_t(size.z);
        zstd_decompress_range(*opened.first, h.body_at, h.packed_size, cells, h.version != kOneFrameSnapshotVersion,
                              std::uint64_t(slab.local_z0) * layer, part.cells,
                              src + ": the compressed cells at byte " + std::to_string(h.body_at));
        return std::make_unique<World>(local, part);
      }) {
  const SnapshotHeader& h = opened.second;
  const std::uint64_t found = snapshot_file_hash(h.meta, hash(), h.version);
  if (found != h.hash) throw ParseError(path.string() + ": " + snapshot_hash_problem(found, h.hash, h.version));
}

void DistributedWorld::save(const std::filesystem::path& path, int root) {
  if (root < 0 || root >= comm_.size())
    throw InvalidArgument("DistributedWorld::save: root = " + std::to_string(root) + " is outside 0.." +
                          std::to_string(comm_.size() - 1));
  if (comm_.rank() == root) on_every_rank(comm_, "checking the snapshot path", [&] { check_snapshot_save_path(path); });
  else on_every_rank(comm_, "checking the snapshot path", [] {});
  const std::uint64_t cells_hash = hash();
  std::vector<std::uint8_t> frame;
  on_every_rank(comm_, "compressing a slab", [&] {
    const std::size_t layer = std::size_t(layout_.size().x) * std::size_t(layout_.size().y);
    ZstdFrameWriter writer(std::uint64_t(slab_range_.z1 - slab_range_.z0) * layer, 3, "DistributedWorld::save");
    for_each_owned_chunk([&](int, int, std::span<const std::uint8_t> bytes) { writer.add(bytes); });
    frame = writer.finish();
  });
  // The frames' sizes, then the frames to the root, in rank order.
  const std::uint64_t mine[1] = {frame.size()};
  std::vector<std::uint64_t> sizes(std::size_t(comm_.size()));
  comm_.all_gather({reinterpret_cast<const std::uint8_t*>(mine), sizeof mine},
                   {reinterpret_cast<std::uint8_t*>(sizes.data()), sizes.size() * sizeof(std::uint64_t)});
  std::uint64_t packed = 0;
  for (const std::uint64_t s : sizes) packed += s;
  if (comm_.rank() != root) {
    comm_.send_receive(root, frame, Communicator::kNoRank, {});
    on_every_rank(comm_, "writing the snapshot file", [] {});
    return;
  }
  // Every frame is received before anything can fail, so no rank waits on a send.
  const WorldSnapshot header = meta();
  std::vector<std::uint8_t> file =
      snapshot_header_bytes(header, kSnapshotVersion, snapshot_file_hash(header, cells_hash, kSnapshotVersion), packed);
  const std::size_t body_at = file.size();
  file.resize(body_at + packed);
  for (int r = 0; r < comm_.size(); ++r) {
    const std::size_t from = body_at + std::size_t(std::accumulate(sizes.begin(), sizes.begin() + r, std::uint64_t(0)));
    const std::span<std::uint8_t> to = std::span(file).subspan(from, sizes[std::size_t(r)]);
    if (r == root)
      std::copy(frame.begin(), frame.end(), to.begin());
    else
      comm_.send_receive(Communicator::kNoRank, {}, r, to);
  }
  on_every_rank(comm_, "writing the snapshot file", [&] { write_file_atomic(path, {std::span<const std::uint8_t>(file)}); });
}

}  // namespace granular
