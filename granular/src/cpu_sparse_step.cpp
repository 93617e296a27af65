#include "cpu_sparse_step.hpp"

#include <atomic>

#include "brick_grid.hpp"
#include "cpu_block_ops.hpp"
#include "inert_keys.hpp"

namespace granular {

namespace {

using namespace cpu_ops;

/// Steps one brick's blocks and remembers whether any had a non-inert key and whether any cell of
/// the brick itself changed; cells changed in a neighbour (by a block straddling into it) are
/// recorded at once.
template <bool kRandom>
class BrickStepper {
 public:
  BrickStepper(const StepContext& c, const BrickRecord& r, Int3 brick) : c_(c), r_(r), brick_(brick) {}

  /// A block with at least one cell outside the grid: outside cells read as solid, never written.
  void boundary_block(int x0, int y0, int z0) {
    const std::size_t sy = std::size_t(c_.size.x), sz = sy * std::size_t(c_.size.y);
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) {
      const int x = x0 + (i & 1), y = y0 + ((i >> 1) & 1), z = z0 + ((i >> 2) & 1);
      const std::uint64_t cell =
          inside(x, y, z) ? c_.cells[std::size_t(x) + sy * std::size_t(y) + sz * std::size_t(z)] : kOutsideCell;
      v |= cell << (8 * i);
    }
    const BlockKey key = pack_key(v);
    const BlockKey next = next_key<kRandom>(c_, key, x0, y0, z0);
    note(key, next);
    if (next == key) return;
    const std::uint64_t out = unpack_key(next);
    for (int i = 0; i < 8; ++i) {
      const int x = x0 + (i & 1), y = y0 + ((i >> 1) & 1), z = z0 + ((i >> 2) & 1);
      if (inside(x, y, z)) c_.cells[std::size_t(x) + sy * std::size_t(y) + sz * std::size_t(z)] = std::uint8_t(out >> (8 * i));
    }
    mark_changed(x0, y0, z0, v ^ out);
  }

  /// A block fully inside the grid; rows r[0..3] are (y0,z0), (y0+1,z0), (y0,z0+1), (y0+1,z0+1).
  void interior_block(std::uint8_t* const* r, int x0, int y0, int z0) {
    const std::uint64_t v = load_pair(r[0] + x0) | (load_pair(r[1] + x0) << 16) | (load_pair(r[2] + x0) << 32) |
                            (load_pair(r[3] + x0) << 48);
    const BlockKey key = pack_key(v);
    const BlockKey next = next_key<kRandom>(c_, key, x0, y0, z0);
    note(key, next);
    if (next == key) return;
    const std::uint64_t out = unpack_key(next);
    store_pair(r[0] + x0, out);
    store_pair(r[1] + x0, out >> 16);
    store_pair(r[2] + x0, out >> 32);
    store_pair(r[3] + x0, out >> 48);
    mark_changed(x0, y0, z0, v ^ out);
  }

  /// Writes what was seen to the record.
  void finish(std::uint32_t index) const {
    if (non_inert_) r_.dirty[index] = 1;
    if (owner_changed_) std::atomic_ref<std::uint8_t>(r_.changed[index]).store(1, std::memory_order_relaxed);
  }

 private:
  bool inside(int x, int y, int z) const {
    return x >= 0 && y >= 0 && z >= 0 && x < c_.size.x && y < c_.size.y && z < c_.size.z;
  }

  /// Notes a block's key: a non-inert one keeps the brick awake for the next cycle. Without random
  /// variants a key is inert iff the rule maps it to itself.
  void note(BlockKey key, BlockKey next) {
    if constexpr (kRandom) {
      if (!non_inert_ && !is_inert(r_.inert, key)) non_inert_ = true;
    } else {
      non_inert_ |= next != key;
    }
  }

  /// Records the bricks of the block's changed cells (`diff`: byte i non-zero when cell i changed).
  void mark_changed(int x0, int y0, int z0, std::uint64_t diff) {
    if (x0 >= brick_.x * kBrickSize && y0 >= brick_.y * kBrickSize && z0 >= brick_.z * kBrickSize) {
      owner_changed_ = true;  // the whole block lies in its owner
      return;
    }
    for (int i = 0; i < 8; ++i) {
      if (((diff >> (8 * i)) & 0xFFu) == 0) continue;
      const int x = x0 + (i & 1), y = y0 + ((i >> 1) & 1), z = z0 + ((i >> 2) & 1);
      const std::uint32_t b = brick_index(r_.bricks, brick_of(x), brick_of(y), brick_of(z));
      std::atomic_ref<std::uint8_t>(r_.changed[b]).store(1, std::memory_order_relaxed);
    }
  }

  const StepContext& c_;
  const BrickRecord& r_;
  Int3 brick_;
  bool non_inert_ = false;
  bool owner_changed_ = false;
};

template <bool kRandom>
void step_brick_blocks(const StepContext& c, const BrickRecord& record, std::uint32_t index) {
  const BlockOffset o = block_offset(c.tick);
  const Int3 brick = brick_coords(record.bricks, index);
  const BlockSpan bx = owned_blocks(brick.x, record.bricks.x, c.size.x, o.x);
  const BlockSpan by = owned_blocks(brick.y, record.bricks.y, c.size.y, o.y);
  const BlockSpan bz = owned_blocks(brick.z, record.bricks.z, c.size.z, o.z);
  const int nx = c.size.x, ny = c.size.y, nz = c.size.z;
  const std::size_t sy = std::size_t(nx), sz = sy * std::size_t(ny);
  BrickStepper<kRandom> stepper(c, record, brick);
  const int x_first = 2 * bx.first - o.x, x_stop = 2 * bx.last - o.x;
  for (int kz = bz.first; kz < bz.last; ++kz) {
    const int z0 = 2 * kz - o.z;
    const bool z_inside = z0 >= 0 && z0 + 1 < nz;
    for (int ky = by.first; ky < by.last; ++ky) {
      const int y0 = 2 * ky - o.y;
      int x = x_first;
      if (!z_inside || y0 < 0 || y0 + 1 >= ny) {
        for (; x < x_stop; x += 2) stepper.boundary_block(x, y0, z0);
        continue;
      }
      std::uint8_t* base = c.cells + sy * std::size_t(y0) + sz * std::size_t(z0);
      std::uint8_t* const rows[4] = {base, base + sy, base + sz, base + sz + sy};
      if (x < 0) {
        stepper.boundary_block(x, y0, z0);
        x += 2;
      }
      const int inside_end = x + ((nx - x) / 2) * 2;  // blocks starting in [x, inside_end) lie inside
      const int x_end = inside_end < x_stop ? inside_end : x_stop;
      // Eight blocks at a time are skipped when all 64 cells are equal: a uniform key is inert.
      for (; x + 16 <= x_end; x += 16) {
        const std::uint64_t ref = (std::uint64_t(rows[0][x]) & 0xFFu) * kEveryByte;
        std::uint64_t diff = 0;
        for (int r = 0; r < 4; ++r) diff |= (load_word(rows[r] + x) ^ ref) | (load_word(rows[r] + x + 8) ^ ref);
        if (diff == 0) continue;
        for (int k = 0; k < 16; k += 2) stepper.interior_block(rows, x + k, y0, z0);
      }
      for (; x < x_end; x += 2) stepper.interior_block(rows, x, y0, z0);
      for (; x < x_stop; x += 2) stepper.boundary_block(x, y0, z0);
    }
  }
  stepper.finish(index);
}

}  // namespace

void step_brick(const StepContext& context, const BrickRecord& record, std::uint32_t brick) {
  if (context.random_symmetry)
    step_brick_blocks<true>(context, record, brick);
  else
    step_brick_blocks<false>(context, record, brick);
}

}  // namespace granular
