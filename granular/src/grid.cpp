#include "granular/grid.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <new>
#include <sstream>

#include "granular/errors.hpp"

namespace granular {

namespace {

double physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return 0;  // unknown: do not pre-check
  return double(pages) * double(page_size);
}

std::string human_bytes(double b) {
  std::ostringstream s;
  s.precision(3);
  if (b >= 1024.0 * 1024 * 1024) s << b / (1024.0 * 1024 * 1024) << " GiB";
  else if (b >= 1024.0 * 1024) s << b / (1024.0 * 1024) << " MiB";
  else s << b << " bytes";
  return s.str();
}

}  // namespace

std::string to_string(Int3 size) {
  return std::to_string(size.x) + "x" + std::to_string(size.y) + "x" + std::to_string(size.z);
}

void check_grid_size(Int3 size, const std::string& what, double bytes_per_cell) {
  const int extents[3] = {size.x, size.y, size.z};
  const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    if (extents[a] <= 0)
      throw InvalidArgument(what + ": size " + to_string(size) + " has a " + (extents[a] == 0 ? "zero" : "negative") +
                            " extent along " + axes[a] + "; every extent must be at least 1");
    if (extents[a] > kMaxGridExtent)
      throw InvalidArgument(what + ": size " + to_string(size) + " exceeds the maximum extent " +
                            std::to_string(kMaxGridExtent) + " along " + axes[a]);
  }
  const double cells = double(size.x) * size.y * size.z;
  const double need = cells * bytes_per_cell;
  const double have = physical_memory_bytes();
  if (have > 0 && need > have)
    throw OutOfMemory(what + ": size " + to_string(size) + " (" + std::to_string(std::int64_t(cells)) +
                      " cells) needs " + human_bytes(need) + " but this machine has " + human_bytes(have) +
                      " of memory");
}

Grid::Grid(Int3 size) {
  check_grid_size(size, "Grid");
  const std::size_t n = std::size_t(size.x) * std::size_t(size.y) * std::size_t(size.z);
  try {
    cells_.assign(n, to_cell(Material::Void));
  } catch (const std::bad_alloc&) {
    throw OutOfMemory("Grid: could not allocate " + std::to_string(n) + " bytes for a " + to_string(size) + " grid");
  }
  size_ = size;
}

void Grid::fill(const Box& box, Material m) {
  const Box b = intersect(box, bounds());
  if (b.empty()) return;
  for (int z = b.min.z; z < b.max.z; ++z)
    for (int y = b.min.y; y < b.max.y; ++y) {
      std::uint8_t* row = cells_.data() + index({b.min.x, y, z});
      std::memset(row, to_cell(m), std::size_t(b.max.x - b.min.x));
    }
}

MaterialCounts Grid::count() const {
  MaterialCounts counts{};
  std::array<std::uint64_t, 256> hist{};
  for (std::uint8_t c : cells_) ++hist[c];
  for (int m = 0; m < kMaterialCount; ++m) counts[m] = hist[m];
  return counts;
}

std::uint64_t Grid::hash() const { return hash_cells(size_, cells_); }

std::uint64_t hash_words(std::span<const std::uint8_t> cells, std::size_t first_word, std::size_t word_count) {
  constexpr std::uint64_t kGolden = 0x9E3779B97F4A7C15ull;
  std::uint64_t sum = 0;
  const std::size_t n = cells.size();
  for (std::size_t i = first_word; i < first_word + word_count; ++i) {
    const std::size_t at = i * 8;
    std::uint64_t w = 0;
    if (at + 8 <= n) {
      std::memcpy(&w, cells.data() + at, 8);
    } else if (at < n) {
      std::memcpy(&w, cells.data() + at, n - at);  // little-endian hosts only (x86-64, aarch64)
    }
    sum += mix64(w + (i + 1) * kGolden);
  }
  return sum;
}

std::uint64_t finish_hash(Int3 size, std::uint64_t partial_sum) {
  const std::uint64_t dims = std::uint64_t(std::uint32_t(size.x)) | (std::uint64_t(std::uint32_t(size.y)) << 21) |
                             (std::uint64_t(std::uint32_t(size.z)) << 42);
  return mix64(mix64(dims ^ 0x6772616E756C6172ull) + partial_sum);
}

std::uint64_t hash_cells(Int3 size, std::span<const std::uint8_t> cells) {
  const std::size_t words = (cells.size() + 7) / 8;
  return finish_hash(size, hash_words(cells, 0, words));
}

}  // namespace granular
