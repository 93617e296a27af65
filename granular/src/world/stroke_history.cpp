#include "granular/stroke_history.hpp"

#include <string>

#include "granular/bricks.hpp"
#include "granular/errors.hpp"
#include "granular/world.hpp"
#include "io/zstd_bytes.hpp"

namespace granular {

namespace {

/// zstd level of the recorded bricks: the fastest, since a stroke's end waits for it.
constexpr int kPackLevel = 1;

}  // namespace

StrokeHistory::StrokeHistory(World& world, std::uint64_t max_bytes) : world_(world), max_bytes_(max_bytes) {
  if (max_bytes == 0) throw InvalidArgument("StrokeHistory: max_bytes = 0; the history needs room for a stroke");
}

StrokeHistory::~StrokeHistory() {
  try {
    if (owns_checkpoint()) world_.drop_checkpoint();
  } catch (const Error&) {
    // The world was moved from: it holds no checkpoint any more.
  }
}

StrokeHistory::Mark StrokeHistory::mark_now() const {
  return Mark{world_.tick(), world_.tool_calls(), false, false, world_.body_states()};
}

std::uint64_t StrokeHistory::mark_bytes(const Mark& m) {
  std::uint64_t bytes = m.bodies.bodies.size() * sizeof(BodyState);
  for (const BodyState& b : m.bodies.bodies) bytes += b.cells.size() * sizeof(std::uint64_t);
  return bytes;
}

void StrokeHistory::push_mark() {
  marks_.push_back(mark_now());
  bytes_ += mark_bytes(marks_.back());
}

bool StrokeHistory::changed() const {
  const Mark& at = marks_[at_];
  return world_.change_version() != version_ || world_.tick() != at.tick || world_.tool_calls() != at.tool_calls;
}

void StrokeHistory::settle() {
  world_.take_checkpoint();
  checkpoint_id_ = world_.checkpoint_id();
  version_ = world_.change_version();
}

bool StrokeHistory::owns_checkpoint() const {
  return !marks_.empty() && checkpoint_id_ != 0 && world_.checkpoint_id() == checkpoint_id_;
}

void StrokeHistory::check_checkpoint(const char* what) const {
  if (marks_.empty() || owns_checkpoint()) return;
  throw StateError(std::string("StrokeHistory::") + what +
                   ": the world's checkpoint is no longer the one this history took (another StrokeHistory on "
                   "this world, or the game's own World::take_checkpoint or drop_checkpoint, replaced it), so "
                   "undo and redo would put back other cells; clear() this history to start it again");
}

std::uint64_t StrokeHistory::delta_bytes(const Delta& d) const {
  return d.packed.size() + d.bricks.size() * sizeof(std::uint32_t);
}

void StrokeHistory::forget_redo() {
  while (marks_.size() > at_ + 1) {
    bytes_ -= mark_bytes(marks_.back());
    marks_.pop_back();
    bytes_ -= delta_bytes(deltas_.back());
    deltas_.pop_back();
  }
}

void StrokeHistory::record_tail() {
  if (marks_.empty()) {
    push_mark();
    at_ = 0;
    settle();
    return;
  }
  if (!changed()) return;
  forget_redo();
  Delta d;
  d.bricks = world_.bricks_changed_since(version_);
  d.cells = brick_cells(world_.size(), d.bricks);
  std::vector<std::uint8_t> before(d.cells);
  world_.read_checkpoint_bricks(d.bricks, before);
  d.packed = zstd_compress(before, kPackLevel, "StrokeHistory");
  bytes_ += delta_bytes(d);
  deltas_.push_back(std::move(d));
  push_mark();
  at_ = marks_.size() - 1;
  settle();
}

void StrokeHistory::begin_stroke() {
  check_checkpoint("begin_stroke");
  if (open_) end_stroke();
  if (!marks_.empty()) forget_redo();
  record_tail();
  marks_[at_].starts_stroke = true;
  open_ = true;
}

void StrokeHistory::end_stroke() {
  if (!open_) return;
  check_checkpoint("end_stroke");
  open_ = false;
  if (!changed()) {
    // Nothing happened in the stroke (no tool call, no tick): nothing to undo.
    marks_[at_].starts_stroke = false;
    return;
  }
  record_tail();
  marks_[at_].ends_stroke = true;
  enforce_bound();
}

std::uint64_t StrokeHistory::cross(std::size_t i, bool back) {
  Delta& d = deltas_[i];
  std::vector<std::uint8_t> here(d.cells);
  world_.read_bricks(d.bricks, here);
  const std::vector<std::uint8_t> there = zstd_decompress(d.packed, d.cells, "StrokeHistory: the recorded bricks");
  const Mark& to = marks_[back ? i : i + 1];
  world_.restore_bricks(d.bricks, there, to.tick, to.tool_calls);
  bytes_ -= delta_bytes(d);
  d.packed = zstd_compress(here, kPackLevel, "StrokeHistory");
  bytes_ += delta_bytes(d);
  return d.bricks.size();
}

std::optional<HistoryMove> StrokeHistory::undo() {
  check_checkpoint("undo");
  if (open_) end_stroke();
  if (marks_.empty()) return std::nullopt;
  const bool moved = changed();
  std::size_t target = marks_.size();
  for (std::size_t i = moved ? at_ + 1 : at_; i-- > 0;)
    if (marks_[i].starts_stroke) {
      target = i;
      break;
    }
  if (target == marks_.size()) return std::nullopt;
  if (moved) record_tail();  // what happened since the last mark, so that it is undone too
  HistoryMove move;
  for (std::size_t i = at_; i > target; --i) move.bricks += cross(i - 1, true);
  world_.restore_bodies(marks_[target].bodies);
  at_ = target;
  settle();
  move.tick = world_.tick();
  move.strokes_left = undo_count();
  return move;
}

std::optional<HistoryMove> StrokeHistory::redo() {
  check_checkpoint("redo");
  if (open_ || marks_.empty()) return std::nullopt;
  if (changed()) {
    forget_redo();
    return std::nullopt;
  }
  std::size_t target = at_ + 1;
  while (target < marks_.size() && !marks_[target].ends_stroke) ++target;
  if (target == marks_.size()) return std::nullopt;
  HistoryMove move;
  for (std::size_t i = at_; i < target; ++i) move.bricks += cross(i, false);
  world_.restore_bodies(marks_[target].bodies);
  at_ = target;
  settle();
  move.tick = world_.tick();
  move.strokes_left = redo_count();
  return move;
}

std::size_t StrokeHistory::undo_count() const {
  if (marks_.empty()) return 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < at_; ++i) n += marks_[i].starts_stroke ? 1 : 0;
  if (marks_[at_].starts_stroke && changed()) ++n;
  return n;
}

std::size_t StrokeHistory::redo_count() const {
  if (open_ || marks_.empty() || changed()) return 0;
  std::size_t n = 0;
  for (std::size_t i = at_ + 1; i < marks_.size(); ++i) n += marks_[i].ends_stroke ? 1 : 0;
  return n;
}

void StrokeHistory::enforce_bound() {
  // Drops marks [0, end) and the deltas between them.
  const auto drop_front = [this](std::size_t end) {
    for (std::size_t i = 0; i < end; ++i) {
      bytes_ -= delta_bytes(deltas_.front()) + mark_bytes(marks_.front());
      deltas_.pop_front();
      marks_.pop_front();
    }
    at_ -= end;
  };
  // What lies before the oldest stroke's start cannot be undone.
  std::size_t first = 0;
  while (first < at_ && !marks_[first].starts_stroke) ++first;
  drop_front(first);
  while (bytes_ > max_bytes_ && at_ > 0) {
    std::size_t next = 1;
    while (next < at_ && !marks_[next].starts_stroke) ++next;
    drop_front(next);
  }
}

std::uint64_t StrokeHistory::checkpoint_bytes() const { return world_.checkpoint_bytes(); }

void StrokeHistory::clear() {
  const bool owned = owns_checkpoint();
  marks_.clear();
  deltas_.clear();
  at_ = 0;
  bytes_ = 0;
  open_ = false;
  checkpoint_id_ = 0;
  if (owned) world_.drop_checkpoint();
}

}  // namespace granular
