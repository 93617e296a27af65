#pragma once
/// @file extend/backend.hpp
/// The interface a compute backend implements. World owns one and routes every read, write and
/// step through it, so tools and queries work the same on every backend. The core library has the
/// CPU backend; the CUDA library (granular_cuda, part of granular::granular) registers its own
/// (backend_registry.hpp); a game may create its backend itself (WorldDef::backend_factory).

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "granular/bricks.hpp"
#include "granular/errors.hpp"
#include "granular/external_memory.hpp"
#include "granular/geometry.hpp"
#include "granular/material.hpp"
#include "granular/world_def.hpp"

namespace granular {

/// A compute backend holding the world's cells. Boxes passed in always lie inside the grid and hold
/// cells at least one wide; spans are exactly box.volume() bytes (or one flag per brick). Cell bytes
/// are a material (material.hpp) in the low bits and a grain's motion state (motion.hpp) above.
/// World calls a backend from one thread at a time, but not always the same one: while it holds
/// bodies, a backend without host_tasks() is stepped and asked for its changed bricks from one of
/// the world's task system's threads, so that the bodies' host work goes on beside it.
class Backend {
 public:
  virtual ~Backend() = default;
  /// Which kind this is.
  virtual BackendKind kind() const = 0;
  /// Name and details for users ("cpu (2 threads)").
  virtual std::string description() const = 0;
  /// Runs ticks first_tick .. first_tick + ticks - 1.
  virtual void step(std::uint64_t first_tick, int ticks) = 0;
  /// Copies the cells of an in-grid box out (x fastest), every earlier write included.
  virtual void read(const Box& box, std::span<std::uint8_t> out) const = 0;
  /// Overwrites the cells of an in-grid box (x fastest) and wakes `wake_bricks` (activity.hpp
  /// indices, each < the brick count): a sparse backend steps them and their neighbours again
  /// (docs/design/sparse-stepping.md). May return before the cells are written, once
  /// `in` and `wake_bricks` are no longer needed: every later call sees the write.
  virtual void write(const Box& box, std::span<const std::uint8_t> in, std::span<const std::uint32_t> wake_bricks) = 0;
  /// Cells per material.
  virtual MaterialCounts count() const = 0;
  /// The grid hash (hash_cells), plus side_hash_term of the side plane and faces_hash_term of the face
  /// plane when it keeps them.
  virtual std::uint64_t hash() const = 0;
  /// The side plane (MotionParams::momentum: one byte per cell, x fastest), or empty when the backend
  /// keeps none or it holds only zeros. The default keeps none.
  virtual std::vector<std::uint8_t> read_side() const { return {}; }
  /// Replaces the side plane with `side` (every cell, x fastest; empty: all zero), after the cells
  /// it belongs to were written and their bricks woken (write's wake_bricks, or a new backend, whose
  /// bricks are all awake): it wakes nothing itself. Throws InvalidArgument when `side` is not empty
  /// and the backend keeps no side plane (the default keeps none).
  virtual void write_side(std::span<const std::uint8_t> side) {
    if (!side.empty())
      throw InvalidArgument("the " + description() + " backend keeps no side plane (MotionParams::momentum) to write "
                            "WorldSnapshot::side into");
  }
  /// The face plane (MotionParams::shallow: 4 int32 per column, shallow_water.hpp's order), or empty
  /// when the backend keeps none or it holds only zeros. The default keeps none.
  virtual std::vector<std::int32_t> read_faces() const { return {}; }
  /// Replaces the face plane with `faces` (as read_faces gives it; empty: all zero), after the cells
  /// were written, as write_side. Throws InvalidArgument when `faces` is not empty and the backend
  /// keeps no face plane (the default keeps none).
  virtual void write_faces(std::span<const std::int32_t> faces) {
    if (!faces.empty())
      throw InvalidArgument("the " + description() + " backend keeps no face plane (MotionParams::shallow) to write "
                            "WorldSnapshot::faces into");
  }
  /// Sets flags[i] = 1 (one entry per brick) for every brick whose cells step() changed since the
  /// last call, and forgets them. A dense backend sets every flag.
  virtual void take_changed_bricks(std::span<std::uint8_t> flags) = 0;
  /// What the last step() call stepped (total_bricks included).
  virtual ActivityStats last_activity() const = 0;

  /// Bytes an imported cell buffer must hold (share_cells), or 0 when this backend cannot share.
  virtual std::uint64_t shared_cell_bytes() const { return 0; }
  /// Moves the cells into imported external memory and steps them there from now on.
  virtual void share_cells(const ExternalCellMemory&) { throw_not_shareable("share_cells"); }
  /// Orders every later write of the cells with a renderer through two imported timelines.
  virtual void attach_timelines(const ExternalTimeline&, const ExternalTimeline&) {
    throw_not_shareable("attach_timelines");
  }
  /// Hands the current cells to a renderer for one read (see World::hand_off_cells).
  virtual CellsHandoff hand_off_cells() { throw_not_shareable("hand_off_cells"); }

  /// Keeps a copy of every cell as it is now, the checkpoint, where the backend keeps its cells (the
  /// CPU backend in host memory, the CUDA backend in device memory), replacing an earlier one; the
  /// state an undo returns to (StrokeHistory). Throws OutOfMemory when it does not fit. The default
  /// throws BackendError: a backend that keeps no checkpoint offers no undo.
  virtual void take_checkpoint() { throw_no_checkpoint(); }
  /// Copies the cells of an in-grid box (x fastest) as they were at the last take_checkpoint().
  /// Throws StateError when there is no checkpoint.
  virtual void read_checkpoint(const Box&, std::span<std::uint8_t>) const { throw_no_checkpoint(); }
  /// Frees the checkpoint, if any.
  virtual void drop_checkpoint() {}
  /// Bytes the checkpoint holds; 0 when there is none.
  virtual std::uint64_t checkpoint_bytes() const { return 0; }

  /// Copies the cells of the in-grid boxes `boxes` into `out`, box after box, each x fastest (`out`
  /// holds the sum of their volumes): the regions of a tick's bodies. The default reads them one by
  /// one; a backend whose every read is a round trip (CUDA) moves them at once.
  virtual void read_boxes(std::span<const Box> boxes, std::span<std::uint8_t> out) const {
    std::size_t at = 0;
    for (const Box& box : boxes) {
      read(box, out.subspan(at, std::size_t(box.volume())));
      at += std::size_t(box.volume());
    }
  }
  /// A host buffer of `bytes` that read_boxes and write_boxes move cells through with no copy of
  /// their own (page-locked memory a GPU reads and writes directly), or an empty span where the
  /// backend has none (the default). It holds until the next call, which may move it; the caller
  /// passes spans of it as read_boxes' `out` and write_boxes' `in`, and writes into it only after
  /// this call (which waits for the device to finish reading it).
  virtual std::span<std::uint8_t> transfer_buffer(std::uint64_t bytes) {
    (void)bytes;
    return {};
  }
  /// Writes `in`, laid out as read_boxes gives it, into the boxes, waking `wake_bricks` as write()
  /// does. Where boxes overlap their bytes agree, so the order of the writes does not matter. The
  /// default writes them one by one.
  virtual void write_boxes(std::span<const Box> boxes, std::span<const std::uint8_t> in,
                           std::span<const std::uint32_t> wake_bricks) {
    std::size_t at = 0;
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      write(boxes[i], in.subspan(at, std::size_t(boxes[i].volume())),
            i == 0 ? wake_bricks : std::span<const std::uint32_t>());
      at += std::size_t(boxes[i].volume());
    }
  }

  /// The threads the backend runs its host loops on, which World's own host work (writing bodies
  /// into the grid) then shares; null (the default) when it has none, and World starts its own.
  virtual TaskSystem* host_tasks() { return nullptr; }

 private:
  [[noreturn]] void throw_no_checkpoint() const {
    throw BackendError("the " + description() +
                       " backend keeps no checkpoint of its cells (Backend::take_checkpoint), which undo needs");
  }
  [[noreturn]] void throw_not_shareable(const char* what) const {
    throw BackendError(std::string("World::") + what + ": the " + description() +
                       " backend keeps its cells in host memory; sharing them with a graphics API needs the "
                       "CUDA backend (WorldDef::backend = cuda)");
  }
};

}  // namespace granular
