#include "session/content_framing.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace viewer {

std::optional<granular::Box> content_bounds(const granular::World& world) {
  const granular::Int3 size = world.size();
  const std::int64_t layer = std::int64_t(size.x) * size.y;
  // Slabs of whole layers, about 16 M cells each, so a large grid is never copied at once.
  const int slab = int(std::clamp<std::int64_t>((std::int64_t(1) << 24) / std::max<std::int64_t>(layer, 1), 1, size.z));
  granular::Int3 lo{size.x, size.y, size.z}, hi{0, 0, 0};
  std::vector<std::uint8_t> cells;
  for (int z0 = 0; z0 < size.z; z0 += slab) {
    const int z1 = std::min(size.z, z0 + slab);
    cells.resize(std::size_t(layer) * std::size_t(z1 - z0));
    world.read_region(granular::Box{{0, 0, z0}, {size.x, size.y, z1}}, cells);
    std::size_t row_start = 0;
    for (int z = z0; z < z1; ++z)
      for (int y = 0; y < size.y; ++y, row_start += std::size_t(size.x)) {
        const std::uint8_t* row = cells.data() + row_start;
        const std::uint8_t* first = std::find_if(row, row + size.x, [](std::uint8_t c) { return c != 0; });
        if (first == row + size.x) continue;
        const std::uint8_t* last = std::find_if(std::make_reverse_iterator(row + size.x), std::make_reverse_iterator(row),
                                                [](std::uint8_t c) { return c != 0; }).base();
        lo = {std::min(lo.x, int(first - row)), std::min(lo.y, y), std::min(lo.z, z)};
        hi = {std::max(hi.x, int(last - row)), std::max(hi.y, y + 1), std::max(hi.z, z + 1)};
      }
  }
  if (hi.x <= lo.x) return std::nullopt;
  return granular::Box{lo, hi};
}

OrbitCamera frame_content(const granular::World& world, float aspect) {
  const granular::Box box = content_bounds(world).value_or(granular::Box{{0, 0, 0}, world.size()});
  return OrbitCamera::framing(box, aspect);
}

OrbitCamera initial_camera(const std::string& camera_text, const granular::World& world, float aspect) {
  return camera_text.empty() ? frame_content(world, aspect) : OrbitCamera::parse(camera_text, world.size());
}

}  // namespace viewer
