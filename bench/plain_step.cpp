#include "plain_step.hpp"

#include <thread>
#include <vector>

namespace granular::bench {

namespace {

/// A block with cells outside the grid: bounds-checked, outside cells read as solid.
void plain_boundary_block(std::uint8_t* cells, Int3 n, const Transition* lut, int x0, int y0, int z0) {
  BlockCells b{};
  std::size_t at[8];
  bool inside[8];
  for (int i = 0; i < 8; ++i) {
    const int x = x0 + (i & 1), y = y0 + ((i >> 1) & 1), z = z0 + ((i >> 2) & 1);
    inside[i] = x >= 0 && y >= 0 && z >= 0 && x < n.x && y < n.y && z < n.z;
    at[i] = inside[i] ? std::size_t(x) + std::size_t(n.x) * (std::size_t(y) + std::size_t(n.y) * std::size_t(z)) : 0;
    b[i] = inside[i] ? cells[at[i]] : 1;
  }
  const BlockCells out = apply_transition(b, lut[encode_key(b)]);
  for (int i = 0; i < 8; ++i)
    if (inside[i]) cells[at[i]] = out[i];
}

void plain_layer(std::uint8_t* cells, Int3 n, const Transition* lut, BlockOffset o, int layer) {
  const int z0 = 2 * layer - o.z;
  const std::size_t sy = std::size_t(n.x), sz = sy * std::size_t(n.y);
  for (int by = 0; by < block_count(n.y, o.y); ++by) {
    const int y0 = 2 * by - o.y;
    for (int bx = 0; bx < block_count(n.x, o.x); ++bx) {
      const int x0 = 2 * bx - o.x;
      if (x0 < 0 || y0 < 0 || z0 < 0 || x0 + 1 >= n.x || y0 + 1 >= n.y || z0 + 1 >= n.z) {
        plain_boundary_block(cells, n, lut, x0, y0, z0);
        continue;
      }
      // Interior: gather the 8 bytes, key, transition, scatter by the permutation.
      std::uint8_t* base = cells + std::size_t(x0) + sy * std::size_t(y0) + sz * std::size_t(z0);
      std::uint8_t* const cell[8] = {base, base + 1, base + sy, base + sy + 1, base + sz, base + sz + 1, base + sz + sy,
                                     base + sz + sy + 1};
      BlockCells b{};
      for (int i = 0; i < 8; ++i) b[i] = *cell[i];
      const Transition t = lut[encode_key(b)];
      for (int i = 0; i < 8; ++i) *cell[destination(t, i)] = b[i];
    }
  }
}

}  // namespace

void plain_step(std::uint8_t* cells, Int3 size, const Transition* lut, std::uint64_t tick, int threads) {
  const BlockOffset o = block_offset(tick);
  const int layers = block_count(size.z, o.z);
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([=] {
      for (int layer = layers * t / threads; layer < layers * (t + 1) / threads; ++layer)
        plain_layer(cells, size, lut, o, layer);
    });
  for (auto& th : pool) th.join();
}

}  // namespace granular::bench
