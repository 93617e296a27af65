#include "granular/accuracy/height_map.hpp"

#include <algorithm>

namespace granular::accuracy {

HeightMap height_map(const Grid& grid, int floor_z, Material material) {
  const Int3 size = grid.size();
  HeightMap m{size.x, size.y, std::vector<double>(std::size_t(size.x) * std::size_t(size.y), 0.0)};
  const std::uint8_t cell = to_cell(material);
  const auto cells = grid.cells();
  const std::size_t layer = std::size_t(size.x) * std::size_t(size.y);
  for (int z = std::max(floor_z, 0); z < size.z; ++z)
    for (std::size_t i = 0; i < layer; ++i) m.h[i] += cells[std::size_t(z) * layer + i] == cell;
  return m;
}

HeightMap stacked_height_map(const Grid& grid, int floor_z, Material material) {
  const Int3 size = grid.size();
  HeightMap m{size.x, size.y, std::vector<double>(std::size_t(size.x) * std::size_t(size.y), 0.0)};
  const std::uint8_t cell = to_cell(material);
  const auto cells = grid.cells();
  const std::size_t layer = std::size_t(size.x) * std::size_t(size.y);
  const int floor = std::max(floor_z, 0);
  for (std::size_t i = 0; i < layer; ++i) {
    int z = floor;
    while (z < size.z && cells[std::size_t(z) * layer + i] == cell) ++z;
    m.h[i] = z - floor;
  }
  return m;
}

}  // namespace granular::accuracy
