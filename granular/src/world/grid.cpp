#include "granular/grid.hpp"

#include <algorithm>
#include <cstring>
#include <new>
#include <sstream>
#include <stdexcept>

#include "granular/errors.hpp"
#include "granular/extend/memory_budget.hpp"

namespace granular {

std::string to_string(Int3 size) {
  return std::to_string(size.x) + "x" + std::to_string(size.y) + "x" + std::to_string(size.z);
}

void check_grid_extents(Int3 size, const std::string& what) {
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
}

void check_grid_size(Int3 size, const std::string& what, double bytes_per_cell, double extra_bytes) {
  check_grid_extents(size, what);
  const double cells = double(size.x) * size.y * size.z;
  const double need = cells * bytes_per_cell + extra_bytes;
  const MemoryBudget have = available_memory();
  if (have.limited_by.empty() || need <= double(have.bytes)) return;
  std::ostringstream per_cell;
  per_cell << bytes_per_cell;
  throw OutOfMemory(what + ": size " + to_string(size) + " (" + std::to_string(std::int64_t(cells)) + " cells) needs " +
                    format_bytes(need) + " (" + per_cell.str() + (bytes_per_cell == 1.0 ? " byte" : " bytes") + " per cell" +
                    (extra_bytes > 0 ? " + " + format_bytes(extra_bytes) : std::string()) + ") but only " +
                    format_bytes(double(have.bytes)) + " can be allocated (limited by " + have.limited_by + ")");
}

namespace {

/// Allocates `n` cells of `value`, turning an allocation failure into OutOfMemory.
std::vector<std::uint8_t> allocate_cells(std::size_t n, std::uint8_t value, Int3 size, const char* purpose) {
  try {
    return std::vector<std::uint8_t>(n, value);
  } catch (const std::bad_alloc&) {
    throw OutOfMemory(std::string("Grid: could not allocate ") + format_bytes(double(n)) + " (" + std::to_string(n) +
                      " bytes) " + purpose + " a " + to_string(size) + " grid");
  } catch (const std::length_error&) {
    throw OutOfMemory(std::string("Grid: ") + std::to_string(n) + " bytes " + purpose + " a " + to_string(size) +
                      " grid exceed what a vector can hold");
  }
}

}  // namespace

Grid::Grid(Int3 size) {
  check_grid_size(size, "Grid");
  const std::size_t n = std::size_t(size.x) * std::size_t(size.y) * std::size_t(size.z);
  cells_ = allocate_cells(n, to_cell(Material::Void), size, "for");
  size_ = size;
}

Grid::Grid(const Grid& other) : size_(other.size_) {
  cells_ = allocate_cells(other.cells_.size(), 0, other.size_, "to copy");
  std::copy(other.cells_.begin(), other.cells_.end(), cells_.begin());
}

Grid& Grid::operator=(const Grid& other) {
  if (this != &other) *this = Grid(other);
  return *this;
}

Grid::Grid(Grid&& other) noexcept : size_(other.size_), cells_(std::move(other.cells_)) {
  other.size_ = {0, 0, 0};
  other.cells_.clear();
}

Grid& Grid::operator=(Grid&& other) noexcept {
  if (this == &other) return *this;
  size_ = other.size_;
  cells_ = std::move(other.cells_);
  other.size_ = {0, 0, 0};
  other.cells_.clear();
  return *this;
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

std::uint64_t hash_words_from(std::span<const std::uint8_t> bytes, std::size_t first_word) {
  constexpr std::uint64_t kGolden = 0x9E3779B97F4A7C15ull;
  std::uint64_t sum = 0;
  for (std::size_t at = 0, i = first_word; at < bytes.size(); at += 8, ++i) {
    std::uint64_t w = 0;
    std::memcpy(&w, bytes.data() + at, std::min<std::size_t>(8, bytes.size() - at));  // little-endian hosts only
    sum += mix64(w + (i + 1) * kGolden);
  }
  return sum;
}

std::uint64_t finish_hash(Int3 size, std::uint64_t partial_sum) {
  const std::uint64_t dims = std::uint64_t(std::uint32_t(size.x)) | (std::uint64_t(std::uint32_t(size.y)) << 21) |
                             (std::uint64_t(std::uint32_t(size.z)) << 42);
  return mix64(mix64(dims ^ 0x6772616E756C6172ull) + partial_sum);
}

std::uint64_t side_hash_term(std::span<const std::uint8_t> side) {
  if (std::all_of(side.begin(), side.end(), [](std::uint8_t b) { return b == 0; })) return 0;
  return side_hash_of_sum(hash_words(side, 0, (side.size() + 7) / 8));
}

std::uint64_t faces_hash_term(std::span<const std::int32_t> faces) {
  std::uint64_t sum = 0;
  bool any = false;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    any = any || faces[i] != 0;
    sum += mix64(std::uint64_t(std::uint32_t(faces[i])) + std::uint64_t(i + 1) * 0x9E3779B97F4A7C15ull);
  }
  return any ? mix64(sum ^ 0x66616365706C616Eull) : 0;  // "faceplan"
}

std::uint64_t hash_cells(Int3 size, std::span<const std::uint8_t> cells) {
  const std::size_t words = (cells.size() + 7) / 8;
  return finish_hash(size, hash_words(cells, 0, words));
}

}  // namespace granular
