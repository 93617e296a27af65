#include "granular/world.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "granular/extend/backend.hpp"
#include "granular/bricks.hpp"
#include "granular/errors.hpp"
#include "world/cell_checks.hpp"

namespace granular {

namespace {

/// Calls copy(box, offset) for each of `bricks` of a grid of `size`: its cells, and where they start
/// in the bricks' packed bytes (brick after brick, each x fastest).
template <class Copy>
void for_each_brick(Int3 size, std::span<const std::uint32_t> bricks, Copy&& copy) {
  std::size_t offset = 0;
  for (const std::uint32_t b : bricks) {
    const Box box = brick_box(size, b);
    copy(box, offset);
    offset += std::size_t(box.volume());
  }
}

/// Calls fn(grid index, packed offset, width) for every row of the cells of `bricks` of a grid of
/// `size`: where the row starts in the grid (x fastest) and in the bricks' packed bytes.
template <class Fn>
void for_each_brick_row(Int3 size, std::span<const std::uint32_t> bricks, Fn&& fn) {
  for_each_brick(size, bricks, [&](const Box& box, std::size_t offset) {
    const std::size_t w = std::size_t(box.max.x - box.min.x);
    for (int z = box.min.z; z < box.max.z; ++z)
      for (int y = box.min.y; y < box.max.y; ++y, offset += w)
        fn(std::size_t(box.min.x) + std::size_t(size.x) * (std::size_t(y) + std::size_t(size.y) * std::size_t(z)),
           offset, w);
  });
}

/// True when bricks holding `cells` cells move faster as one copy of a whole grid of `size` than
/// brick by brick (one backend call each): when they hold more than an eighth of it.
bool whole_grid_is_faster(Int3 size, std::uint64_t cells) {
  return cells * 8 > std::uint64_t(size.x) * std::uint64_t(size.y) * std::uint64_t(size.z);
}

}  // namespace

void World::read_bricks(std::span<const std::uint32_t> bricks, std::span<std::uint8_t> out) const {
  gather_bricks(bricks, out, "World::read_bricks", [this](const Box& box, std::span<std::uint8_t> cells) {
    live().read(box, cells);
  });
}

void World::read_checkpoint_bricks(std::span<const std::uint32_t> bricks, std::span<std::uint8_t> out) const {
  if (live().checkpoint_bytes() == 0)
    throw StateError("World::read_checkpoint_bricks: there is no checkpoint (take_checkpoint)");
  gather_bricks(bricks, out, "World::read_checkpoint_bricks", [this](const Box& box, std::span<std::uint8_t> cells) {
    live().read_checkpoint(box, cells);
  });
}

void World::take_checkpoint() {
  live().take_checkpoint();
  checkpoint_id_ = ++checkpoints_taken_;
}
void World::drop_checkpoint() {
  live().drop_checkpoint();
  checkpoint_id_ = 0;
}
std::uint64_t World::checkpoint_bytes() const { return live().checkpoint_bytes(); }

void World::check_bricks(std::span<const std::uint32_t> bricks, std::size_t bytes, const char* what) const {
  const std::size_t total = brick_version_.size();
  for (const std::uint32_t b : bricks)
    if (b >= total)
      throw InvalidArgument(std::string(what) + ": brick " + std::to_string(b) + " is not one of the " +
                            std::to_string(total) + " bricks of the " + to_string(size_) + " grid");
  const std::uint64_t cells = brick_cells(size_, bricks);
  if (bytes != cells)
    throw InvalidArgument(std::string(what) + ": the buffer holds " + std::to_string(bytes) + " bytes; the " +
                          std::to_string(bricks.size()) + " bricks hold " + std::to_string(cells) + " cells");
}

template <class Read>
void World::gather_bricks(std::span<const std::uint32_t> bricks, std::span<std::uint8_t> out, const char* what,
                          Read&& read) const {
  check_bricks(bricks, out.size(), what);
  if (!whole_grid_is_faster(size_, out.size())) {
    for_each_brick(size_, bricks, [&](const Box& box, std::size_t offset) {
      read(box, out.subspan(offset, std::size_t(box.volume())));
    });
    return;
  }
  std::vector<std::uint8_t> whole = cell_buffer(Box{{0, 0, 0}, size_});
  read(Box{{0, 0, 0}, size_}, whole);
  for_each_brick_row(size_, bricks, [&](std::size_t cell, std::size_t offset, std::size_t w) {
    std::copy_n(whole.data() + cell, w, out.data() + offset);
  });
}

void World::restore_bricks(std::span<const std::uint32_t> bricks, std::span<const std::uint8_t> bytes,
                           std::uint64_t tick, std::uint64_t tool_calls) {
  check_bricks(bricks, bytes.size(), "World::restore_bricks");
  check_cell_bytes(bytes, *rules_, "World::restore_bricks", [&](std::size_t i) {
    std::size_t brick = 0;
    for (std::size_t cells = 0; brick < bricks.size(); ++brick) {
      const auto volume = std::size_t(brick_box(size_, bricks[brick]).volume());
      if (i < cells + volume) return "byte " + std::to_string(i) + " (brick " + std::to_string(bricks[brick]) + ")";
      cells += volume;
    }
    return "byte " + std::to_string(i);
  });
  // A rewound tick moves the 8-tick activity cycle against the cells: every brick wakes, as after
  // load(), so that sparse stepping stays exact whatever it held.
  if (whole_grid_is_faster(size_, bytes.size())) {
    std::vector<std::uint8_t> whole = read_cells(Box{{0, 0, 0}, size_});
    for_each_brick_row(size_, bricks, [&](std::size_t cell, std::size_t offset, std::size_t w) {
      std::copy_n(bytes.data() + offset, w, whole.data() + cell);
    });
    write_grid(whole, bricks);
  } else if (bricks.empty()) {
    // Nothing to write: brick 0 gets its own bytes back, a write that wakes every brick.
    const std::vector<std::uint8_t> own = read_cells(brick_box(size_, 0));
    live().write(brick_box(size_, 0), own, all_bricks(brick_counts()));
  } else {
    mark_bricks(bricks);
    const std::vector<std::uint32_t> every = all_bricks(brick_counts());
    bool woken = false;
    for_each_brick(size_, bricks, [&](const Box& box, std::size_t offset) {
      live().write(box, bytes.subspan(offset, std::size_t(box.volume())),
                   woken ? std::span<const std::uint32_t>() : std::span<const std::uint32_t>(every));
      woken = true;
    });
  }
  tick_ = tick;
  tool_calls_ = tool_calls;
}

}  // namespace granular
