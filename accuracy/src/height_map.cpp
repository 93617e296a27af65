#include "granular/accuracy/height_map.hpp"

#include <algorithm>

namespace granular::accuracy {

namespace {

/// The `material` cells of each column from floor_z up, layer by layer; with `stacked`, a column
/// stops counting at its first other cell (it counts layer z only while it holds z - floor cells).
HeightMap column_counts(const Grid& grid, int floor_z, Material material, bool stacked) {
  const Int3 size = grid.size();
  HeightMap m{size.x, size.y, std::vector<double>(std::size_t(size.x) * std::size_t(size.y), 0.0)};
  const std::uint8_t cell = to_cell(material);
  const auto cells = grid.cells();
  const std::size_t layer = std::size_t(size.x) * std::size_t(size.y);
  const int floor = std::max(floor_z, 0);
  for (int z = floor; z < size.z; ++z)
    for (std::size_t i = 0; i < layer; ++i)
      if (cells[std::size_t(z) * layer + i] == cell && (!stacked || m.h[i] == double(z - floor))) m.h[i] += 1;
  return m;
}

}  // namespace

HeightMap height_map(const Grid& grid, int floor_z, Material material) {
  return column_counts(grid, floor_z, material, false);
}

HeightMap stacked_height_map(const Grid& grid, int floor_z, Material material) {
  return column_counts(grid, floor_z, material, true);
}

}  // namespace granular::accuracy
