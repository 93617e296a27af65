#include "cpu_step.hpp"

#include <cstring>

#include "cpu_block_ops.hpp"
#include "thread_pool.hpp"

namespace granular {

namespace {

using namespace cpu_ops;

/// A block with at least one cell outside the grid: outside cells read as static, never written.
template <class Rule>
void boundary_block(const StepContext& c, const Rule& rule, int x0, int y0, int z0) {
  const std::size_t sy = std::size_t(c.size.x), sz = sy * std::size_t(c.size.y);
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) {
    const int x = x0 + (i & 1), y = y0 + ((i >> 1) & 1), z = z0 + ((i >> 2) & 1);
    const bool inside = x >= 0 && y >= 0 && z >= 0 && x < c.size.x && y < c.size.y && z < c.size.z;
    const std::uint64_t cell = inside ? c.cells[std::size_t(x) + sy * std::size_t(y) + sz * std::size_t(z)] : std::uint64_t(rule.outside);
    v |= cell << (8 * i);
  }
  const std::uint64_t out = rule.step(v, x0, y0, z0);
  if (out == v) return;
  for (int i = 0; i < 8; ++i) {
    const int x = x0 + (i & 1), y = y0 + ((i >> 1) & 1), z = z0 + ((i >> 2) & 1);
    if (x >= 0 && y >= 0 && z >= 0 && x < c.size.x && y < c.size.y && z < c.size.z)
      c.cells[std::size_t(x) + sy * std::size_t(y) + sz * std::size_t(z)] = std::uint8_t(out >> (8 * i));
  }
}

/// A block fully inside the grid; rows r[0..3] are (y0,z0), (y0+1,z0), (y0,z0+1), (y0+1,z0+1).
/// Branch-free: a uniform block's key maps to itself, and the store rewrites the same bytes.
template <class Rule>
inline void interior_block(const Rule& rule, std::uint8_t* const* r, int x0, int y0, int z0) {
  const std::uint64_t v = load_pair(r[0] + x0) | (load_pair(r[1] + x0) << 16) | (load_pair(r[2] + x0) << 32) |
                          (load_pair(r[3] + x0) << 48);
  const std::uint64_t out = rule.step(v, x0, y0, z0);
  store_pair(r[0] + x0, out);
  store_pair(r[1] + x0, out >> 16);
  store_pair(r[2] + x0, out >> 32);
  store_pair(r[3] + x0, out >> 48);
}

template <class Rule>
void step_layer(const StepContext& c, const Rule& rule, int layer) {
  const BlockOffset o = rule.offset;
  const int nx = c.size.x, ny = c.size.y, nz = c.size.z;
  const int z0 = 2 * layer - o.z;
  const int blocks_x = block_count(nx, o.x), blocks_y = block_count(ny, o.y);
  const std::size_t sy = std::size_t(nx), sz = sy * std::size_t(ny);
  const bool z_inside = z0 >= 0 && z0 + 1 < nz;
  for (int by = 0; by < blocks_y; ++by) {
    const int y0 = 2 * by - o.y;
    if (!z_inside || y0 < 0 || y0 + 1 >= ny) {
      for (int bx = 0; bx < blocks_x; ++bx) boundary_block(c, rule, 2 * bx - o.x, y0, z0);
      continue;
    }
    std::uint8_t* base = c.cells + sy * std::size_t(y0) + sz * std::size_t(z0);
    std::uint8_t* const rows[4] = {base, base + sy, base + sz, base + sz + sy};
    int x = -o.x;
    if (x < 0) {
      boundary_block(c, rule, x, y0, z0);
      x += 2;
    }
    const int x_end = x + ((nx - x) / 2) * 2;  // blocks starting in [x, x_end) lie inside
    // Eight blocks (16 bytes per row) at a time: skip them when all 64 cells are equal, since a
    // permutation of equal cells changes nothing.
    for (; x + 16 <= x_end; x += 16) {
      const std::uint64_t ref = (std::uint64_t(rows[0][x]) & 0xFFu) * kEveryByte;
      std::uint64_t diff = 0;
      for (int r = 0; r < 4; ++r) diff |= (load_word(rows[r] + x) ^ ref) | (load_word(rows[r] + x + 8) ^ ref);
      if (diff == 0 && !rule.steps_uniform(rows[0][x])) continue;
      for (int k = 0; k < 16; k += 2) interior_block(rule, rows, x + k, y0, z0);
    }
    for (; x < x_end; x += 2) interior_block(rule, rows, x, y0, z0);
    if (x_end < nx) boundary_block(c, rule, x_end, y0, z0);
  }
}

}  // namespace

std::vector<BlockKey> derive_result_table(std::span<const Transition> lut, int threads) {
  std::vector<BlockKey> result(lut.size());
  ThreadPool pool(threads);
  constexpr int kChunks = 64;
  pool.run(kChunks, [&](int chunk) {
    const std::size_t first = lut.size() * std::size_t(chunk) / kChunks, last = lut.size() * std::size_t(chunk + 1) / kChunks;
    for (std::size_t k = first; k < last; ++k)
      result[k] = encode_key(apply_transition(decode_key(BlockKey(k)), lut[k]));
  });
  return result;
}

int block_layers(const StepContext& context) { return block_count(context.size.z, context_offset(context).z); }

void step_block_layer(const StepContext& context, int layer) {
  with_host_rule(context, [&](const auto& rule) { step_layer(context, rule, layer); });
}

}  // namespace granular
