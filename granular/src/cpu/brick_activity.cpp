#include "cpu/brick_activity.hpp"

#include <algorithm>
#include <limits>

#include "step/brick_grid.hpp"

namespace granular {

BrickActivity::BrickActivity(Int3 grid_size) : size_(grid_size), bricks_(brick_counts(grid_size)) {
  const std::size_t n = std::size_t(bricks_.x) * std::size_t(bricks_.y) * std::size_t(bricks_.z);
  awake_.assign(n, 1);
  dirty_.assign(n, 1);
  changed_.assign(n, 0);
  changed_pass_.assign(n, 0);
  quiet_pass_.assign(n * 8, 0);
  reach_.assign(n, 0);
  rebuild_active();
}

BrickRecord BrickActivity::next_pass() {
  if (pass_ == std::numeric_limits<std::uint32_t>::max()) {
    pass_ = 0;
    std::fill(changed_pass_.begin(), changed_pass_.end(), 0);
    std::fill(quiet_pass_.begin(), quiet_pass_.end(), 0);
  }
  BrickRecord r;
  r.bricks = bricks_;
  r.dirty = dirty_.data();
  r.changed = changed_.data();
  r.pass = ++pass_;
  r.changed_pass = changed_pass_.data();
  r.quiet_pass = quiet_pass_.data();
  r.reach = reach_.data();
  return r;
}

void BrickActivity::set_neighbours_awake(std::uint32_t brick) {
  const Int3 b = brick_coords(bricks_, brick);
  for (int z = std::max(b.z - 1, 0); z <= std::min(b.z + 1, bricks_.z - 1); ++z)
    for (int y = std::max(b.y - 1, 0); y <= std::min(b.y + 1, bricks_.y - 1); ++y)
      for (int x = std::max(b.x - 1, 0); x <= std::min(b.x + 1, bricks_.x - 1); ++x)
        awake_[brick_index(bricks_, x, y, z)] = 1;
}

void BrickActivity::rebuild_active() {
  active_.clear();
  runs_.clear();
  active_cells_ = 0;
  for (std::uint32_t i = 0; i < awake_.size(); ++i)
    if (awake_[i]) {
      active_.push_back(i);
      const Int3 b = brick_coords(bricks_, i);
      active_cells_ += brick_cells(size_, b.x, b.y, b.z);
      Run* last = runs_.empty() ? nullptr : &runs_.back();
      if (last != nullptr && b.x > 0 && last->first + std::uint32_t(last->length) == i && last->length < kMaxBrickRun)
        ++last->length;
      else
        runs_.push_back({i, 1});
    }
}

void BrickActivity::end_cycle() {
  std::fill(awake_.begin(), awake_.end(), 0);
  for (std::uint32_t i = 0; i < dirty_.size(); ++i)
    if (dirty_[i]) set_neighbours_awake(i);
  std::fill(dirty_.begin(), dirty_.end(), 0);
  rebuild_active();
}

void BrickActivity::wake(std::span<const std::uint32_t> bricks) {
  if (bricks.empty()) return;
  for (const std::uint32_t b : bricks) {
    dirty_[b] = 1;
    changed_pass_[b] = pass_ + 1;  // 0 after the last pass before the count wraps, which forgets it
    set_neighbours_awake(b);
  }
  rebuild_active();
}

void BrickActivity::mark_changed(std::span<const std::uint32_t> bricks) {
  for (const std::uint32_t b : bricks) changed_[b] = 1;
}

void BrickActivity::take_changed(std::span<std::uint8_t> flags) {
  for (std::size_t i = 0; i < changed_.size(); ++i) flags[i] |= changed_[i];
  std::fill(changed_.begin(), changed_.end(), 0);
}

bool BrickActivity::changed_since(std::uint32_t pass) const {
  if (pass_ < pass) return true;  // the count wrapped
  for (const std::uint32_t changed : changed_pass_)
    if (changed > pass) return true;
  return false;
}

}  // namespace granular
