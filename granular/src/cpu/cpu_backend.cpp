#include "cpu/cpu_backend.hpp"

#include <algorithm>
#include <cstring>
#include <map>
#include <mutex>
#include <new>
#include <tuple>

#include "cpu/cpu_column_trains.hpp"
#include "cpu/cpu_sparse_step.hpp"
#include "cpu/cpu_step.hpp"
#include "granular/errors.hpp"
#include "granular/extend/threads.hpp"
#include "step/inert_keys.hpp"
#include "step/motion_table.hpp"
#include "step/step_rules_builder.hpp"
#include "cpu/thread_pool.hpp"

namespace granular {

namespace {

/// Result tables are 64 MiB: backends of one process share them per transition table.
std::shared_ptr<const std::vector<BlockKey>> shared_result_table(const Lut& lut, int threads) {
  static std::mutex mutex;
  static std::map<std::uint64_t, std::weak_ptr<const std::vector<BlockKey>>> live;
  std::lock_guard lock(mutex);
  auto& slot = live[lut.content_hash()];
  if (auto table = slot.lock()) return table;
  auto table = std::make_shared<const std::vector<BlockKey>>(derive_result_table(lut.entries(), threads));
  slot = table;
  return table;
}

/// Inert-key tables are 2 MiB: backends of one process share them per table and variants. A motion
/// rule set's is derived for its rest keys only (derive_rest_inert_table), from the table itself;
/// a one-step rule set's for every key, from its result table.
std::shared_ptr<const std::vector<std::uint64_t>> shared_inert_table(const Lut& lut, const std::vector<BlockKey>* result,
                                                                      bool random_symmetry, int threads) {
  static std::mutex mutex;
  static std::map<std::tuple<std::uint64_t, bool, bool>, std::weak_ptr<const std::vector<std::uint64_t>>> live;
  std::lock_guard lock(mutex);
  auto& slot = live[{lut.content_hash(), random_symmetry, result == nullptr}];
  if (auto table = slot.lock()) return table;
  auto table = std::make_shared<const std::vector<std::uint64_t>>(
      result ? derive_inert_table(*result, random_symmetry, threads) : derive_rest_inert_table(lut.entries(), random_symmetry));
  slot = table;
  return table;
}

}  // namespace

CpuBackend::CpuBackend(const BackendCreateInfo& info)
    : grid_(info.initial),
      lut_(info.lut),
      result_(info.rules->motion.enabled() ? nullptr : shared_result_table(*lut_, info.threads)),
      sparse_(info.sparse),
      inert_(info.sparse && (info.rules->random_symmetry || info.rules->motion.enabled())
                 ? shared_inert_table(*lut_, result_.get(), info.rules->random_symmetry, info.threads)
                 : nullptr),
      activity_(info.initial.size()),
      task_system_(info.task_system ? info.task_system : std::make_shared<ThreadPool>(info.threads)),
      pool_(*task_system_) {
  const Int3 b = activity_.bricks();
  last_.total_bricks = std::uint64_t(b.x) * std::uint64_t(b.y) * std::uint64_t(b.z);
  const bool motion = info.rules->motion.enabled();
  if (motion) motion_table_ = derive_motion_table(lut_->entries());
  if (motion && info.rules->motion.pressure && step_materials(info.rules->materials).liquids != 0)
    head_field_.emplace(grid_.size());
  step_rules_ = make_step_rules(info, StepTables{.result = result_ ? result_->data() : nullptr,
                                                 .transitions = motion ? motion_table_.data() : nullptr,
                                                 .inert = inert_ ? inert_->data() : nullptr,
                                                 .heads = head_field_ ? head_field_->heads() : nullptr});
  outside_row_.assign(std::size_t(grid_.size().x), std::uint8_t(step_rules_.materials.outside));
  if (info.rules->motion.shallow && step_materials(info.rules->materials).liquids != 0) shallow_.emplace(grid_.size());
  if (head_field_ || shallow_) liquid_cells_ = liquid_in(grid_.cells());
  if (head_field_ && info.rules->motion.momentum) {
    side_.assign(grid_.cells().size(), 0);
    outside_side_row_.assign(std::size_t(grid_.size().x), 0);
  }
}

std::string CpuBackend::description() const {
  return "cpu (" + std::to_string(pool_.thread_count()) + (pool_.thread_count() == 1 ? " thread)" : " threads)");
}

void CpuBackend::step(std::uint64_t first_tick, int ticks) {
  const std::uint64_t total = last_.total_bricks;
  last_ = ActivityStats{};
  last_.total_bricks = total;
  const int substeps = step_rules_.motion.substeps;
  for (int i = 0; i < ticks; ++i) {
    const std::uint64_t tick = first_tick + std::uint64_t(i);
    if (head_field_) prepare_heads();
    if (sparse_) {
      last_.active_bricks = activity_.active().size();
      last_.active_cells = activity_.active_cells();
    } else {
      last_.active_bricks = total;
      last_.active_cells = std::uint64_t(grid_.cell_count());
    }
    for (int s = 0; s < substeps; ++s) {
      const StepContext c = context(tick, s);
      if (sparse_) {
        step_pass_sparse(c);
        // The sleep/wake decision rests on a cycle of 8 Margolus steps, which walk all 8 offsets
        // (ticks 8k .. 8k + 7, or sub-steps 8k .. 8k + 7 of a tick with the motion model): a
        // grain moves at most 8 cells in one, so the neighbourhood of a brick covers its reach.
        if (((tick * std::uint64_t(substeps) + std::uint64_t(s)) & 7u) == 7u) activity_.end_cycle();
      } else {
        step_pass(c);
      }
    }
    if (step_rules_.motion.trains) close_tick_trains();
    if (shallow_) run_shallow_pass();
    ++last_.ticks;
    last_.brick_ticks += last_.active_bricks;
    last_.cell_ticks += last_.active_cells;
  }
}

void CpuBackend::close_tick_trains() {
  // After the tick's last sub-step, which ended a sparse cycle: the awake bricks are those of the next
  // cycle, and every brick holding a moving grain or a carried train's sweep is among them. The
  // bricks where the block step sees a change wake as a tool's write wakes them; every brick a train
  // changed (inside a carried train too) counts as changed for the host.
  const TrainChanges changes = close_trains(grid_.cells().data(), grid_.size(), step_rules_.materials,
                                            step_rules_.motion.max_level(), sparse_ ? &activity_.active() : nullptr, pool_);
  if (!sparse_) return;
  activity_.wake(changes.seen);
  activity_.mark_changed(changes.changed);
}

void CpuBackend::run_shallow_pass() {
  // The pass is a function of the cells and the face plane: at rest on cells no step or write has
  // changed since, it would change nothing, so it is skipped (a pool at rest costs nothing). A grid
  // without liquid whose faces are at rest has nothing to move either.
  if (sparse_ && shallow_rest_ && !activity_.changed_since(shallow_pass_)) return;
  if (liquid_cells_ == 0 && shallow_->at_rest()) return;
  const std::vector<std::uint32_t> changed = shallow_->run(grid_.cells().data(), step_rules_.materials, pool_);
  shallow_rest_ = shallow_->at_rest();
  if (sparse_) {
    if (!changed.empty()) activity_.wake(changed);
    shallow_pass_ = activity_.pass();
  }
}

void CpuBackend::prepare_heads() {
  // A grid without liquid (stepping never makes one: it permutes cells) has no head, and steps with
  // the Rules without pressure. Otherwise the heads are solved again when a cell changed since the
  // last solve, or while a pressure move may start somewhere: they are a function of the cells, so a
  // world at rest keeps them and costs nothing. The bricks where a pressure move may start stay awake.
  step_rules_.heads = liquid_cells_ == 0 ? nullptr : head_field_->heads();
  step_rules_.side = step_rules_.heads != nullptr && !side_.empty();
  if (liquid_cells_ == 0) {
    pressing_.clear();
  } else if (!sparse_ || !heads_solved_ || !pressing_.empty() || activity_.changed_since(heads_pass_)) {
    pressing_ = head_field_->solve(grid_.cells().data(), step_rules_.materials, pool_);
    heads_solved_ = true;
  }
  if (sparse_) {
    activity_.wake(pressing_);
    heads_pass_ = activity_.pass();
  }
}

StepContext CpuBackend::context(std::uint64_t tick, int substep) {
  return StepContext{.cells = grid_.cells().data(),
                     .size = grid_.size(),
                     .outside_row = outside_row_.data(),
                     .side = step_rules_.side ? side_.data() : nullptr,
                     .outside_side_row = step_rules_.side ? outside_side_row_.data() : nullptr,
                     .rules = step_rules_,
                     .tick = tick,
                     .substep = substep};
}

void CpuBackend::step_pass_sparse(const StepContext& c) {
  // One task per few runs, taken by the threads as they come free: runs differ in cost (sand or
  // air), so many small tasks balance best. The task reads everything through one pointer, which
  // keeps the std::function the pool takes free of an allocation.
  struct Pass {
    const StepContext& context;
    BrickRecord record;
    const std::vector<BrickActivity::Run>& runs;
    int tasks;
  };
  const auto& runs = activity_.runs();
  const int count = int(runs.size());
  const int tasks = std::min(count, pool_.thread_count() == 1 ? 1 : pool_.thread_count() * 32);
  const Pass pass{c, activity_.next_pass(), runs, tasks};
  if (pass.tasks > 0)
    pool_.run(pass.tasks, [p = &pass](int task) {
      const std::size_t count = p->runs.size();
      const std::size_t first = count * std::size_t(task) / std::size_t(p->tasks);
      const std::size_t last = count * std::size_t(task + 1) / std::size_t(p->tasks);
      for (std::size_t i = first; i < last; ++i)
        step_brick_run(p->context, p->record, p->runs[i].first, p->runs[i].length);
    });
}

void CpuBackend::take_changed_bricks(std::span<std::uint8_t> flags) {
  if (sparse_)
    activity_.take_changed(flags);
  else
    std::fill(flags.begin(), flags.end(), std::uint8_t(1));
}

void CpuBackend::step_pass(const StepContext& c) {
  // Several layer ranges per thread so that uneven layers (sand vs. air) still balance; the task
  // reads everything through one pointer (no allocation for the pool's std::function).
  struct Pass {
    const StepContext& context;
    int layers;
    int tasks;
  };
  const int layers = block_layers(c);
  const Pass pass{c, layers, std::min(layers, pool_.thread_count() == 1 ? 1 : pool_.thread_count() * 8)};
  pool_.run(pass.tasks, [p = &pass](int task) {
    const int first = int(std::int64_t(p->layers) * task / p->tasks);
    const int last = int(std::int64_t(p->layers) * (task + 1) / p->tasks);
    for (int layer = first; layer < last; ++layer) step_block_layer(p->context, layer);
  });
}

std::uint64_t CpuBackend::liquid_in(std::span<const std::uint8_t> cells) const {
  std::uint64_t n = 0;
  for (const std::uint8_t c : cells) n += step_rules_.materials.is_liquid(c & kMaterialMask) ? 1u : 0u;
  return n;
}

std::uint64_t CpuBackend::liquid_in(const Box& box) const {
  const int w = box.max.x - box.min.x;
  std::uint64_t n = 0;
  for (int z = box.min.z; z < box.max.z; ++z)
    for (int y = box.min.y; y < box.max.y; ++y)
      n += liquid_in(grid_.cells().subspan(grid_.index({box.min.x, y, z}), std::size_t(w)));
  return n;
}

void CpuBackend::read(const Box& box, std::span<std::uint8_t> out) const { copy_box(grid_.cells().data(), box, out); }

void CpuBackend::copy_box(const std::uint8_t* cells, const Box& box, std::span<std::uint8_t> out) const {
  const int w = box.max.x - box.min.x;
  std::size_t o = 0;
  for (int z = box.min.z; z < box.max.z; ++z)
    for (int y = box.min.y; y < box.max.y; ++y, o += std::size_t(w))
      std::memcpy(out.data() + o, cells + grid_.index({box.min.x, y, z}), std::size_t(w));
}

void CpuBackend::take_checkpoint() {
  try {
    checkpoint_.assign(grid_.cells().begin(), grid_.cells().end());
  } catch (const std::bad_alloc&) {
    throw OutOfMemory("cpu backend: could not allocate the " + std::to_string(grid_.cell_count()) +
                      " bytes of a checkpoint of the " + to_string(grid_.size()) + " grid");
  }
}

void CpuBackend::read_checkpoint(const Box& box, std::span<std::uint8_t> out) const {
  if (checkpoint_.empty()) throw StateError("cpu backend: read_checkpoint: no checkpoint was taken");
  copy_box(checkpoint_.data(), box, out);
}

void CpuBackend::drop_checkpoint() {
  checkpoint_.clear();
  checkpoint_.shrink_to_fit();
}

void CpuBackend::write(const Box& box, std::span<const std::uint8_t> in, std::span<const std::uint32_t> wake_bricks) {
  const int w = box.max.x - box.min.x;
  if (head_field_ || shallow_) liquid_cells_ = liquid_cells_ - liquid_in(box) + liquid_in(in);
  std::size_t o = 0;
  for (int z = box.min.z; z < box.max.z; ++z)
    for (int y = box.min.y; y < box.max.y; ++y, o += std::size_t(w)) {
      const std::size_t at = grid_.index({box.min.x, y, z});
      // A cell a write changes loses its velocity (it is a new cell, at rest).
      if (!side_.empty())
        for (int x = 0; x < w; ++x)
          if (grid_.cells()[at + std::size_t(x)] != in[o + std::size_t(x)]) side_[at + std::size_t(x)] = 0;
      std::memcpy(grid_.cells().data() + at, in.data() + o, std::size_t(w));
    }
  if (sparse_) activity_.wake(wake_bricks);
  heads_solved_ = false;
  shallow_rest_ = false;
}

MaterialCounts CpuBackend::count() const {
  const auto cells = grid_.cells();
  const int tasks = pool_.thread_count();
  std::vector<std::array<std::uint64_t, 256>> hist(std::size_t(tasks), std::array<std::uint64_t, 256>{});
  pool_.run(tasks, [&](int t) {
    const std::size_t first = cells.size() * std::size_t(t) / std::size_t(tasks);
    const std::size_t last = cells.size() * std::size_t(t + 1) / std::size_t(tasks);
    auto& h = hist[std::size_t(t)];
    for (std::size_t i = first; i < last; ++i) ++h[cells[i]];
  });
  MaterialCounts counts{};
  // A cell's high bits hold its motion level (motion.hpp): count by material.
  for (const auto& h : hist)
    for (int v = 0; v < 256; ++v) counts[v & kMaterialMask] += h[std::size_t(v)];
  return counts;
}

std::uint64_t CpuBackend::hash() const {
  const auto cells = grid_.cells();
  const std::size_t words = (cells.size() + 7) / 8;
  const int tasks = pool_.thread_count() * 4;
  std::vector<std::uint64_t> partial(std::size_t(tasks), 0);
  pool_.run(tasks, [&](int t) {
    const std::size_t first = words * std::size_t(t) / std::size_t(tasks);
    const std::size_t last = words * std::size_t(t + 1) / std::size_t(tasks);
    partial[std::size_t(t)] = hash_words(cells, first, last - first);
  });
  std::uint64_t sum = 0;
  for (auto p : partial) sum += p;
  // With a side plane, the velocities are part of the state.
  sum += side_hash_term(side_);
  if (shallow_) sum += faces_hash_term(shallow_->faces());
  return finish_hash(grid_.size(), sum);
}

std::vector<std::uint8_t> CpuBackend::read_side() const {
  if (std::all_of(side_.begin(), side_.end(), [](std::uint8_t b) { return b == 0; })) return {};
  return side_;
}

void CpuBackend::write_side(std::span<const std::uint8_t> side) {
  if (side.empty()) {
    std::fill(side_.begin(), side_.end(), std::uint8_t(0));
    return;
  }
  if (side_.empty())
    throw InvalidArgument("cpu backend: write_side: the rule set has no side plane (MotionParams::momentum with a "
                          "liquid material) to write WorldSnapshot::side into");
  if (side.size() != side_.size())
    throw InvalidArgument("cpu backend: write_side: " + std::to_string(side.size()) + " side bytes for the " +
                          std::to_string(side_.size()) + " cells of the " + to_string(grid_.size()) + " grid");
  std::copy(side.begin(), side.end(), side_.begin());
}

std::vector<std::int32_t> CpuBackend::read_faces() const { return shallow_ ? shallow_->faces() : std::vector<std::int32_t>{}; }

void CpuBackend::write_faces(std::span<const std::int32_t> faces) {
  if (!shallow_) {
    if (std::all_of(faces.begin(), faces.end(), [](std::int32_t f) { return f == 0; })) return;
    throw InvalidArgument("cpu backend: write_faces: the rule set has no face plane (MotionParams::shallow with a "
                          "liquid material) to write WorldSnapshot::faces into");
  }
  if (!faces.empty() && faces.size() != shallow_->face_count())
    throw InvalidArgument("cpu backend: write_faces: " + std::to_string(faces.size()) + " face values for the " +
                          std::to_string(shallow_->face_count()) + " of the " + to_string(grid_.size()) +
                          " grid (4 per column)");
  shallow_->set_faces(faces);
  shallow_rest_ = false;
}

std::unique_ptr<Backend> make_cpu_backend(const BackendCreateInfo& info) {
  if (info.initial.cell_count() == 0) throw InvalidArgument("cpu backend: the initial grid is empty (0 cells)");
  if (!info.lut || info.lut->entries().size() != kBlockKeyCount)
    throw InvalidArgument("cpu backend: BackendCreateInfo::lut must be a full transition table (16,777,216 entries)");
  if (!info.rules) throw InvalidArgument("cpu backend: BackendCreateInfo::rules is null");
  if (info.threads < 1 || info.threads > max_threads())
    throw InvalidArgument("cpu backend: BackendCreateInfo::threads = " + std::to_string(info.threads) + "; use 1.." +
                          std::to_string(max_threads()) + " (4 times the hardware threads)");
  if (info.task_system && (info.task_system->thread_count() < 1 || info.task_system->thread_count() > max_threads()))
    throw InvalidArgument("cpu backend: BackendCreateInfo::task_system->thread_count() = " +
                          std::to_string(info.task_system->thread_count()) + "; use 1.." +
                          std::to_string(max_threads()) + " (4 times the hardware threads)");
  return std::make_unique<CpuBackend>(info);
}

}  // namespace granular
