#include <cuda_runtime.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "box_transfer.cuh"
#include "cuda_check.cuh"
#include "cuda_device.cuh"
#include "cuda_stream.cuh"
#include "device_buffer.cuh"
#include "external_interop.cuh"
#include "granular/backend.hpp"
#include "granular/backend_factory.hpp"
#include "granular/block.hpp"
#include "granular/errors.hpp"
#include "granular/grid.hpp"
#include "granular/lut.hpp"
#include "granular/motion.hpp"
#include "granular/rule_set.hpp"
#include "granular_cuda/cuda_backend_factory.hpp"
#include "motion_step_kernel.cuh"
#include "pinned_counters.cuh"
#include "reduce_kernels.cuh"
#include "sparse_motion_kernel.cuh"
#include "sparse_step_kernel.cuh"
#include "step_kernel.cuh"
#include "step_pair_kernel.cuh"
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
/// sparse state (docs/ARCHITECTURE.md, "Activity tracking"): sparse ticks (one launch per tick over
/// the awake bricks), or, when more than `dense_fraction` of the bricks were awake at the last tick
/// the host knows of, dense-recording ticks (the dense kernels, fused pairs included, recording
/// the sparse flags).
///
/// A rule set with the motion model (granular/motion.hpp) keeps the transition table on the device
/// and steps each tick as MotionParams::substeps sub-steps of the motion kernels
/// (motion_step_kernel.cuh, sparse_motion_kernel.cuh); every other rule set runs the kernels above,
/// unchanged.
class CudaBackend final : public Backend {
 public:
  /// Uploads info.initial and derives the result table from info.lut on the device (keeping the
  /// table there too when the rule set's motion model is enabled). info.cuda.dense_fraction (0..1)
  /// is the awake fraction above which sparse stepping uses dense-recording ticks (0: always, 1:
  /// never). The checks are make_cuda_backend's.
  explicit CudaBackend(const BackendCreateInfo& info)
      : device_(prepare_device(info.initial.size())),
        size_(info.initial.size()),
        cell_count_(std::uint64_t(info.initial.cell_count())),
        random_symmetry_(info.rules->random_symmetry),
        random_axis_order_(info.rules->random_axis_order),
        motion_(info.rules->motion),
        seed_(info.seed),
        shape_(cuda::step_shape(info.initial.size())),
        owned_cells_(cuda::cell_buffer_bytes(cell_count_), "the grid's cells"),
        cells_(owned_cells_.data()),
        result_(kBlockKeyCount, "the result table"),
        scratch_(kMaterialCount, "reduction counters"),
        sparse_(info.sparse),
        dense_fraction_(info.cuda.dense_fraction),
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
    if (sparse_) init_sparse(s);
    stream_.synchronize("building the result table");
    if (motion_.enabled()) table_ = std::move(table);  // the motion kernels look up the transitions
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
    if (sparse_ && asleep_) {
      // Nothing is awake and nothing can wake without a tool: the ticks change no cell, so they
      // cost no device work at all (a settled world costs nothing).
      last_ = ActivityStats{};
      last_.total_bricks = total_bricks_;
      last_.ticks = std::uint64_t(ticks);
      after_write();
      return;
    }
    if (sparse_) {
      if (motion_.enabled())
        enqueue_motion(first_tick, ticks);
      else if (dense_recording())
        enqueue_dense(first_tick, ticks, true);
      else
        enqueue_sparse(first_tick, ticks);
      after_write();
      // With a renderer attached the host goes on at once; last_activity() waits for the counters.
      if (!ready_) collect_sparse_counters();
      return;
    }
    if (motion_.enabled())
      enqueue_motion(first_tick, ticks);
    else
      enqueue_dense(first_tick, ticks, false);
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
    copy_out(box, out.data());
  }

  /// Enqueues the write and returns without waiting for the device (box_transfer.cuh). The bricks
  /// wait on the host to be woken all at once before the next step (enqueue_pending_wake).
  void write(const Box& box, std::span<const std::uint8_t> in, std::span<const std::uint32_t> wake_bricks) override {
    check_box(box, in.size(), "write");
    for (const std::uint32_t b : wake_bricks)
      if (b >= total_bricks_)
        throw InvalidArgument("cuda backend: write: brick " + std::to_string(b) + " to wake is not one of the " +
                              std::to_string(total_bricks_) + " bricks of the " + to_string(size_) + " grid");
    copy_in(box, in.data());
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

  std::uint64_t hash() const override {
    activate();
    cudaStream_t s = stream_.get();
    cuda::check(cudaMemsetAsync(scratch_.data(), 0, sizeof(unsigned long long), s), "cudaMemsetAsync (hash)");
    cuda::hash_kernel<<<cuda::reduce_blocks(cell_count_, device_.sm_count), cuda::kReduceThreads, 0, s>>>(
        cells_, cell_count_, scratch_.data());
    cuda::check_launch("hash kernel launch");
    unsigned long long sum = 0;
    cuda::check(cudaMemcpyAsync(&sum, scratch_.data(), sizeof sum, cudaMemcpyDeviceToHost, s),
                "cudaMemcpyAsync (hash)");
    stream_.synchronize("hash");
    return finish_hash(size_, sum);
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
    if (random_symmetry_ || motion_.enabled()) {
      inert_ = cuda::DeviceBuffer<std::uint64_t>(kInertTableWords, "the inert-key table");
      cuda::inert_table_kernel<<<cuda::activity_blocks(kInertTableWords), cuda::kActivityThreads, 0, s>>>(
          result_.data(), random_symmetry_, inert_.data());
      cuda::check_launch("inert-key table kernel launch");
    }
    // Enough CUDA blocks of the sparse kernel to fill the device; each walks the list from there.
    const std::uint64_t resident = std::uint64_t(device_.sm_count) * (2048 / cuda::kBrickThreads);
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
    sp.list = list_.data();
    sp.count = count_.data();
    sp.counters = counters_.data();
    sp.inert = inert_.data();
    return sp;
  }

  /// True when the next step() should use dense-recording ticks: more than dense_fraction_ of the
  /// bricks were awake at the last tick the host knows of (no synchronisation to find out).
  bool dense_recording() const {
    return dense_fraction_ <= 0.0 || double(known_awake_) > dense_fraction_ * double(total_bricks_);
  }

  /// Enqueues the ticks with the dense kernels: an odd first tick alone, then even-odd pairs in one
  /// fused pass each, then a last odd one out. With `record` (dense-recording ticks of sparse mode)
  /// the kernels record the sparse flags of every tick as the sparse kernel would, and the cycle
  /// updates and activity counters (the awake list counted per run of ticks between two list
  /// changes) are enqueued as enqueue_sparse does; stepping an asleep brick changes nothing and
  /// records nothing (its blocks are inert), so the cells and the sparse state are those of sparse
  /// ticks.
  void enqueue_dense(std::uint64_t first_tick, int ticks, bool record) {
    cuda::StepParams p;
    p.cells = cells_;
    p.size = size_;
    p.result = result_.data();
    p.seed = seed_;
    p.random_axis_order = random_axis_order_;
    cudaStream_t s = stream_.get();
    cuda::SparseParams sp;
    cuda::ActivityRecord rec;
    const cuda::ActivityRecord* recording = nullptr;
    if (record) {
      sp = sparse_params();
      rec.bricks = bricks_;
      rec.dirty = dirty_.data();
      rec.changed = changed_.data();
      rec.inert = inert_.data();
      recording = &rec;
      reset_counters();
    }
    std::uint64_t tick = first_tick;
    int left = ticks;
    unsigned uncounted = 0;  // ticks stepped over the current awake list, not yet counted
    // After `done` ticks up to tick - 1: when recording, counts them and runs a cycle's end.
    auto finish = [&](unsigned done) {
      if (!record) return;
      uncounted += done;
      if (((tick - 1) & 7u) == 7u) {
        cuda::launch_count_awake(sp, size_, uncounted, left == 0, s);
        uncounted = 0;
        cuda::launch_end_cycle(sp, s);
      }
    };
    auto single = [&] {
      p.tick = tick++;
      --left;
      cuda::launch_step(p, random_symmetry_, shape_, s, recording);
      finish(1);
    };
    if (left > 0 && (tick & 1u) != 0) single();
    if (left >= 2) {
      const cuda::PairShape pair = cuda::pair_shape(size_);
      const std::size_t halo_bytes = cuda::pair_halo_bytes(size_, pair);
      void* halo = nullptr;
      // Without room for the halo buffer the ticks run one by one (the same result).
      if (halo_bytes == 0 || cudaMallocAsync(&halo, halo_bytes, s) == cudaSuccess) {
        while (left >= 2) {
          p.tick = tick;
          tick += 2;
          left -= 2;
          cuda::launch_step_pair(p, random_symmetry_, pair, static_cast<std::uint8_t*>(halo), s, recording);
          finish(2);
        }
        if (halo != nullptr) cuda::check(cudaFreeAsync(halo, s), "cudaFreeAsync (pair halo)");
      } else {
        (void)cudaGetLastError();
      }
    }
    while (left > 0) single();
    if (!record) return;
    if (uncounted > 0) cuda::launch_count_awake(sp, size_, uncounted, true, s);
    fetch_counters(ticks);
  }

  /// Enqueues the ticks over the awake bricks, one launch per tick plus the sleep/wake update at
  /// the end of every 8-tick cycle, and the copy of the activity counters to pinned host memory.
  void enqueue_sparse(std::uint64_t first_tick, int ticks) {
    cudaStream_t s = stream_.get();
    cuda::StepParams p;
    p.cells = cells_;
    p.size = size_;
    p.result = result_.data();
    p.seed = seed_;
    p.random_axis_order = random_axis_order_;
    const cuda::SparseParams sp = sparse_params();
    reset_counters();
    for (int i = 0; i < ticks; ++i) {
      p.tick = first_tick + std::uint64_t(i);
      cuda::launch_sparse_step(p, sp, random_symmetry_, i + 1 == ticks, sparse_grid_, s);
      if ((p.tick & 7u) == 7u) cuda::launch_end_cycle(sp, s);
    }
    fetch_counters(ticks);
  }

  /// Enqueues the ticks of a motion rule set, each as motion_.substeps sub-steps: one launch of the
  /// dense motion kernel per sub-step, or in sparse mode of the sparse motion kernel over the awake
  /// bricks, with a cycle's end after every 8th sub-step (substeps is a multiple of 8; a grain moves
  /// at most 8 cells in a cycle, as with one step per tick) and the
  /// activity counters as enqueue_sparse (the bricks counted once per tick). Motion rule sets have
  /// no dense-recording ticks (no recording form of the dense motion kernel): sparse mode always
  /// steps the awake bricks, whatever dense_fraction_.
  void enqueue_motion(std::uint64_t first_tick, int ticks) {
    cudaStream_t s = stream_.get();
    cuda::MotionStepParams p;
    p.cells = cells_;
    p.size = size_;
    p.table = table_.data();
    p.random_axis_order = random_axis_order_;
    p.sub = motion::sub_step(motion_, seed_, first_tick, 0, random_symmetry_);
    const cuda::SparseParams sp = sparse_ ? sparse_params() : cuda::SparseParams{};
    if (sparse_) reset_counters();
    for (int i = 0; i < ticks; ++i) {
      p.sub.tick = first_tick + std::uint64_t(i);
      for (int sub = 0; sub < motion_.substeps; ++sub) {
        p.sub.substep = sub;
        if (sparse_) {
          cuda::launch_sparse_motion(p, sp, sub == 0, sub == 0 && i + 1 == ticks, sparse_grid_, s);
          if ((sub & 7) == 7) cuda::launch_end_cycle(sp, s);
        } else {
          cuda::launch_motion_step(p, shape_, s);
        }
      }
    }
    if (sparse_) fetch_counters(ticks);
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

  /// Copies the cells of `box` out to `host` (x fastest, no padding): a large run in one copy, else
  /// chunk by chunk, a kernel gathering the chunk into the staging (box_transfer.cuh) and the host
  /// taking it from there once the device has finished.
  void copy_out(const Box& box, std::uint8_t* host) const {
    activate();
    cudaStream_t s = stream_.get();
    if (const std::int64_t first = large_run(box); first >= 0) {
      cuda::check(cudaMemcpyAsync(host, cells_ + first, std::size_t(box.volume()), cudaMemcpyDeviceToHost, s),
                  "cudaMemcpyAsync (cells to the host)");
      stream_.synchronize("read");
      return;
    }
    cuda::for_each_chunk(box, cuda::kTransferChunkBytes, [&](const cuda::BoxChunk& chunk) {
      const std::uint64_t bytes = chunk.cells();
      staging_.reserve(bytes, s);
      const cuda::ChunkCopy copy = cuda::chunk_copy(cells_, size_, chunk, staging_.device());
      cuda::gather_chunk_kernel<<<cuda::chunk_blocks(copy.count), cuda::kChunkThreads, 0, s>>>(copy);
      cuda::check_launch("gather kernel launch (reading cells)");
      stream_.synchronize("read");
      std::memcpy(host + chunk.offset, staging_.host(), bytes);
    });
  }

  /// Enqueues copying `host` (x fastest, no padding) into the cells of `box`: a large run in one
  /// copy (which returns once the driver holds the bytes), else chunk by chunk, the host filling the
  /// staging (once the device has finished the last kernel that reads it) and a kernel scattering
  /// it into the grid. A tool's write is that one kernel.
  void copy_in(const Box& box, const std::uint8_t* host) {
    activate();
    before_write();
    cudaStream_t s = stream_.get();
    if (const std::int64_t first = large_run(box); first >= 0) {
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
      const cuda::ChunkCopy copy = cuda::chunk_copy(cells_, size_, chunk, staging_.device());
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
  bool random_symmetry_;
  bool random_axis_order_;
  MotionParams motion_;  ///< the rule set's motion model (enabled: the motion kernels step)
  std::uint64_t seed_;
  cuda::StepShape shape_;
  cuda::Stream stream_;
  cuda::DeviceBuffer<std::uint8_t> owned_cells_;  ///< the cells, until share_cells() moves them
  std::uint8_t* cells_;                           ///< the cells: owned_cells_ or imported_
  std::optional<cuda::ImportedMemory> imported_;   ///< the renderer's buffer, after share_cells()
  std::optional<cuda::ImportedTimeline> ready_;    ///< signalled after each write (attach_timelines)
  std::optional<cuda::ImportedTimeline> released_;  ///< waited on before each write
  std::uint64_t writes_ = 0;                       ///< last value signalled on ready_
  std::uint64_t handoffs_ = 0;                     ///< last value handed out for released_
  cuda::DeviceBuffer<BlockKey> result_;
  cuda::DeviceBuffer<Transition> table_;  ///< the transition table, kept for motion rule sets only
  cuda::DeviceBuffer<unsigned long long> scratch_;
  bool sparse_;
  double dense_fraction_;  ///< awake fraction above which step() uses dense-recording ticks
  Int3 bricks_;
  std::uint32_t total_bricks_;
  mutable std::uint64_t known_awake_;  ///< bricks awake at the last tick the host knows of (an upper
                                       ///< bound after a tool's wake); all at creation
  unsigned sparse_grid_ = 1;
  cuda::DeviceBuffer<std::uint8_t> awake_, dirty_, changed_;
  cuda::DeviceBuffer<std::uint32_t> list_;
  cuda::DeviceBuffer<unsigned> count_;
  cuda::DeviceBuffer<unsigned long long> counters_;
  cuda::DeviceBuffer<std::uint64_t> inert_;
  cuda::PinnedCounters counters_host_;        ///< the activity counters, copied back by each step
  mutable bool counters_pending_ = false;     ///< a step's counters are on their way to counters_host_
  mutable ActivityStats last_{};
  mutable bool asleep_ = false;  ///< no brick awake and none dirty: ticks need no device work until a wake
  mutable cuda::TransferStaging staging_;  ///< reused by every read and write of a box (box_transfer.cuh)
  std::vector<std::uint32_t> pending_wake_;  ///< bricks that writes asked to wake, woken before the next step
};

}  // namespace

std::unique_ptr<Backend> make_cuda_backend(const BackendCreateInfo& info) {
  if (info.initial.cell_count() == 0) throw InvalidArgument("cuda backend: the initial grid is empty (0 cells)");
  if (!info.lut || info.lut->entries().size() != kBlockKeyCount)
    throw InvalidArgument("cuda backend: BackendCreateInfo::lut must be a full transition table (16,777,216 entries)");
  if (!info.rules) throw InvalidArgument("cuda backend: BackendCreateInfo::rules is null");
  if (!(info.cuda.dense_fraction >= 0.0 && info.cuda.dense_fraction <= 1.0))
    throw InvalidArgument("cuda backend: BackendCreateInfo::cuda.dense_fraction = " +
                          std::to_string(info.cuda.dense_fraction) + " must lie in 0..1");
  return std::make_unique<CudaBackend>(info);
}

}  // namespace granular
