#include "cpu/cpu_sparse_step.hpp"

#include <array>
#include <atomic>

#include "cpu/cpu_block_ops.hpp"
#include "cpu/cpu_block_row.hpp"
#include "step/brick_grid.hpp"
#include "step/brick_reach.hpp"

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

/// The codes (kBrickCodes) of the bricks of the changed cells of blocks with straddle flags
/// `straddle`, `diff` the OR of their changed bytes.
inline unsigned changed_codes(unsigned straddle, std::uint64_t diff) {
  if (diff == 0) return 0;
  return straddle == 0 ? 1u : kBrickCodes.codes[straddle][changed_cells(diff)];
}

/// True when every one of `count` blocks is quiet (`before`, `after`: their bytes). Out of line: the
/// walk's loops stay small, and the test runs only on bricks not yet seen non-inert in the cycle.
template <class Rule>
[[gnu::noinline]] bool all_quiet(const Rule& rule, const std::uint64_t* before, const std::uint64_t* after, int count) {
  for (int k = 0; k < count; ++k)
    if (!rule.quiet(before[k], after[k])) return false;
  return true;
}

/// The Notes (cpu_block_row.hpp) of one brick's blocks in one row of blocks: which of their bytes
/// that are grid cells changed, apart from the block that reaches into the brick below along x
/// (offset 1: the brick's first block), and whether one was not quiet (tested only until one is).
template <class Rule>
struct BrickNotes {
  const Rule& rule;
  bool non_inert;                ///< a block that is not quiet was seen (or the brick was dirty already)
  int below_x;                   ///< the x0 of the block reaching into the brick below along x (-2: none)
  std::uint64_t diff = 0;        ///< OR over the other blocks of their changed bytes inside the grid
  std::uint64_t below_diff = 0;  ///< the same for the block reaching into the brick below
  std::uint32_t reach = 0;       ///< the largest reach the blocks added (Rule::kReach)

  /// Adds stepped blocks.
  /// A side byte that changed counts as a changed cell, and a block holding a velocity is not quiet.
  void blocks(int x0, const std::uint64_t* before, const std::uint64_t* after, int count, std::uint64_t inside,
              const std::uint64_t* side_before = nullptr, const std::uint64_t* side_after = nullptr) {
    if constexpr (Rule::kReach)
      for (int k = 0; k < count; ++k) {
        const std::uint32_t added = rule.reach_added(before[k], after[k]);
        if (added > reach) reach = added;
      }
    const std::uint64_t first = ((before[0] ^ after[0]) | (side_after ? side_before[0] ^ side_after[0] : 0)) & inside;
    std::uint64_t rest = 0;
    for (int k = 1; k < count; ++k) rest |= (before[k] ^ after[k]) | (side_after ? side_before[k] ^ side_after[k] : 0);
    if (side_after != nullptr)
      for (int k = 0; k < count && !non_inert; ++k) non_inert = side_after[k] != 0;
    rest &= inside;
    if (x0 == below_x)
      below_diff = first;
    else
      rest |= first;
    diff |= rest;
    if (!non_inert) non_inert = !all_quiet(rule, before, after, count);
  }
};

/// What a run's bricks saw, and the walk over their blocks.
template <class Rule>
class RunStepper {
 public:
  /// A brick already dirty in this cycle starts as seen non-inert: its blocks need no quiet test.
  RunStepper(const StepContext& c, const Rule& rule, const BrickRecord& r, std::uint32_t first, int length)
      : c_(c), rule_(rule), r_(r), first_index_(first), first_(brick_coords(r.bricks, first)), length_(length) {
    for (int i = 0; i < length; ++i) non_inert_[std::size_t(i)] = r_.dirty[first + std::uint32_t(i)] != 0;
  }

  /// Steps the blocks of the run's bricks first .. first + length - 1.
  void step() {
    const BlockOffset o = rule_.offset;
    const BlockSpan bx_first = owned_blocks(first_.x, r_.bricks.x, c_.size.x, o.x);
    const BlockSpan bx_last = owned_blocks(first_.x + length_ - 1, r_.bricks.x, c_.size.x, o.x);
    const BlockSpan by = owned_blocks(first_.y, r_.bricks.y, c_.size.y, o.y);
    const BlockSpan bz = owned_blocks(first_.z, r_.bricks.z, c_.size.z, o.z);
    x_first_ = 2 * bx_first.first - o.x;
    x_stop_ = 2 * bx_last.last - o.x;
    x_inside_end_ = inside_end(c_, x_first_ < 0 ? x_first_ + 2 : x_first_, x_stop_);
    // Bricks regular_begin_ .. regular_end_ - 1 own one group of eight blocks inside the grid each
    // (starting with the one reaching into the brick below along x at offset 1); the others (an
    // edge block at x = -1, a partial brick or the extra block at the grid's end) take the general
    // path.
    regular_begin_ = x_first_ < 0 ? 1 : 0;
    const bool last_regular = x_stop_ == x_first_ + length_ * kBrickSize && x_inside_end_ == x_stop_;
    regular_end_ = last_regular ? length_ : length_ - 1;
    if (regular_end_ < regular_begin_) regular_end_ = regular_begin_;
    const int y_min = first_.y * kBrickSize, z_min = first_.z * kBrickSize;
    for (int kz = bz.first; kz < bz.last; ++kz) {
      const int z0 = 2 * kz - o.z;
      for (int ky = by.first; ky < by.last; ++ky) {
        const int y0 = 2 * ky - o.y;
        const BlockRow row = block_row(c_, y0, z0);
        // Blocks below the brick's first row or layer reach into the brick below along y or z.
        const unsigned straddle = (y0 < y_min ? 2u : 0u) | (z0 < z_min ? 4u : 0u);
        if (row.inside == kWholeBlock)
          step_row<true>(row, y0, z0, straddle);
        else
          step_row<false>(row, y0, z0, straddle);
      }
    }
  }

  /// Writes what the run's bricks saw to the record: dirty, changed (and the pass it changed in),
  /// and for a brick all of whose blocks were quiet, this pass at this offset.
  void finish() const {
    const int offset = offset_index(rule_.offset);
    for (int i = 0; i < length_; ++i) {
      const std::uint32_t b = first_index_ + std::uint32_t(i);
      if (non_inert_[std::size_t(i)])
        r_.dirty[b] = 1;
      else
        r_.quiet_pass[std::size_t(b) * 8 + std::size_t(offset)] = r_.pass;
      if constexpr (Rule::kReach) {
        std::atomic_ref<std::uint8_t> stored(r_.reach[b]);
        if (rule_.reach_restarts() || reach_[std::size_t(i)] > stored.load(std::memory_order_relaxed))
          stored.store(std::uint8_t(reach_[std::size_t(i)]), std::memory_order_relaxed);
      }
      unsigned codes = 0;
      for (unsigned s = 0; s < 8; ++s) codes |= changed_codes(s, changed_[std::size_t(i)][s]);
      for (unsigned code = 0; code < 8; ++code)
        if ((codes >> code) & 1u)
          mark_changed(brick_index(r_.bricks, first_.x + i - int(code & 1u), first_.y - int((code >> 1) & 1u),
                                   first_.z - int(code >> 2)));
    }
  }

 private:
  /// One row of blocks across the run. `straddle`: the row's y and z straddle flags (kBrickCodes).
  template <bool kWhole>
  void step_row(const BlockRow& row, int y0, int z0, unsigned straddle) {
    if (regular_begin_ > 0) step_brick_row<kWhole>(0, row, y0, z0, straddle);
    // The regular bricks: one group of eight each, its first block reaching into the brick below
    // along x at offset 1.
    const bool below = rule_.offset.x != 0;
    int x = x_first_ + regular_begin_ * kBrickSize;
    for (int i = regular_begin_; i < regular_end_; ++i, x += kBrickSize) {
      BrickNotes<Rule> notes{rule_, non_inert_[std::size_t(i)], below ? x : -2};
      step_group<kWhole>(rule_, row, x, y0, z0, notes);
      keep(i, notes, straddle);
    }
    if (regular_end_ < length_) step_brick_row<kWhole>(length_ - 1, row, y0, z0, straddle);
  }

  /// Brick i's blocks in one row of blocks, in general: the edge block at x = -1, its blocks eight
  /// at a time where eight remain, the edge block at the grid's far side.
  template <bool kWhole>
  void step_brick_row(int i, const BlockRow& row, int y0, int z0, unsigned straddle) {
    int x = x_first_ + i * kBrickSize;
    BrickNotes<Rule> notes{rule_, non_inert_[std::size_t(i)], x >= 0 && x < (first_.x + i) * kBrickSize ? x : -2};
    const int stop = i + 1 == length_ ? x_stop_ : x + kBrickSize;
    const int x_end = stop < x_inside_end_ ? stop : x_inside_end_;
    if (x < 0) {
      step_edge_block(rule_, row, -1, y0, z0, notes);  // its outside column is no brick's
      x += 2;
    }
    step_blocks<kWhole>(rule_, row, x, x_end, y0, z0, notes);
    if (x_end < stop) step_edge_block(rule_, row, x_end, y0, z0, notes);
    keep(i, notes, straddle);
  }

  /// Keeps what brick i's blocks of one row (straddle flags `straddle`) saw.
  void keep(int i, const BrickNotes<Rule>& notes, unsigned straddle) {
    non_inert_[std::size_t(i)] = notes.non_inert;
    if (notes.reach > reach_[std::size_t(i)]) reach_[std::size_t(i)] = notes.reach;
    changed_[std::size_t(i)][straddle] |= notes.diff;
    changed_[std::size_t(i)][straddle | 1u] |= notes.below_diff;
  }

  void mark_changed(std::uint32_t brick) const {
    std::atomic_ref<std::uint8_t>(r_.changed[brick]).store(1, std::memory_order_relaxed);
    std::atomic_ref<std::uint32_t>(r_.changed_pass[brick]).store(r_.pass, std::memory_order_relaxed);
  }

  const StepContext& c_;
  const Rule& rule_;
  const BrickRecord& r_;
  std::uint32_t first_index_;
  Int3 first_;
  int length_;
  int x_first_ = 0, x_stop_ = 0;  // the first block start of the run's first brick, one past its last brick's
  int x_inside_end_ = 0;          // one past the run's last block start inside the grid along x
  int regular_begin_ = 0, regular_end_ = 0;  // the bricks that own one group of eight inside the grid each
  std::array<bool, kMaxBrickRun> non_inert_{};
  std::array<std::uint32_t, kMaxBrickRun> reach_{};  ///< per brick: the largest reach its blocks added
  /// Per brick and straddle flags s (kBrickCodes), the OR of the changed bytes inside the grid of
  /// the blocks with those flags.
  std::array<std::array<std::uint64_t, 8>, kMaxBrickRun> changed_{};
};

/// True when brick `b` (at `at`) may skip the pass: all its blocks were quiet at this offset in a
/// pass after which no cell of its footprint changed (BrickRecord).
inline bool may_skip(const BrickRecord& r, std::uint32_t b, Int3 at, int offset) {
  const std::uint32_t quiet = r.quiet_pass[std::size_t(b) * 8 + std::size_t(offset)];
  if (quiet == 0) return false;
  for (int dz = 0; dz <= (at.z > 0 ? 1 : 0); ++dz)
    for (int dy = 0; dy <= (at.y > 0 ? 1 : 0); ++dy)
      for (int dx = 0; dx <= (at.x > 0 ? 1 : 0); ++dx) {
        const std::uint32_t n = brick_index(r.bricks, at.x - dx, at.y - dy, at.z - dz);
        if (std::atomic_ref<std::uint32_t>(r.changed_pass[n]).load(std::memory_order_relaxed) > quiet) return false;
      }
  return true;
}

/// True when `rule` leaves brick `b` (at `at`) out of its sub-step: the brick is dirty already and
/// idle (brick_reach.hpp).
template <class Rule>
inline bool leaves_out(const Rule& rule, const BrickRecord& r, std::uint32_t b, Int3 at) {
  if constexpr (!Rule::kReach) {
    return false;
  } else {
    if (!rule.may_idle() || r.dirty[b] == 0) return false;
    for (int n = 0; n < kReachNeighbours; ++n) {
      std::uint32_t neighbour = 0;
      if (reach_neighbour(r.bricks, at, n, neighbour) &&
          !rule.idle(std::atomic_ref<std::uint8_t>(r.reach[neighbour]).load(std::memory_order_relaxed)))
        return false;
    }
    return true;
  }
}

template <class Rule>
void step_run(const StepContext& c, const Rule& rule, const BrickRecord& record, std::uint32_t first, int length) {
  const int offset = offset_index(rule.offset);
  const Int3 at = brick_coords(record.bricks, first);
  std::array<bool, kMaxBrickRun> skip{};
  for (int i = 0; i < length; ++i) {
    const Int3 brick{at.x + i, at.y, at.z};
    skip[std::size_t(i)] = may_skip(record, first + std::uint32_t(i), brick, offset) ||
                           leaves_out(rule, record, first + std::uint32_t(i), brick);
  }
  // The other bricks, stepped in runs of consecutive ones.
  for (int i = 0; i < length;) {
    if (skip[std::size_t(i)]) {
      ++i;
      continue;
    }
    int j = i + 1;
    while (j < length && !skip[std::size_t(j)]) ++j;
    RunStepper<Rule> stepper(c, rule, record, first + std::uint32_t(i), j - i);
    stepper.step();
    stepper.finish();
    i = j;
  }
}

}  // namespace

void step_brick_run(const StepContext& context, const BrickRecord& record, std::uint32_t first_brick, int length) {
  cpu_ops::with_host_rule(context, [&](const auto& rule) { step_run(context, rule, record, first_brick, length); });
}

}  // namespace granular
