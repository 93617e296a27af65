#include "world/region_edit.hpp"

#include <algorithm>
#include <cstring>

#include "cpu/scratch_buffer.hpp"
#include "world/sphere_runs.hpp"

namespace granular {

void RegionEdit::begin(const Box& region, Int3 grid_size, Int3 origin) {
  region_ = region;
  origin_ = origin;
  extent_ = region.extent();
  count_ = std::size_t(region.volume());
  grid_bricks_ = brick_counts(grid_size);
  first_brick_ = {region.min.x / kBrickSize, region.min.y / kBrickSize, region.min.z / kBrickSize};
  bricks_ = {(region.max.x - 1) / kBrickSize - first_brick_.x + 1, (region.max.y - 1) / kBrickSize - first_brick_.y + 1,
             (region.max.z - 1) / kBrickSize - first_brick_.z + 1};
  if (cells_.size() < count_) cells_.resize(count_);
  flags_.assign(std::size_t(bricks_.x) * std::size_t(bricks_.y) * std::size_t(bricks_.z), 0);
  report_ = ChangeReport{};
}

template <class ForEachRun, class NewMaterial>
void RegionEdit::set_runs(ForEachRun&& for_each_run, NewMaterial&& new_material) {
  // Locals, not members, in the loop: a store of a cell byte could alias any member (and the map
  // of map_materials is the lambda's own copy for the same reason).
  std::uint8_t* const cells = cells_.data();
  std::uint8_t* const flags = flags_.data();
  std::array<std::int64_t, kMaterialCount> changed_from{}, changed_to{};
  for_each_run([&](int y, int z, int first, int last) {
    const Row r = row(y, z);
    for (int x = first; x < last; ++x) {
      const std::size_t i = r.cell(x);
      const std::uint8_t was = cell_material(cells[i]), now = new_material(i, was);
      if (now == was) continue;
      cells[i] = now;
      ++changed_from[was];
      ++changed_to[now];
      flags[r.flag(x)] = 1;
    }
  });
  for (std::size_t m = 0; m < changed_from.size(); ++m) {
    report_.cells_changed += changed_from[m];
    report_.removed[m] += std::uint64_t(changed_from[m]);
    report_.added[m] += std::uint64_t(changed_to[m]);
  }
}

template <class Fn>
void RegionEdit::for_each_row(Fn&& fn) const {
  for (int z = region_.min.z; z < region_.max.z; ++z)
    for (int y = region_.min.y; y < region_.max.y; ++y) fn(y, z, region_.min.x, region_.max.x);
}

void RegionEdit::replace_bytes(std::span<const std::uint8_t> bytes) {
  // A brick's part of a row at a time: compared (and copied when it differs) as one block of bytes.
  std::uint8_t* const cells = cells_.data();
  std::uint8_t* const flags = flags_.data();
  std::size_t i = 0;
  for_each_row([&](int y, int z, int first, int last) {
    const Row r = row(y, z);
    for (int x = first; x < last;) {
      const int end = std::min(last, (x / kBrickSize + 1) * kBrickSize);
      const std::size_t n = std::size_t(end - x);
      if (std::memcmp(cells + r.cell(x), bytes.data() + i, n) != 0) {
        std::memcpy(cells + r.cell(x), bytes.data() + i, n);
        flags[r.flag(x)] = 1;
      }
      i += n;
      x = end;
    }
  });
}

void RegionEdit::map_materials(const MaterialMap& to) {
  set_runs([&](auto&& fn) { for_each_row(fn); }, [map = to](std::size_t, std::uint8_t was) { return map[was]; });
}

void RegionEdit::map_materials(const Sphere& sphere, const MaterialMap& to) {
  set_runs([&](auto&& fn) { for_each_run_in_sphere(region_, sphere, fn, origin_); },
           [map = to](std::size_t, std::uint8_t was) { return map[was]; });
}

void RegionEdit::flag_written(std::span<const std::uint32_t> cells) {
  for (const std::uint32_t i : cells) {
    const std::size_t row = i / std::size_t(extent_.x);
    const int x = region_.min.x + int(i % std::size_t(extent_.x));
    const int y = region_.min.y + int(row % std::size_t(extent_.y)),
              z = region_.min.z + int(row / std::size_t(extent_.y));
    flags_[this->row(y, z).flag(x)] = 1;
  }
}

void RegionEdit::put_materials(std::span<const std::uint8_t> after) {
  const std::uint8_t* const materials = after.data();
  set_runs([&](auto&& fn) { for_each_row(fn); }, [&](std::size_t i, std::uint8_t) { return materials[i]; });
}

std::span<const std::uint32_t> RegionEdit::bricks() {
  list_.clear();
  std::size_t f = 0;
  for (int bz = first_brick_.z; bz < first_brick_.z + bricks_.z; ++bz)
    for (int by = first_brick_.y; by < first_brick_.y + bricks_.y; ++by) {
      const std::size_t row =
          (std::size_t(bz) * std::size_t(grid_bricks_.y) + std::size_t(by)) * std::size_t(grid_bricks_.x);
      for (int bx = first_brick_.x; bx < first_brick_.x + bricks_.x; ++bx, ++f)
        if (flags_[f]) list_.push_back(std::uint32_t(row + std::size_t(bx)));
    }
  return list_;
}

void RegionEdit::trim() {
  trim_scratch(cells_);
  trim_scratch(flags_);
  trim_scratch(list_);
}

}  // namespace granular
