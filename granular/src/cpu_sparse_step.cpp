#include "cpu_sparse_step.hpp"

#include <array>
#include <atomic>

#include "step/brick_grid.hpp"
#include "cpu_block_ops.hpp"
#include "step/inert_keys.hpp"

namespace granular {

namespace {

using namespace cpu_ops;

/// Bit i set when byte i of `diff` is non-zero (cell i of a block changed).
inline unsigned changed_cells(std::uint64_t diff) {
  std::uint64_t low = diff | (diff >> 4);
  low |= low >> 2;
  low = (low | (low >> 1)) & kEveryByte;
  return unsigned((low * 0x0102040810204080ull) >> 56);
}

/// Where the cells of a block lie relative to the brick being stepped, as a code per cell: bit 0
/// set when the cell is in the brick below along x, bit 1 along y, bit 2 along z (code 0: the
/// brick itself). kBrickCodes[s][m] is the set of codes (bit c for code c) of the cells in mask m
/// for a block whose straddle flags are s (bit 0: it reaches into the brick below along x, ...):
/// cell i's code is the flags its position does not cover, (~i) & s.
struct BrickCodeTable {
  std::uint8_t codes[8][256];
};

constexpr BrickCodeTable make_brick_codes() {
  BrickCodeTable t{};
  for (int s = 0; s < 8; ++s)
    for (int m = 0; m < 256; ++m) {
      unsigned set = 0;
      for (int i = 0; i < 8; ++i)
        if ((m >> i) & 1) set |= 1u << ((~i) & s);
      t.codes[s][m] = std::uint8_t(set);
    }
  return t;
}

constexpr BrickCodeTable kBrickCodes = make_brick_codes();

/// Steps the blocks of a run of bricks along x and remembers, per brick, whether any had a
/// non-inert key and whether any cell of the brick itself changed; cells changed in a neighbour
/// (by a block straddling into it) are recorded at once. select() names the brick whose blocks
/// come next.
template <class Rule>
class BrickStepper {
 public:
  /// A brick already dirty in this cycle starts as seen non-inert: its blocks need no quiet test.
  BrickStepper(const StepContext& c, const Rule& rule, const BrickRecord& r, Int3 first, int length)
      : c_(c), rule_(rule), r_(r), first_(first), brick_(first) {
    const std::uint32_t index = brick_index(r_.bricks, first_.x, first_.y, first_.z);
    for (int i = 0; i < length; ++i) non_inert_[std::size_t(i)] = r_.dirty[index + std::uint32_t(i)] != 0;
  }

  /// True when the selected brick has been seen non-inert (so far, or earlier in the cycle).
  bool non_inert() const { return non_inert_[std::size_t(current_)]; }

  /// The following blocks belong to brick `i` of the run.
  void select(int i) {
    current_ = i;
    brick_.x = first_.x + i;
  }

  /// A block with at least one cell outside the grid: outside cells read as static, never written.
  void boundary_block(int x0, int y0, int z0) {
    const std::size_t sy = std::size_t(c_.size.x), sz = sy * std::size_t(c_.size.y);
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) {
      const int x = x0 + (i & 1), y = y0 + ((i >> 1) & 1), z = z0 + ((i >> 2) & 1);
      const std::uint64_t cell =
          inside(x, y, z) ? c_.cells[std::size_t(x) + sy * std::size_t(y) + sz * std::size_t(z)] : std::uint64_t(rule_.outside);
      v |= cell << (8 * i);
    }
    const std::uint64_t out = rule_.step(v, x0, y0, z0);
    bool& non_inert = non_inert_[std::size_t(current_)];
    if (!non_inert) non_inert = !rule_.quiet(v, out);
    if (out == v) return;
    for (int i = 0; i < 8; ++i) {
      const int x = x0 + (i & 1), y = y0 + ((i >> 1) & 1), z = z0 + ((i >> 2) & 1);
      if (inside(x, y, z)) c_.cells[std::size_t(x) + sy * std::size_t(y) + sz * std::size_t(z)] = std::uint8_t(out >> (8 * i));
    }
    mark_changed(x0, y0, z0, v ^ out);
  }

  /// A block fully inside the grid; rows r[0..3] are (y0,z0), (y0+1,z0), (y0,z0+1), (y0+1,z0+1).
  /// `straddle`: bit a set when the block reaches into the brick below the selected one along axis
  /// a. Returns the codes (see kBrickCodes) of the bricks of its changed cells, with kNonInertSeen
  /// set when `check_quiet` and the block is not quiet; the caller ORs them over a row and hands
  /// them over by flush(), branch-free like the dense kernel's loop.
  unsigned interior_block(std::uint8_t* const* r, int x0, int y0, int z0, unsigned straddle, bool check_quiet) const {
    const std::uint64_t v = load_pair(r[0] + x0) | (load_pair(r[1] + x0) << 16) | (load_pair(r[2] + x0) << 32) |
                            (load_pair(r[3] + x0) << 48);
    const std::uint64_t out = rule_.step(v, x0, y0, z0);
    const unsigned seen = check_quiet && !rule_.quiet(v, out) ? kNonInertSeen : 0u;
    store_pair(r[0] + x0, out);
    store_pair(r[1] + x0, out >> 16);
    store_pair(r[2] + x0, out >> 32);
    store_pair(r[3] + x0, out >> 48);
    // A block inside the brick changes only the brick (code 0); the rare straddling ones look
    // their cells' codes up.
    if (straddle == 0) return seen | unsigned(out != v);
    return seen | kBrickCodes.codes[straddle][changed_cells(v ^ out)];
  }

  /// The bit interior_block sets when a block is not quiet.
  static constexpr unsigned kNonInertSeen = 1u << 8;

  /// Adds what interior blocks of the selected brick saw: code 0 is the brick itself, code c the
  /// brick (-(c & 1), -((c >> 1) & 1), -(c >> 2)) from it.
  void flush(bool non_inert, unsigned codes) {
    non_inert_[std::size_t(current_)] |= non_inert;
    if (codes & 1u) owner_changed_[std::size_t(current_)] = true;
    for (unsigned c = 1; c < 8; ++c)
      if ((codes >> c) & 1u) {
        const std::uint32_t b = brick_index(r_.bricks, brick_.x - int(c & 1u), brick_.y - int((c >> 1) & 1u),
                                            brick_.z - int(c >> 2));
        std::atomic_ref<std::uint8_t>(r_.changed[b]).store(1, std::memory_order_relaxed);
      }
  }

  /// Writes what was seen of the run's `length` bricks to the record.
  void finish(int length) const {
    const std::uint32_t first = brick_index(r_.bricks, first_.x, first_.y, first_.z);
    for (int i = 0; i < length; ++i) {
      if (non_inert_[std::size_t(i)]) r_.dirty[first + std::uint32_t(i)] = 1;
      if (owner_changed_[std::size_t(i)])
        std::atomic_ref<std::uint8_t>(r_.changed[first + std::uint32_t(i)]).store(1, std::memory_order_relaxed);
    }
  }

 private:
  bool inside(int x, int y, int z) const {
    return x >= 0 && y >= 0 && z >= 0 && x < c_.size.x && y < c_.size.y && z < c_.size.z;
  }

  /// Records the bricks of the block's changed cells (`diff`: byte i non-zero when cell i changed).
  void mark_changed(int x0, int y0, int z0, std::uint64_t diff) {
    if (x0 >= brick_.x * kBrickSize && y0 >= brick_.y * kBrickSize && z0 >= brick_.z * kBrickSize) {
      owner_changed_[std::size_t(current_)] = true;  // the whole block lies in its owner
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
  const Rule& rule_;
  const BrickRecord& r_;
  Int3 first_;
  Int3 brick_;
  int current_ = 0;
  std::array<bool, kMaxBrickRun> non_inert_{};
  std::array<bool, kMaxBrickRun> owner_changed_{};
};

template <class Rule>
void step_run_blocks(const StepContext& c, const Rule& rule, const BrickRecord& record, std::uint32_t first_index,
                     int length) {
  const BlockOffset o = rule.offset;
  const Int3 first = brick_coords(record.bricks, first_index);
  const BlockSpan bx_first = owned_blocks(first.x, record.bricks.x, c.size.x, o.x);
  const BlockSpan bx_last = owned_blocks(first.x + length - 1, record.bricks.x, c.size.x, o.x);
  const BlockSpan by = owned_blocks(first.y, record.bricks.y, c.size.y, o.y);
  const BlockSpan bz = owned_blocks(first.z, record.bricks.z, c.size.z, o.z);
  const int nx = c.size.x, ny = c.size.y, nz = c.size.z;
  const std::size_t sy = std::size_t(nx), sz = sy * std::size_t(ny);
  BrickStepper<Rule> stepper(c, rule, record, first, length);
  // Brick i of the run owns the blocks starting in [x_first + i * kBrickSize, ...) up to the next
  // brick's; the last brick's end is its own (it may own one block more at the grid's edge).
  const int x_first = 2 * bx_first.first - o.x, x_stop = 2 * bx_last.last - o.x;
  const int y_min = first.y * kBrickSize, z_min = first.z * kBrickSize;
  for (int kz = bz.first; kz < bz.last; ++kz) {
    const int z0 = 2 * kz - o.z;
    const bool z_inside = z0 >= 0 && z0 + 1 < nz;
    for (int ky = by.first; ky < by.last; ++ky) {
      const int y0 = 2 * ky - o.y;
      if (!z_inside || y0 < 0 || y0 + 1 >= ny) {
        for (int i = 0; i < length; ++i) {
          stepper.select(i);
          const int stop = i + 1 == length ? x_stop : x_first + (i + 1) * kBrickSize;
          for (int x = x_first + i * kBrickSize; x < stop; x += 2) stepper.boundary_block(x, y0, z0);
        }
        continue;
      }
      std::uint8_t* base = c.cells + sy * std::size_t(y0) + sz * std::size_t(z0);
      std::uint8_t* const rows[4] = {base, base + sy, base + sz, base + sz + sy};
      // Blocks below the brick's first row or layer, or left of its first column, straddle into
      // a neighbour brick.
      const unsigned row_straddle = (y0 < y_min ? 2u : 0u) | (z0 < z_min ? 4u : 0u);
      for (int i = 0; i < length; ++i) {
        stepper.select(i);
        const int x_min = (first.x + i) * kBrickSize;
        const int stop = i + 1 == length ? x_stop : x_first + (i + 1) * kBrickSize;
        int x = x_first + i * kBrickSize;
        if (x < 0) {
          stepper.boundary_block(x, y0, z0);
          x += 2;
        }
        const int inside_end = x + ((nx - x) / 2) * 2;  // blocks starting in [x, inside_end) lie inside
        const int x_end = inside_end < stop ? inside_end : stop;
        unsigned codes = stepper.non_inert() ? BrickStepper<Rule>::kNonInertSeen : 0u;
        // Eight blocks at a time are skipped when all 64 cells are equal and the rule says such a
        // block does not change; such blocks are quiet too.
        for (; x + 16 <= x_end; x += 16) {
          const std::uint64_t ref = (std::uint64_t(rows[0][x]) & 0xFFu) * kEveryByte;
          std::uint64_t diff = 0;
          for (int r = 0; r < 4; ++r) diff |= (load_word(rows[r] + x) ^ ref) | (load_word(rows[r] + x + 8) ^ ref);
          if (diff == 0 && !rule.steps_uniform(rows[0][x])) continue;
          for (int k = 0; k < 16; k += 2)
            codes |= stepper.interior_block(rows, x + k, y0, z0, row_straddle | (x + k < x_min ? 1u : 0u),
                                            (codes & BrickStepper<Rule>::kNonInertSeen) == 0);
        }
        for (; x < x_end; x += 2)
          codes |= stepper.interior_block(rows, x, y0, z0, row_straddle | (x < x_min ? 1u : 0u),
                                          (codes & BrickStepper<Rule>::kNonInertSeen) == 0);
        stepper.flush((codes & BrickStepper<Rule>::kNonInertSeen) != 0, codes & 0xFFu);
        for (; x < stop; x += 2) stepper.boundary_block(x, y0, z0);
      }
    }
  }
  stepper.finish(length);
}

}  // namespace

void step_brick_run(const StepContext& context, const BrickRecord& record, std::uint32_t first_brick, int length) {
  cpu_ops::with_host_rule(context, [&](const auto& rule) { step_run_blocks(context, rule, record, first_brick, length); });
}

}  // namespace granular
