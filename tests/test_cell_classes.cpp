/// @file test_cell_classes.cpp
/// The stamp's per-cell class lookup (classify_cells, bodies/cell_classes.hpp) against the table
/// read a cell at a time: every mark and material, the high bits of a byte ignored, and lengths
/// that end inside and on a step of sixteen cells.

#include <doctest/doctest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "bodies/cell_classes.hpp"

namespace granular {
namespace {

TEST_CASE("classify_cells gives every cell its table entry") {
  std::mt19937 rng(7);
  CellClassTable table{};
  for (auto& row : table)
    for (std::uint8_t& entry : row) entry = std::uint8_t(rng());
  for (const std::size_t count : {0u, 1u, 15u, 16u, 17u, 31u, 32u, 100u, 4099u}) {
    std::vector<std::uint8_t> marks(count), bytes(count), out(count, 0);
    for (std::size_t i = 0; i < count; ++i) {
      marks[i] = std::uint8_t(rng() % 4);
      bytes[i] = std::uint8_t(rng());  // a cell byte's bits above the material are not its class's
    }
    classify_cells(table, marks, bytes, out);
    for (std::size_t i = 0; i < count; ++i) {
      INFO("cell ", i, " of ", count);
      CHECK(out[i] == table[marks[i]][bytes[i] & kMaterialMask]);
    }
  }
}

}  // namespace
}  // namespace granular
