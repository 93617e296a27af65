#include "cpu/cpu_column_trains.hpp"

#include <algorithm>

#include "granular/bricks.hpp"
#include "step/brick_grid.hpp"
#include "step/column_trains.hpp"

namespace granular {

namespace {

/// Column x of a row of the grid, as TrainWalk reads it.
struct HostColumn {
  std::uint8_t* first;  // the column's cell at z = 0
  std::size_t layer;    // cells per layer
  std::uint8_t get(int z) const { return first[std::size_t(z) * layer]; }
  void set(int z, std::uint8_t byte) const { first[std::size_t(z) * layer] = byte; }
};

}  // namespace

std::vector<std::uint32_t> close_trains(std::uint8_t* cells, Int3 size, const StepMaterials& materials,
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
  const int chunks = std::max(1, std::min(size.y, tasks.thread_count() * 4));
  std::vector<std::vector<std::uint32_t>> changed(static_cast<std::size_t>(chunks));
  tasks.run(chunks, [&](int t) {
    std::vector<trains::TrainWalk> walks(std::size_t(size.x));
    std::vector<HostColumn> columns(std::size_t(size.x));
    for (int y = size.y * t / chunks; y < size.y * (t + 1) / chunks; ++y) {
      const std::uint8_t* row_walked = walked.data() + std::size_t(bricks.x) * std::size_t(brick_of(y));
      bool any = false;
      for (int bx = 0; bx < bricks.x; ++bx) any = any || row_walked[bx] != 0;
      if (!any) continue;
      for (int x = 0; x < size.x; ++x) {
        walks[std::size_t(x)] = trains::TrainWalk{};
        columns[std::size_t(x)] = HostColumn{cells + std::size_t(x) + std::size_t(size.x) * std::size_t(y), layer};
      }
      // Layer by layer, so each step reads a row of cells in order; each column's walk sees its cells
      // bottom up, as close_column would.
      for (int z = 0; z < size.z; ++z)
        for (int x = 0; x < size.x; ++x)
          if (row_walked[brick_of(x)] != 0) walks[std::size_t(x)].visit(columns[std::size_t(x)], z, materials);
      for (int x = 0; x < size.x; ++x) {
        const trains::ChangedSpan span = walks[std::size_t(x)].changed;
        if (!span.any()) continue;
        for (int bz = brick_of(span.lo); bz <= brick_of(span.hi); ++bz)
          changed[std::size_t(t)].push_back(brick_index(bricks, brick_of(x), brick_of(y), bz));
      }
    }
  });
  std::vector<std::uint32_t> all;
  for (const auto& c : changed) all.insert(all.end(), c.begin(), c.end());
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  return all;
}

}  // namespace granular
