#include "cpu/cpu_column_trains.hpp"

#include <algorithm>

#include "granular/bricks.hpp"
#include "step/brick_grid.hpp"
#include "step/column_trains.hpp"

namespace granular {

namespace {

/// Column x of a row of the grid, as TrainWalk reads it; its changes flag the bricks of its brick
/// column (a byte per brick: 1 changed, 3 changed where the block step sees it).
struct HostColumn {
  std::uint8_t* first;   // the column's cell at z = 0
  std::size_t layer;     // cells per layer
  std::uint8_t* flags;   // the flag of brick (bx, by, 0); brick layer bz at flags + bz * brick_layer
  std::size_t brick_layer;
  std::uint8_t get(int z) const { return first[std::size_t(z) * layer]; }
  void set(int z, std::uint8_t byte) const { first[std::size_t(z) * layer] = byte; }
  void changed(int z, bool seen) const { flags[std::size_t(brick_of(z)) * brick_layer] |= seen ? 3 : 1; }
};

}  // namespace

TrainChanges close_trains(std::uint8_t* cells, Int3 size, const StepMaterials& materials, int max_level,
                          const std::vector<std::uint32_t>* active, TaskSystem& tasks) {
  const Int3 bricks = brick_counts(size);
  // Which brick columns to walk (all without `active`).
  std::vector<std::uint8_t> walked(std::size_t(bricks.x) * std::size_t(bricks.y), active == nullptr ? 1 : 0);
  if (active != nullptr)
    for (const std::uint32_t b : *active) {
      const Int3 c = brick_coords(bricks, b);
      walked[std::size_t(c.x) + std::size_t(bricks.x) * std::size_t(c.y)] = 1;
    }
  const std::size_t layer = std::size_t(size.x) * std::size_t(size.y);
  const std::size_t brick_layer = std::size_t(bricks.x) * std::size_t(bricks.y);
  // Chunks of whole brick rows, so that no two tasks flag one brick.
  std::vector<std::uint8_t> flags(brick_layer * std::size_t(bricks.z), 0);
  const int chunks = std::max(1, std::min(bricks.y, tasks.thread_count() * 4));
  tasks.run(chunks, [&](int t) {
    std::vector<trains::TrainWalk> walks(std::size_t(size.x));
    std::vector<HostColumn> columns(std::size_t(size.x));
    const int y_begin = std::min(size.y, kBrickSize * (bricks.y * t / chunks));
    const int y_end = std::min(size.y, kBrickSize * (bricks.y * (t + 1) / chunks));
    for (int y = y_begin; y < y_end; ++y) {
      const std::uint8_t* row_walked = walked.data() + std::size_t(bricks.x) * std::size_t(brick_of(y));
      bool any = false;
      for (int bx = 0; bx < bricks.x; ++bx) any = any || row_walked[bx] != 0;
      if (!any) continue;
      for (int x = 0; x < size.x; ++x) {
        walks[std::size_t(x)] = trains::TrainWalk{};
        columns[std::size_t(x)] = HostColumn{cells + std::size_t(x) + std::size_t(size.x) * std::size_t(y), layer,
                                             flags.data() + brick_index(bricks, brick_of(x), brick_of(y), 0), brick_layer};
      }
      // Layer by layer, so each step reads a row of cells in order; each column's walk sees its cells
      // bottom up, as close_column would.
      for (int z = 0; z < size.z; ++z)
        for (int x = 0; x < size.x; ++x)
          if (row_walked[brick_of(x)] != 0) walks[std::size_t(x)].visit(columns[std::size_t(x)], z, materials, max_level);
      for (int x = 0; x < size.x; ++x)
        if (row_walked[brick_of(x)] != 0) walks[std::size_t(x)].finish(columns[std::size_t(x)], size.z, materials);
    }
  });
  TrainChanges all;
  for (std::uint32_t b = 0; b < flags.size(); ++b) {
    if (flags[b] != 0) all.changed.push_back(b);
    if (flags[b] == 3) all.seen.push_back(b);
  }
  return all;
}

}  // namespace granular
