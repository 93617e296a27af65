#include "plain_step.hpp"

#include <thread>
#include <vector>

namespace granular::bench {

namespace {

void plain_layer(std::uint8_t* cells, Int3 n, const Transition* lut, BlockOffset o, int layer) {
  const int z0 = 2 * layer - o.z;
  for (int by = 0; by < block_count(n.y, o.y); ++by)
    for (int bx = 0; bx < block_count(n.x, o.x); ++bx) {
      const int x0 = 2 * bx - o.x, y0 = 2 * by - o.y;
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
