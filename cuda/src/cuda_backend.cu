#include <cuda_runtime.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "box_transfer.cuh"
#include "cuda_check.cuh"
#include "cuda_device.cuh"
#include "cuda_stream.cuh"
#include "device_buffer.cuh"
#include "device_head_field.cuh"
#include "device_shallow_pass.cuh"
#include "external_interop.cuh"
#include "granular/extend/backend.hpp"
#include "granular/extend/backend_factory.hpp"
#include "granular/extend/block.hpp"
#include "granular/errors.hpp"
#include "granular/grid.hpp"
#include "granular/extend/lut.hpp"
#include "granular/motion.hpp"
#include "granular/rule_set.hpp"
#include "granular_cuda/cuda_backend_factory.hpp"
#include "activity_record.cuh"
#include "block_walk.cuh"
#include "pair_kernel.cuh"
#include "pinned_counters.cuh"
#include "rule_launch.cuh"
#include "reduce_kernels.cuh"
#include "sparse_kernel.cuh"
#include "train_kernels.cuh"
#include "step/block_step.hpp"
#include "step/motion_table.hpp"
#include "step/step_rules_builder.hpp"
#include "table_kernels.cuh"

namespace granular {

namespace {

/// The device current and the grid checked to fit, before anything is allocated.
cuda::DeviceInfo prepare_device(Int3 size) {
  cuda::DeviceInfo device = cuda::acquire_device();
  cuda::check_fits(device, size);
  return device;
}

/// Steps a byte-per-cell grid on a CUDA device: the same cells, result table and block arithmetic
/// as the CPU backend, so both produce the same grid after any number of ticks. Every call runs
/// on the backend's own stream, which orders it after the calls before; write() returns once its
/// work is enqueued (a failure of that work is reported by the next call that waits), the others
/// once the device has finished (step() too unless a renderer's timelines are attached).
///
/// Sparse stepping runs each step() call in one of two ways with the same result and the same
/// sparse state (docs/design/sparse-stepping.md): sparse steps (one launch per step over
/// the awake bricks), or, when more than the rule set's fraction (CudaOptions::dense_fraction, or
/// motion_dense_fraction with a motion model) of the bricks were awake at the last tick the host
/// knows of, dense-recording steps (the dense kernels, fused pairs included, recording the sparse
/// flags).
///
/// Every path steps blocks through the one block step (step/block_step.hpp) with the Rule of the
/// rule set: a motion rule set keeps the motion table on the device and steps each tick as
/// MotionParams::substeps sub-steps, fused in pairs by the pair kernel wherever two consecutive
/// steps share their x and y offsets, as the one-step rules fuse pairs of ticks. A rule set with
/// the pressure lever and a liquid keeps the head field on the device too (device_head_field.cuh)
/// and solves it at the start of every tick, as the CPU backend does; with the momentum lever too it
/// keeps the side plane (one byte per cell), which every path steps with the cells, block by block
/// (walk_side_block in block_walk.cuh), never fused in pairs.
class CudaBackend final : public Backend {
 public:
  /// Uploads info.initial, derives the result table from info.lut on the device, and uploads the
  /// motion table when the rule set's motion model is enabled. The checks are make_cuda_backend's.
  explicit CudaBackend(const BackendCreateInfo& info)
      : device_(prepare_device(info.initial.size())),
        size_(info.initial.size()),
        cell_count_(std::uint64_t(info.initial.cell_count())),
        shape_(cuda::step_shape(info.initial.size())),
        owned_cells_(cuda::cell_buffer_bytes(cell_count_), "the grid's cells"),
        cells_(owned_cells_.data()),
        result_(kBlockKeyCount, "the result table"),
        scratch_(kMaterialCount, "reduction counters"),
        sparse_(info.sparse),
        dense_fraction_(info.rules->motion.enabled() ? info.cuda.motion_dense_fraction : info.cuda.dense_fraction),
        bricks_(brick_counts(info.initial.size())),
        total_bricks_(std::uint32_t(std::uint64_t(bricks_.x) * std::uint64_t(bricks_.y) * std::uint64_t(bricks_.z))),
        known_awake_(total_bricks_) {
    cudaStream_t s = stream_.get();
    last_.total_bricks = total_bricks_;
    if (owned_cells_.bytes() > cell_count_)  // the tail of the last word, read (masked) by the reductions
      cuda::check(cudaMemsetAsync(cells_ + cell_count_, 0, owned_cells_.bytes() - cell_count_, s),
                  "cudaMemsetAsync (cells)");
    cuda::check(cudaMemcpyAsync(cells_, info.initial.cells().data(), cell_count_, cudaMemcpyHostToDevice, s),
                "cudaMemcpyAsync (upload cells)");
    cuda::DeviceBuffer<Transition> table(kBlockKeyCount, "the transition table");
    cuda::check(cudaMemcpyAsync(table.data(), info.lut->entries().data(), table.bytes(), cudaMemcpyHostToDevice, s),
                "cudaMemcpyAsync (upload transition table)");
    cuda::launch_result_table(table.data(), result_.data(), s);
    // The sparse state is made for the Rules' type (init_sparse), so the inert-key table and the
    // motion entries made after it are pointed to once they exist.
    StepTables tables;
    tables.result = result_.data();
    step_rules_ = make_step_rules(info, tables);
    // The head field, as the CPU backend keeps it: a motion model with the pressure lever and a liquid.
    if (step_rules_.motion.enabled() && step_rules_.motion.pressure && step_rules_.materials.liquids != 0) {
      head_field_.emplace(size_, sparse_ ? total_bricks_ : 0u, s);
      step_rules_.heads = head_field_->heads();
    }
    // The side plane (momentum.hpp), as the CPU backend keeps it: the momentum lever with a head field.
    if (head_field_ && info.rules->motion.momentum) {
      side_ = cuda::DeviceBuffer<std::uint8_t>(cuda::cell_buffer_bytes(cell_count_), "the side plane");
      cuda::check(cudaMemsetAsync(side_.data(), 0, side_.bytes(), s), "cudaMemsetAsync (side plane)");
      step_rules_.side = true;
    }
    // The face plane (shallow_water.hpp), as the CPU backend keeps it: the shallow lever and a liquid.
    if (info.rules->motion.shallow && step_rules_.materials.liquids != 0)
      shallow_.emplace(size_, sparse_ ? total_bricks_ : 0u, s);
    if (sparse_) init_sparse(s);
    // MotionParams::trains with sparse stepping: a byte per brick for the wake of the bricks a train changed.
    if (sparse_ && step_rules_.motion.trains) {
      train_flags_ = cuda::DeviceBuffer<std::uint8_t>(total_bricks_, "the bricks a train changed");
      cuda::check(cudaMemsetAsync(train_flags_.data(), 0, train_flags_.bytes(), s), "cudaMemsetAsync (train bricks)");
    }
    step_rules_.inert = inert_.data();
    stream_.synchronize("building the result table");
    if (info.rules->motion.enabled()) {
      // The motion model looks up the motion entries (2 MiB, cache-resident on the device).
      const std::vector<motion::MotionEntry> motion_table = derive_motion_table(info.lut->entries());
      table_ = cuda::DeviceBuffer<motion::MotionEntry>(motion_table.size(), "the motion entries");
      cuda::check(cudaMemcpy(table_.data(), motion_table.data(), table_.bytes(), cudaMemcpyHostToDevice),
                  "cudaMemcpy (upload motion table)");
    }
    step_rules_.transitions = table_.data();
  }

  BackendKind kind() const override { return BackendKind::Cuda; }
  std::string description() const override { return cuda::describe(device_); }

  void step(std::uint64_t first_tick, int ticks) override {
    // A failure names the grid and the ticks, so a user can tell a bad launch from a lost device.
    try {
      enqueue_pending_wake();
      step_ticks(first_tick, ticks);
    } catch (const BackendError& e) {
      throw BackendError(std::string(e.what()) + " (stepping the " + to_string(size_) + " grid, ticks " +
                         std::to_string(first_tick) + " to " + std::to_string(first_tick + std::uint64_t(ticks) - 1) +
                         ")");
    }
  }

 private:
  /// Enqueues the ticks (fused pairs where the parity allows) and synchronises once.
  void step_ticks(std::uint64_t first_tick, int ticks) {
    activate();
    before_write();
    if (sparse_ && asleep_ && !head_field_ && (!shallow_ || shallow_->at_rest(stream_.get()))) {
      // Nothing is awake and nothing can wake without a tool: the ticks change no cell, so they
      // cost no device work at all (a settled world costs nothing). A head field may wake bricks at
      // any tick, so a world that keeps one always steps; a shallow-water pass that changed
      // something last time may change more.
      last_ = ActivityStats{};
      last_.total_bricks = total_bricks_;
      last_.ticks = std::uint64_t(ticks);
      after_write();
      return;
    }
    if (sparse_) {
      enqueue_steps(first_tick, ticks, dense_recording() ? Mode::Recording : Mode::Sparse);
      after_write();
      // With a renderer attached the host goes on at once; last_activity() waits for the counters.
      if (!ready_) collect_sparse_counters();
      return;
    }
    enqueue_steps(first_tick, ticks, Mode::Dense);
    after_write();
    // With a renderer attached the host goes on at once; the timelines order the device's work.
    if (!ready_) stream_.synchronize("step");
    last_.active_bricks = last_.total_bricks;
    last_.active_cells = cell_count_;
    last_.ticks = std::uint64_t(ticks);
    last_.brick_ticks = last_.total_bricks * std::uint64_t(ticks);
    last_.cell_ticks = cell_count_ * std::uint64_t(ticks);
  }

 public:

  void take_changed_bricks(std::span<std::uint8_t> flags) override {
    if (!sparse_) {
      std::fill(flags.begin(), flags.end(), std::uint8_t(1));
      return;
    }
    activate();
    cudaStream_t s = stream_.get();
    std::vector<std::uint8_t> changed(total_bricks_);
    cuda::check(cudaMemcpyAsync(changed.data(), changed_.data(), changed.size(), cudaMemcpyDeviceToHost, s),
                "cudaMemcpyAsync (changed bricks)");
    cuda::check(cudaMemsetAsync(changed_.data(), 0, changed_.bytes(), s), "cudaMemsetAsync (changed bricks)");
    stream_.synchronize("taking the changed bricks");
    for (std::size_t i = 0; i < changed.size(); ++i) flags[i] |= changed[i];
  }

  ActivityStats last_activity() const override {
    if (counters_pending_) collect_sparse_counters();
    return last_;
  }

  /// Waits for the device once per chunk of the box (box_transfer.cuh): once for a tool's box.
  void read(const Box& box, std::span<std::uint8_t> out) const override {
    check_box(box, out.size(), "read");
    copy_out(cells_, box, out.data());
  }

  /// A device-to-device copy of the cells into a buffer kept until drop_checkpoint(), enqueued on
  /// the stream (so after every earlier write and before every later step).
  void take_checkpoint() override {
    activate();
    if (checkpoint_.size() == 0) checkpoint_ = cuda::DeviceBuffer<std::uint8_t>(cell_count_, "a checkpoint of the cells");
    cuda::check(cudaMemcpyAsync(checkpoint_.data(), cells_, cell_count_, cudaMemcpyDeviceToDevice, stream_.get()),
                "cudaMemcpyAsync (checkpoint)");
  }

  /// As read(), from the checkpoint.
  void read_checkpoint(const Box& box, std::span<std::uint8_t> out) const override {
    if (checkpoint_.size() == 0) throw StateError("cuda backend: read_checkpoint: no checkpoint was taken");
    check_box(box, out.size(), "read_checkpoint");
    copy_out(checkpoint_.data(), box, out.data());
  }

  void drop_checkpoint() override { checkpoint_.reset(); }

  std::uint64_t checkpoint_bytes() const override { return checkpoint_.bytes(); }

  /// Enqueues the write and returns without waiting for the device (box_transfer.cuh). The bricks
  /// wait on the host to be woken all at once before the next step (enqueue_pending_wake).
  void write(const Box& box, std::span<const std::uint8_t> in, std::span<const std::uint32_t> wake_bricks) override {
    check_box(box, in.size(), "write");
    check_wake(wake_bricks, "write");
    copy_in(box, in.data());
    note_wake(wake_bricks);
  }

  /// One batch launch per kernel and up to kTransferChunkBytes cells (box_transfer.cuh), the
  /// device waited for once per batch.
  void read_boxes(std::span<const Box> boxes, std::span<std::uint8_t> out) const override {
    check_boxes(boxes, out.size(), "read_boxes");
    activate();
    cudaStream_t s = stream_.get();
    std::uint8_t* direct = direct_cells(out);
    cuda::for_each_batch(boxes, [&](std::span<const cuda::BoxChunk> chunks, std::uint64_t bytes) {
      staging_.wait_free();  // the host writes the chunk table into it
      const cuda::ChunkCopy* table = fill_batch_table(chunks, bytes, nullptr, direct);
      cuda::gather_chunks_kernel<<<dim3(batch_blocks(chunks), unsigned(chunks.size())), cuda::kChunkThreads, 0, s>>>(
          table);
      cuda::check_launch("gather kernel launch (reading boxes)");
      stream_.synchronize("read_boxes");
      staging_.mark_free();
      if (direct != nullptr) return;  // the kernel wrote them in place
      std::uint64_t at = cuda::batch_table_bytes(chunks.size());
      for (const cuda::BoxChunk& chunk : chunks) {
        std::memcpy(out.data() + chunk.offset, staging_.host() + at, chunk.cells());
        at += chunk.cells();
      }
    });
  }

  /// As read_boxes, the other way: one scatter launch per batch, waiting for nothing but the
  /// staging being free of the last one.
  void write_boxes(std::span<const Box> boxes, std::span<const std::uint8_t> in,
                   std::span<const std::uint32_t> wake_bricks) override {
    check_boxes(boxes, in.size(), "write_boxes");
    check_wake(wake_bricks, "write_boxes");
    activate();
    before_write();
    cudaStream_t s = stream_.get();
    std::uint8_t* direct = direct_cells(in);
    cuda::for_each_batch(boxes, [&](std::span<const cuda::BoxChunk> chunks, std::uint64_t bytes) {
      staging_.wait_free();
      const cuda::ChunkCopy* table = fill_batch_table(chunks, bytes, side_.data(), direct);
      std::uint64_t at = cuda::batch_table_bytes(chunks.size());
      if (direct == nullptr)
        for (const cuda::BoxChunk& chunk : chunks) {
          std::memcpy(staging_.host() + at, in.data() + chunk.offset, chunk.cells());
          at += chunk.cells();
        }
      cuda::scatter_chunks_kernel<<<dim3(batch_blocks(chunks), unsigned(chunks.size())), cuda::kChunkThreads, 0, s>>>(
          table);
      cuda::check_launch("scatter kernel launch (writing boxes)");
      staging_.read_until(s);
      if (direct != nullptr) transfer_.read_until(s);
    });
    after_write();
    note_wake(wake_bricks);
  }

  /// Page-locked, mapped: the kernels of read_boxes and write_boxes reach spans of it in place.
  std::span<std::uint8_t> transfer_buffer(std::uint64_t bytes) override {
    activate();
    transfer_.reserve(bytes, stream_.get());
    transfer_.wait_free();  // the last write_boxes' kernel may still read it
    return {transfer_.host(), std::size_t(bytes)};
  }

  /// Notes that a write woke `wake_bricks` (already checked): they wake before the next step.
  void note_wake(std::span<const std::uint32_t> wake_bricks) {
    if (!sparse_ || wake_bricks.empty()) return;
    asleep_ = false;
    // At most this many more are awake now (each wakes its neighbourhood, most of which a large
    // wake, e.g. load(), wakes anyway): a large wake switches the next step to dense-recording ticks.
    known_awake_ = std::min<std::uint64_t>(total_bricks_, known_awake_ + wake_bricks.size());
    // A list longer than the bricks would repeat some: wake those listed so far first.
    if (pending_wake_.size() + wake_bricks.size() > total_bricks_) enqueue_pending_wake();
    pending_wake_.insert(pending_wake_.end(), wake_bricks.begin(), wake_bricks.end());
  }

  MaterialCounts count() const override {
    activate();
    cudaStream_t s = stream_.get();
    cuda::check(cudaMemsetAsync(scratch_.data(), 0, scratch_.bytes(), s), "cudaMemsetAsync (counters)");
    cuda::count_kernel<<<cuda::reduce_blocks(cell_count_, device_.sm_count), cuda::kReduceThreads, 0, s>>>(
        cells_, cell_count_, scratch_.data());
    cuda::check_launch("count kernel launch");
    unsigned long long counts[kMaterialCount] = {};
    cuda::check(cudaMemcpyAsync(counts, scratch_.data(), sizeof counts, cudaMemcpyDeviceToHost, s),
                "cudaMemcpyAsync (counts)");
    stream_.synchronize("count");
    MaterialCounts out{};
    for (int m = 0; m < kMaterialCount; ++m) out[std::size_t(m)] = counts[m];
    return out;
  }

  /// The cells' word sum, plus side_hash_term of the side plane and faces_hash_term of the face
  /// plane when the backend keeps them.
  std::uint64_t hash() const override {
    activate();
    cudaStream_t s = stream_.get();
    const unsigned blocks = cuda::reduce_blocks(cell_count_, device_.sm_count);
    // Slot 0: the cells' sum; with a side plane, slot 1 its sum and slot 2 whether it holds a velocity.
    cuda::check(cudaMemsetAsync(scratch_.data(), 0, 3 * sizeof(unsigned long long), s), "cudaMemsetAsync (hash)");
    cuda::hash_kernel<<<blocks, cuda::kReduceThreads, 0, s>>>(cells_, cell_count_, scratch_.data());
    cuda::check_launch("hash kernel launch");
    if (side_.size() != 0) {
      cuda::hash_kernel<<<blocks, cuda::kReduceThreads, 0, s>>>(side_.data(), cell_count_, scratch_.data() + 1);
      cuda::check_launch("side plane hash kernel launch");
      cuda::nonzero_kernel<<<blocks, cuda::kReduceThreads, 0, s>>>(side_.data(), cell_count_,
                                                                   reinterpret_cast<unsigned*>(scratch_.data() + 2));
      cuda::check_launch("side plane nonzero kernel launch");
    }
    unsigned long long sums[3] = {};
    cuda::check(cudaMemcpyAsync(sums, scratch_.data(), sizeof sums, cudaMemcpyDeviceToHost, s), "cudaMemcpyAsync (hash)");
    stream_.synchronize("hash");
    const std::uint64_t side = sums[2] != 0 ? side_hash_of_sum(sums[1]) : 0;
    const std::uint64_t faces = shallow_ ? faces_hash_term(shallow_->read(s)) : 0;
    return finish_hash(size_, sums[0] + side + faces);
  }

  /// The side plane copied to the host; empty when the backend keeps none or it holds only zeros.
  std::vector<std::uint8_t> read_side() const override {
    if (side_.size() == 0) return {};
    activate();
    std::vector<std::uint8_t> side(cell_count_);
    cuda::check(cudaMemcpyAsync(side.data(), side_.data(), cell_count_, cudaMemcpyDeviceToHost, stream_.get()),
                "cudaMemcpyAsync (side plane to the host)");
    stream_.synchronize("read_side");
    if (std::all_of(side.begin(), side.end(), [](std::uint8_t b) { return b == 0; })) return {};
    return side;
  }

  /// Replaces the side plane (empty: all zero); returns once the device holds it.
  void write_side(std::span<const std::uint8_t> side) override {
    if (side.empty() && side_.size() == 0) return;
    if (side_.size() == 0)
      throw InvalidArgument("cuda backend: write_side: the rule set has no side plane (MotionParams::momentum with "
                            "a liquid material) to write WorldSnapshot::side into");
    if (!side.empty() && side.size() != cell_count_)
      throw InvalidArgument("cuda backend: write_side: " + std::to_string(side.size()) + " side bytes for the " +
                            std::to_string(cell_count_) + " cells of the " + to_string(size_) + " grid");
    activate();
    before_write();
    cudaStream_t s = stream_.get();
    if (side.empty())
      cuda::check(cudaMemsetAsync(side_.data(), 0, side_.bytes(), s), "cudaMemsetAsync (side plane)");
    else
      cuda::check(cudaMemcpyAsync(side_.data(), side.data(), cell_count_, cudaMemcpyHostToDevice, s),
                  "cudaMemcpyAsync (side plane to the device)");
    after_write();
    stream_.synchronize("write_side");
  }

  /// The face plane copied to the host; empty when the backend keeps none or it holds only zeros.
  std::vector<std::int32_t> read_faces() const override {
    if (!shallow_) return {};
    activate();
    return shallow_->read(stream_.get());
  }

  /// Replaces the face plane (empty: all zero); returns once the device holds it.
  void write_faces(std::span<const std::int32_t> faces) override {
    const bool zero = std::all_of(faces.begin(), faces.end(), [](std::int32_t f) { return f == 0; });
    if (!shallow_) {
      if (zero) return;
      throw InvalidArgument("cuda backend: write_faces: the rule set has no face plane (MotionParams::shallow with a "
                            "liquid material) to write WorldSnapshot::faces into");
    }
    if (!faces.empty() && faces.size() != shallow_->face_count())
      throw InvalidArgument("cuda backend: write_faces: " + std::to_string(faces.size()) + " face values for the " +
                            std::to_string(shallow_->face_count()) + " of the " + to_string(size_) +
                            " grid (4 per column)");
    activate();
    before_write();
    shallow_->write(faces, stream_.get());
    after_write();
  }

  std::uint64_t shared_cell_bytes() const override { return cuda::cell_buffer_bytes(cell_count_); }

  void share_cells(const ExternalCellMemory& memory) override {
    activate();
    if (imported_) throw BackendError("World::share_cells: the cells are already shared; share them once per world");
    cuda::ImportedMemory imported(memory, shared_cell_bytes());
    cuda::check(cudaMemcpyAsync(imported.data(), cells_, shared_cell_bytes(), cudaMemcpyDeviceToDevice, stream_.get()),
                "cudaMemcpyAsync (cells into the shared buffer)");
    stream_.synchronize("share_cells");
    imported_.emplace(std::move(imported));
    cells_ = imported_->data();
    owned_cells_.reset();
  }

  void attach_timelines(const ExternalTimeline& cells_ready, const ExternalTimeline& cells_released) override {
    activate();
    if (!imported_) throw BackendError("World::attach_timelines: call share_cells first (the timelines order the shared cells)");
    if (ready_) throw BackendError("World::attach_timelines: timelines are already attached");
    cuda::ImportedTimeline ready(cells_ready, "cudaImportExternalSemaphore (cells_ready)");
    cuda::ImportedTimeline released(cells_released, "cudaImportExternalSemaphore (cells_released)");
    ready_.emplace(std::move(ready));
    released_.emplace(std::move(released));
  }

  CellsHandoff hand_off_cells() override {
    if (!ready_) throw BackendError("World::hand_off_cells: call share_cells and attach_timelines first");
    return {writes_, ++handoffs_};
  }

 private:
  /// Allocates and initialises the sparse state (every brick dirty and awake) and the inert-key table
  /// (with random symmetry, and for every motion rule set: the sparse motion kernel asks it about
  /// rest keys).
  void init_sparse(cudaStream_t s) {
    awake_ = cuda::DeviceBuffer<std::uint8_t>(total_bricks_, "awake bricks");
    dirty_ = cuda::DeviceBuffer<std::uint8_t>(total_bricks_, "dirty bricks");
    changed_ = cuda::DeviceBuffer<std::uint8_t>(total_bricks_, "changed bricks");
    if (step_rules_.motion.enabled()) {
      reach_ = cuda::DeviceBuffer<unsigned>(total_bricks_, "brick reaches");
      cuda::check(cudaMemsetAsync(reach_.data(), 0, reach_.bytes(), s), "cudaMemsetAsync (brick reaches)");
    }
    list_ = cuda::DeviceBuffer<std::uint32_t>(total_bricks_, "the awake brick list");
    count_ = cuda::DeviceBuffer<unsigned>(1, "the awake brick count");
    counters_ = cuda::DeviceBuffer<unsigned long long>(cuda::kCounterSlots, "activity counters");
    counters_host_ = cuda::pinned_counters(cuda::kCounterSlots);
    cuda::check(cudaMemsetAsync(awake_.data(), 1, total_bricks_, s), "cudaMemsetAsync (awake bricks)");
    cuda::check(cudaMemsetAsync(dirty_.data(), 1, total_bricks_, s), "cudaMemsetAsync (dirty bricks)");
    cuda::check(cudaMemsetAsync(changed_.data(), 0, total_bricks_, s), "cudaMemsetAsync (changed bricks)");
    cuda::check(cudaMemsetAsync(count_.data(), 0, sizeof(unsigned), s), "cudaMemsetAsync (brick count)");
    cuda::build_list_kernel<<<cuda::activity_blocks(total_bricks_), cuda::kActivityThreads, 0, s>>>(sparse_params());
    cuda::check_launch("build brick list kernel launch");
    if (step_rules_.random_symmetry || step_rules_.motion.enabled()) {
      inert_ = cuda::DeviceBuffer<std::uint64_t>(kInertTableWords, "the inert-key table");
      cuda::inert_table_kernel<<<cuda::activity_blocks(kInertTableWords), cuda::kActivityThreads, 0, s>>>(
          result_.data(), step_rules_.random_symmetry, inert_.data());
      cuda::check_launch("inert-key table kernel launch");
    }
    // As many CUDA blocks of this rule set's sparse kernel as the device runs at once; each walks the
    // list from there.
    std::uint64_t resident = 1;
    with_rule_type<cuda::DevicePlatform>(step_rules_, [&](auto* tag) {
      resident = cuda::RuleLaunch<std::remove_pointer_t<decltype(tag)>>::sparse_resident(device_.sm_count);
    });
    sparse_grid_ = unsigned(std::max<std::uint64_t>(1, std::min<std::uint64_t>(resident, total_bricks_)));
  }

  /// The device state of sparse stepping, as the kernels take it.
  cuda::SparseParams sparse_params() const {
    cuda::SparseParams sp;
    sp.bricks = bricks_;
    sp.total = total_bricks_;
    sp.awake = awake_.data();
    sp.dirty = dirty_.data();
    sp.changed = changed_.data();
    sp.reach = reach_.data();
    sp.list = list_.data();
    sp.count = count_.data();
    sp.counters = counters_.data();
    return sp;
  }

  /// True when the next step() should use dense-recording ticks: more than dense_fraction_ of the
  /// bricks were awake at the last tick the host knows of (no synchronisation to find out).
  bool dense_recording() const {
    return dense_fraction_ <= 0.0 || double(known_awake_) > dense_fraction_ * double(total_bricks_);
  }

  /// How step() runs its ticks: every block (not sparse), or in sparse mode the dense kernels
  /// recording the sparse state (dense-recording ticks), or the sparse kernel over the awake bricks.
  enum class Mode { Dense, Recording, Sparse };

  /// Enqueues the steps of ticks first_tick .. first_tick + ticks - 1 (substeps_of steps per tick,
  /// numbered as in block_step.hpp). Dense and Recording fuse two consecutive steps into one pass of
  /// the pair kernel wherever their offsets allow (pairable) and, when recording, no cycle ends
  /// between them; the other steps run the dense kernel. Recording notes the sparse flags of every
  /// step as the sparse kernel would and runs the cycle updates and activity counters as Sparse does
  /// (the awake list counted once per tick, in runs of ticks between two list changes); stepping an
  /// asleep brick changes nothing and records nothing (its blocks are quiet), so the cells and the
  /// sparse state are those of sparse ticks. Sparse launches the sparse kernel per step and ends a
  /// cycle after every 8th. With a head field, every tick starts with its solve and, sparse or
  /// recording, the wake of the bricks where a pressure move may start (so no pair spans two ticks).
  void enqueue_steps(std::uint64_t first_tick, int ticks, Mode mode) {
    cudaStream_t s = stream_.get();
    const cuda::DeviceCells g{cells_, size_, side_.data()};
    const std::uint64_t substeps = std::uint64_t(substeps_of(step_rules_));
    const std::uint64_t first = first_tick * substeps, end = (first_tick + std::uint64_t(ticks)) * substeps;
    const std::uint64_t last_tick = first_tick + std::uint64_t(ticks) - 1;
    const cuda::SparseParams sp = sparse_ ? sparse_params() : cuda::SparseParams{};
    const cuda::ActivityRecord record{bricks_, dirty_.data(), changed_.data()};
    // Recording ticks note the sparse flags into `record`; the other modes note nothing.
    const cuda::ActivityRecord* notes = mode == Mode::Recording ? &record : nullptr;
    if (mode != Mode::Dense) reset_counters();
    // Recording counts the awake list per run of ticks: `uncounted` ticks began since the last count.
    unsigned uncounted = 0;
    bool last_uncounted = false;
    auto count = [&] {
      if (uncounted > 0) cuda::launch_count_awake(sp, size_, uncounted, last_uncounted, s);
      uncounted = 0;
    };
    // The pair kernel's halo buffer, allocated at the first pair; without room for it the steps run
    // one by one (the same result).
    const cuda::PairShape pair = cuda::pair_shape(size_);
    const std::size_t halo_bytes = cuda::pair_halo_bytes(size_, pair);
    void* halo = nullptr;
    bool halo_failed = false;
    auto halo_ready = [&] {
      if (halo_bytes == 0 || halo != nullptr) return true;
      if (halo_failed) return false;
      if (cudaMallocAsync(&halo, halo_bytes, s) == cudaSuccess) return true;
      (void)cudaGetLastError();
      halo_failed = true;
      return false;
    };
    for (std::uint64_t n = first; n < end;) {
      const std::uint64_t tick = n / substeps;
      const bool tick_start = n % substeps == 0;
      if (tick_start && head_field_) {
        // The heads of this tick, from the cells its first sub-step reads; with sparse stepping the
        // bricks where a pressure move may start wake, which changes the awake list, so recording
        // counts the ticks before with the list they stepped.
        if (mode == Mode::Recording) count();
        head_field_->enqueue(cells_, step_rules_.materials, sparse_ ? &sp : nullptr, s);
      }
      if (mode == Mode::Sparse) {
        cuda::with_device_step(step_rules_, n, [&](const auto& rule) {
          cuda::RuleLaunch<std::decay_t<decltype(rule)>>::sparse(g, rule, sp, tick_start, tick_start && tick == last_tick,
                                                                  sparse_grid_, s);
        });
        if ((n & 7u) == 7u) cuda::launch_end_cycle(sp, s);
        ++n;
        if (n % substeps == 0) {
          close_trains(sp, s);
          run_shallow_pass(sp, s);
        }
        continue;
      }
      // The pair kernel steps no side plane: a rule set with one runs its steps one by one.
      const bool fuse = n + 1 < end && !step_rules_.side &&
                        cuda::pairable(step_offset(step_rules_, n), step_offset(step_rules_, n + 1)) &&
                        !(mode == Mode::Recording && (n & 7u) == 7u) &&
                        !((head_field_ || step_rules_.motion.trains || shallow_) && (n + 1) % substeps == 0) &&
                        halo_ready();
      if (fuse) {
        cuda::with_device_step_pair(step_rules_, n, [&](const auto& a, const auto& b) {
          cuda::RuleLaunch<std::decay_t<decltype(a)>>::pair(g, a, b, pair, static_cast<std::uint8_t*>(halo), notes, s);
        });
      } else {
        cuda::with_device_step(step_rules_, n, [&](const auto& rule) {
          cuda::RuleLaunch<std::decay_t<decltype(rule)>>::dense(g, rule, shape_, notes, s);
        });
      }
      const std::uint64_t done = fuse ? 2 : 1;
      if (mode == Mode::Recording)
        for (std::uint64_t k = n; k < n + done; ++k) {
          if (k % substeps == 0) {
            ++uncounted;
            last_uncounted = k / substeps == last_tick;
          }
          if ((k & 7u) == 7u) {
            count();
            cuda::launch_end_cycle(sp, s);
          }
        }
      n += done;
      if (n % substeps == 0 && step_rules_.motion.trains) {
        // The tick's trains close; with sparse stepping the bricks they changed wake, which changes
        // the awake list, so recording counts the ticks before with the list they stepped.
        if (mode == Mode::Recording) count();
        close_trains(sp, s);
      }
      if (n % substeps == 0 && shallow_) {
        // The tick's shallow-water pass, after the trains (the CPU's order); its wake changes the
        // awake list as the trains' does.
        if (mode == Mode::Recording) count();
        run_shallow_pass(sp, s);
      }
    }
    if (halo != nullptr) cuda::check(cudaFreeAsync(halo, s), "cudaFreeAsync (pair halo)");
    if (mode == Mode::Dense) return;
    count();
    fetch_counters(ticks);
  }

  /// Enqueues the closing of the trains after a tick (MotionParams::trains; nothing without the
  /// lever): every column with dense stepping, the columns of awake brick columns with sparse
  /// stepping (`sp`), whose changed bricks then wake.
  void close_trains(const cuda::SparseParams& sp, cudaStream_t s) {
    if (!step_rules_.motion.trains) return;
    cuda::launch_close_trains(cells_, size_, step_rules_.materials, step_rules_.motion.max_level(), sparse_ ? &sp : nullptr,
                              train_flags_.data(), s);
  }

  /// Enqueues the shallow-water pass after a tick (MotionParams::shallow; nothing without it): with
  /// sparse stepping (`sp`) the bricks it changed then wake.
  void run_shallow_pass(const cuda::SparseParams& sp, cudaStream_t s) {
    if (!shallow_) return;
    shallow_->enqueue(cells_, step_rules_.materials, sparse_ ? &sp : nullptr, s);
  }

  /// Enqueues zeroing the activity counters (before a sparse step's first tick).
  void reset_counters() {
    cuda::check(cudaMemsetAsync(counters_.data(), 0, counters_.bytes(), stream_.get()),
                "cudaMemsetAsync (activity counters)");
  }

  /// Enqueues the copy of the activity counters to pinned host memory after a sparse step of `ticks`
  /// ticks; collect_sparse_counters takes them.
  void fetch_counters(int ticks) {
    cuda::check(cudaMemcpyAsync(counters_host_.get(), counters_.data(), counters_.bytes(), cudaMemcpyDeviceToHost,
                                stream_.get()),
                "cudaMemcpyAsync (activity counters)");
    last_.ticks = std::uint64_t(ticks);
    counters_pending_ = true;
  }

  /// Waits for the last step and takes its activity counters into last_.
  void collect_sparse_counters() const {
    stream_.synchronize("step");
    counters_pending_ = false;
    const unsigned long long* counters = counters_host_.get();
    last_.brick_ticks = counters[cuda::kBrickTicks];
    last_.cell_ticks = counters[cuda::kCellTicks];
    last_.active_bricks = counters[cuda::kLastBricks];
    last_.active_cells = counters[cuda::kLastCells];
    known_awake_ = last_.active_bricks;
    // The last tick stepped no brick: the awake list was empty since the last cycle's end (only a
    // cycle's end or a tool rebuilds it), so no brick was dirty either and it stays empty.
    asleep_ = last_.active_bricks == 0;
  }

  /// With timelines attached: the next write waits until the renderer released its last read.
  void before_write() {
    if (released_) released_->wait(handoffs_, stream_.get());
  }
  /// With timelines attached: tells the renderer the writes so far are done.
  void after_write() {
    if (ready_) ready_->signal(++writes_, stream_.get());
  }

  /// Makes the backend's device current on the calling thread.
  void activate() const { cuda::check(cudaSetDevice(device_.index), "cudaSetDevice"); }

  /// Throws InvalidArgument unless `box` is a non-empty in-grid box of `bytes` cells.
  void check_box(const Box& box, std::size_t bytes, const char* what) const {
    if (box.empty() || !(intersect(box, Box{{0, 0, 0}, size_}) == box) || std::uint64_t(box.volume()) != bytes)
      throw InvalidArgument(std::string("cuda backend: ") + what + ": the box must be a non-empty box inside the " +
                            to_string(size_) + " grid with as many cells as the buffer holds (" +
                            std::to_string(bytes) + ")");
  }

  /// Throws InvalidArgument unless every box of `boxes` is a non-empty in-grid box and together they
  /// hold `bytes` cells.
  void check_boxes(std::span<const Box> boxes, std::size_t bytes, const char* what) const {
    std::uint64_t cells = 0;
    for (const Box& box : boxes) {
      check_box(box, std::size_t(box.volume()), what);
      cells += std::uint64_t(box.volume());
    }
    if (cells != bytes)
      throw InvalidArgument(std::string("cuda backend: ") + what + ": the boxes hold " + std::to_string(cells) +
                            " cells but the buffer " + std::to_string(bytes) + " bytes");
  }

  /// Throws InvalidArgument unless every brick of `wake_bricks` is one of the grid's.
  void check_wake(std::span<const std::uint32_t> wake_bricks, const char* what) const {
    for (const std::uint32_t b : wake_bricks)
      if (b >= total_bricks_)
        throw InvalidArgument(std::string("cuda backend: ") + what + ": brick " + std::to_string(b) +
                              " to wake is not one of the " + std::to_string(total_bricks_) + " bricks of the " +
                              to_string(size_) + " grid");
  }

  /// The device address of `cells` where they lie in the transfer buffer (transfer_buffer), so that a
  /// batch's kernel reaches them in place; else null.
  std::uint8_t* direct_cells(std::span<const std::uint8_t> cells) const {
    const std::uint8_t* base = transfer_.host();
    if (base == nullptr || cells.data() < base || cells.data() + cells.size() > base + transfer_.capacity())
      return nullptr;
    return transfer_.device() + (cells.data() - base);
  }

  /// Makes the staging hold a batch of `chunks` (`bytes` cells) and writes its table: each chunk's
  /// copy of the grid (with `side`, the side plane a scatter clears, or null), its cells following
  /// the table in order, or with `direct` (direct_cells) in the transfer buffer, each at its offset
  /// from there. Returns the table's device address. The staging must be free.
  const cuda::ChunkCopy* fill_batch_table(std::span<const cuda::BoxChunk> chunks, std::uint64_t bytes,
                                          std::uint8_t* side, std::uint8_t* direct) const {
    const std::uint64_t table = cuda::batch_table_bytes(chunks.size());
    staging_.reserve(direct != nullptr ? table : table + bytes, stream_.get());
    auto* copies = reinterpret_cast<cuda::ChunkCopy*>(staging_.host());
    std::uint64_t at = table;
    for (std::size_t k = 0; k < chunks.size(); ++k) {
      copies[k] = cuda::chunk_copy(cells_, size_, chunks[k],
                                   direct != nullptr ? direct + chunks[k].offset : staging_.device() + at);
      copies[k].side = side;
      at += chunks[k].cells();
    }
    return reinterpret_cast<const cuda::ChunkCopy*>(staging_.device());
  }

  /// Blocks along x of a batch launch: enough for its largest chunk (the kernels loop over the rest).
  static unsigned batch_blocks(std::span<const cuda::BoxChunk> chunks) {
    std::uint64_t most = 0;
    for (const cuda::BoxChunk& chunk : chunks) most = std::max(most, chunk.cells());
    return cuda::chunk_blocks(unsigned(most));
  }

  /// The grid index of the first cell of `box` when its cells are one run of the grid's bytes of
  /// more than a chunk (whole slices, or whole rows of one slice, or part of one row), else -1:
  /// such a box moves in one copy between the grid and the caller's memory, the way a whole-grid
  /// load or snapshot does, with no staging.
  std::int64_t large_run(const Box& box) const {
    const Int3 e = box.extent();
    const bool run = (e.x == size_.x && (e.y == size_.y || e.z == 1)) || (e.y == 1 && e.z == 1);
    if (!run || std::uint64_t(box.volume()) <= cuda::kTransferChunkBytes) return -1;
    return std::int64_t(box.min.x) + std::int64_t(size_.x) * (std::int64_t(box.min.y) + std::int64_t(size_.y) * box.min.z);
  }

  /// Copies the cells of `box` of `grid` (the cells or the checkpoint) out to `host` (x fastest, no
  /// padding): a large run in one copy, else chunk by chunk, a kernel gathering the chunk into the
  /// staging (box_transfer.cuh) and the host taking it from there once the device has finished.
  void copy_out(std::uint8_t* grid, const Box& box, std::uint8_t* host) const {
    activate();
    cudaStream_t s = stream_.get();
    if (const std::int64_t first = large_run(box); first >= 0) {
      cuda::check(cudaMemcpyAsync(host, grid + first, std::size_t(box.volume()), cudaMemcpyDeviceToHost, s),
                  "cudaMemcpyAsync (cells to the host)");
      stream_.synchronize("read");
      return;
    }
    cuda::for_each_chunk(box, cuda::kTransferChunkBytes, [&](const cuda::BoxChunk& chunk) {
      const std::uint64_t bytes = chunk.cells();
      staging_.reserve(bytes, s);
      const cuda::ChunkCopy copy = cuda::chunk_copy(grid, size_, chunk, staging_.device());
      cuda::gather_chunk_kernel<<<cuda::chunk_blocks(copy.count), cuda::kChunkThreads, 0, s>>>(copy);
      cuda::check_launch("gather kernel launch (reading cells)");
      stream_.synchronize("read");
      staging_.mark_free();
      std::memcpy(host + chunk.offset, staging_.host(), bytes);
    });
  }

  /// Enqueues copying `host` (x fastest, no padding) into the cells of `box`: a large run in one
  /// copy (which returns once the driver holds the bytes) unless a side plane is kept, else chunk
  /// by chunk, the host filling the staging (once the device has finished the last kernel that
  /// reads it) and a kernel scattering it into the grid. A tool's write is that one kernel.
  void copy_in(const Box& box, const std::uint8_t* host) {
    activate();
    before_write();
    cudaStream_t s = stream_.get();
    // With a side plane every chunk goes through the scatter kernel, which clears the velocity of
    // each cell it changes.
    if (const std::int64_t first = large_run(box); first >= 0 && side_.size() == 0) {
      cuda::check(cudaMemcpyAsync(cells_ + first, host, std::size_t(box.volume()), cudaMemcpyHostToDevice, s),
                  "cudaMemcpyAsync (cells to the device)");
      after_write();
      return;
    }
    const std::uint64_t total = std::uint64_t(box.volume());
    cuda::for_each_chunk(box, cuda::kTransferChunkBytes, [&](const cuda::BoxChunk& chunk) {
      const std::uint64_t bytes = chunk.cells();
      staging_.reserve(bytes, s);
      staging_.wait_free();
      std::memcpy(staging_.host(), host + chunk.offset, bytes);
      cuda::ChunkCopy copy = cuda::chunk_copy(cells_, size_, chunk, staging_.device());
      copy.side = side_.data();
      cuda::scatter_chunk_kernel<<<cuda::chunk_blocks(copy.count), cuda::kChunkThreads, 0, s>>>(copy);
      cuda::check_launch("scatter kernel launch (writing cells)");
      staging_.read_until(s);
      if (chunk.offset + bytes == total) after_write();
    });
  }

  /// Enqueues the wake of the bricks that writes since the last step left pending (dirty, their
  /// neighbourhoods awake, the awake list rebuilt), the kernel reading the list from the staging:
  /// the wakes of any number of tools between two steps cost one.
  void enqueue_pending_wake() {
    if (pending_wake_.empty()) return;
    activate();
    cudaStream_t s = stream_.get();
    const std::uint64_t bytes = pending_wake_.size() * sizeof(std::uint32_t);
    staging_.reserve(bytes, s);
    staging_.wait_free();
    std::memcpy(staging_.host(), pending_wake_.data(), bytes);
    cuda::launch_wake(sparse_params(), reinterpret_cast<const std::uint32_t*>(staging_.device()),
                      unsigned(pending_wake_.size()), s);
    staging_.read_until(s);
    pending_wake_.clear();
    asleep_ = false;
  }

  cuda::DeviceInfo device_;
  Int3 size_;
  std::uint64_t cell_count_;
  StepRules step_rules_;  ///< the Rules' tables (device memory) and parameters
  cuda::StepShape shape_;
  cuda::Stream stream_;
  cuda::DeviceBuffer<std::uint8_t> owned_cells_;  ///< the cells, until share_cells() moves them
  std::uint8_t* cells_;                           ///< the cells: owned_cells_ or imported_
  cuda::DeviceBuffer<std::uint8_t> checkpoint_;   ///< the cells at take_checkpoint(); empty when there is none
  std::optional<cuda::ImportedMemory> imported_;   ///< the renderer's buffer, after share_cells()
  std::optional<cuda::ImportedTimeline> ready_;    ///< signalled after each write (attach_timelines)
  std::optional<cuda::ImportedTimeline> released_;  ///< waited on before each write
  std::uint64_t writes_ = 0;                       ///< last value signalled on ready_
  std::uint64_t handoffs_ = 0;                     ///< last value handed out for released_
  cuda::DeviceBuffer<BlockKey> result_;
  cuda::DeviceBuffer<motion::MotionEntry> table_;  ///< the motion entries (motion rule sets only, motion_table.hpp)
  cuda::DeviceBuffer<unsigned long long> scratch_;
  bool sparse_;
  double dense_fraction_;  ///< awake fraction above which step() uses dense-recording ticks
  Int3 bricks_;
  std::uint32_t total_bricks_;
  mutable std::uint64_t known_awake_;  ///< bricks awake at the last tick the host knows of (an upper
                                       ///< bound after a tool's wake); all at creation
  unsigned sparse_grid_ = 1;
  cuda::DeviceBuffer<std::uint8_t> awake_, dirty_, changed_;
  cuda::DeviceBuffer<unsigned> reach_;  ///< per brick: its reach in the tick (motion model only)
  cuda::DeviceBuffer<std::uint32_t> list_;
  cuda::DeviceBuffer<unsigned> count_;
  cuda::DeviceBuffer<unsigned long long> counters_;
  cuda::DeviceBuffer<std::uint64_t> inert_;
  std::optional<cuda::DeviceHeadField> head_field_;  ///< MotionParams::pressure with a liquid in the table: the heads
  std::optional<cuda::DeviceShallowPass> shallow_;   ///< MotionParams::shallow with a liquid in the table: the face plane
  cuda::DeviceBuffer<std::uint8_t> side_;  ///< the side plane (MotionParams::momentum with a head field), else empty
  cuda::DeviceBuffer<std::uint8_t> train_flags_;  ///< per brick, MotionParams::trains with sparse stepping: a train changed it
  cuda::PinnedCounters counters_host_;        ///< the activity counters, copied back by each step
  mutable bool counters_pending_ = false;     ///< a step's counters are on their way to counters_host_
  mutable ActivityStats last_{};
  mutable bool asleep_ = false;  ///< no brick awake and none dirty: ticks need no device work until a wake
  mutable cuda::TransferStaging staging_;  ///< reused by every read and write of a box (box_transfer.cuh)
  cuda::TransferStaging transfer_;  ///< transfer_buffer: boxes' cells the batch kernels reach in place
  std::vector<std::uint32_t> pending_wake_;  ///< bricks that writes asked to wake, woken before the next step
};

}  // namespace

std::unique_ptr<Backend> make_cuda_backend(const BackendCreateInfo& info) {
  if (info.initial.cell_count() == 0) throw InvalidArgument("cuda backend: the initial grid is empty (0 cells)");
  if (!info.lut || info.lut->entries().size() != kBlockKeyCount)
    throw InvalidArgument("cuda backend: BackendCreateInfo::lut must be a full transition table (16,777,216 entries)");
  if (!info.rules) throw InvalidArgument("cuda backend: BackendCreateInfo::rules is null");
  for (const auto& [field, value] : {std::pair{"dense_fraction", info.cuda.dense_fraction},
                                     std::pair{"motion_dense_fraction", info.cuda.motion_dense_fraction}})
    if (!(value >= 0.0 && value <= 1.0))
      throw InvalidArgument(std::string("cuda backend: BackendCreateInfo::cuda.") + field + " = " +
                            std::to_string(value) + " must lie in 0..1");
  return std::make_unique<CudaBackend>(info);
}

}  // namespace granular
