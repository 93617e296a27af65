#include "plain_step.hpp"

#include <cstddef>
#include <thread>
#include <vector>

#include "granular/material.hpp"

namespace granular::reference {

namespace {

constexpr std::uint8_t kVoidCell = to_cell(Material::Void);
constexpr std::uint8_t kGrainCell = to_cell(Material::Granular);
/// What a cell outside the grid reads as.
constexpr std::uint8_t kOutsideCell = to_cell(Material::Solid);

/// The motion model's table codes (what its transition table is indexed by, 3 bits per cell).
constexpr std::uint8_t kCodeVoid = 0, kCodeObstacle = 1, kCodeGrain = 2, kCodeRoller = 3;

/// One block of one pass: its lowest corner, the sub-step (0 for a one-step rule set) and the
/// tick it belongs to.
struct BlockAt {
  int x0, y0, z0;
  std::uint64_t tick;
  int substep;
};

/// The 8 cells of a block gathered from the grid, with where each lives; outside cells read as solid.
struct Gathered {
  BlockCells cells{};
  std::size_t at[8] = {};
  bool inside[8] = {};
};

Gathered gather(std::span<const std::uint8_t> grid, Int3 n, const BlockAt& b) {
  Gathered g;
  for (int i = 0; i < 8; ++i) {
    const int x = b.x0 + (i & 1), y = b.y0 + ((i >> 1) & 1), z = b.z0 + ((i >> 2) & 1);
    g.inside[i] = x >= 0 && y >= 0 && z >= 0 && x < n.x && y < n.y && z < n.z;
    g.at[i] = g.inside[i] ? std::size_t(x) + std::size_t(n.x) * (std::size_t(y) + std::size_t(n.y) * std::size_t(z)) : 0;
    g.cells[i] = g.inside[i] ? grid[g.at[i]] : kOutsideCell;
  }
  return g;
}

void scatter(std::span<std::uint8_t> grid, const Gathered& g, const BlockCells& out) {
  for (int i = 0; i < 8; ++i)
    if (g.inside[i]) grid[g.at[i]] = out[i];
}

/// The block after a one-step rule set's tick: the transition of its key, or, under a random
/// symmetry s, the transition of the key seen through s (cell i at map[i]), mapped back.
BlockCells one_step_block(const PlainRules& r, const BlockCells& cells, const BlockAt& b) {
  if (!r.random_symmetry) return apply_transition(cells, (*r.lut)[encode_key(cells)]);
  const auto map = horizontal_symmetry(int(block_random(r.seed, b.tick, b.x0, b.y0, b.z0) & 7u));
  BlockCells viewed{};
  for (int i = 0; i < 8; ++i) viewed[map[i]] = cells[i];
  const BlockCells after = apply_transition(viewed, (*r.lut)[encode_key(viewed)]);
  BlockCells out{};
  for (int i = 0; i < 8; ++i) out[i] = after[map[i]];
  return out;
}

/// A top-layer cell i has only void beside it in the top layer.
bool alone_in_top_layer(const BlockCells& cells, int i) {
  for (int j = 4; j < 8; ++j)
    if (j != i && (cells[j] & kMaterialMask) != kVoidCell) return false;
  return true;
}

/// The block after one sub-step of the motion model (motion.hpp, motion_block.hpp).
BlockCells motion_block(const PlainRules& r, BlockCells cells, const BlockAt& b) {
  const int s = b.substep;
  // Sub-step 0: every grain notes its layer as its phase (top: 0, bottom: the phase bit).
  if (s == 0)
    for (int i = 0; i < 8; ++i)
      if ((cells[i] & kMaterialMask) == kGrainCell)
        cells[i] = std::uint8_t((cells[i] & ~kMotionPhaseBit) | (i < 4 ? kMotionPhaseBit : 0));
  const std::uint64_t random =
      block_random(r.seed, b.tick * std::uint64_t(r.substeps) + std::uint64_t(s), b.x0, b.y0, b.z0);
  // The level draw of top cell i (out of 256, in steps of 4) and its roll draw.
  auto level_draw = [&](int i) { return int((random >> (40 + 6 * (i - 4))) & 63u) * 4; };
  auto roll_draw = [&](int i) { return int((random >> (8 * (i - 3))) & 0xFFu); };

  BlockCells code{};
  bool moving[8] = {};
  bool any_moving = false;
  for (int i = 0; i < 8; ++i) {
    const std::uint8_t material = cells[i] & kMaterialMask;
    if (material == kVoidCell) {
      code[i] = kCodeVoid;
    } else if (material != kGrainCell) {
      code[i] = kCodeObstacle;
    } else if (i < 4) {
      code[i] = kCodeGrain;  // a bottom-layer grain never moves on its own
    } else {
      const int level = cell_motion(cells[i]);
      const int window_start = (cells[i] & kMotionPhaseBit) ? 1 : 0;
      const bool in_window = s >= window_start && s < window_start + motion_window(level);
      if (!in_window) {
        code[i] = kCodeObstacle;  // too slow to move in this sub-step
      } else {
        moving[i] = any_moving = true;
        code[i] = level > 0 && roll_draw(i) < r.roll_chance ? kCodeRoller : kCodeGrain;
      }
    }
  }
  if (!any_moving) return cells;

  const auto map = horizontal_symmetry(r.random_symmetry ? int(random & 7u) : 0);
  BlockCells viewed{};
  for (int i = 0; i < 8; ++i) viewed[map[i]] = code[i];
  const Transition t = (*r.lut)[encode_key(viewed)];
  int destination_of[8] = {};
  for (int i = 0; i < 8; ++i) {
    const int viewed_destination = destination(t, map[i]);
    for (int j = 0; j < 8; ++j)
      if (map[j] == viewed_destination) destination_of[i] = j;
  }

  const int max_level = MotionParams{.substeps = r.substeps}.max_level();
  BlockCells out{};
  for (int i = 0; i < 8; ++i) {
    std::uint8_t cell = cells[i];
    const int to = destination_of[i];
    if (moving[i]) {
      int level = cell_motion(cell);
      const std::uint8_t phase = cell & kMotionPhaseBit;
      if (to < 4) {
        const bool straight_down = (to & 3) == (i & 3);
        if (straight_down) {
          if (s == (phase ? 1 : 0) && alone_in_top_layer(cells, i)) ++level;
        } else if (level_draw(i) < r.topple_gain) {
          ++level;
        }
        if (level > max_level) level = max_level;
      } else if (level > 0 && level_draw(i) < (to != i ? r.roll_cost : kPlainStuckCost)) {
        --level;
      }
      cell = std::uint8_t(kGrainCell | (level << kMotionShift) | phase);
    }
    out[to] = cell;
  }
  return out;
}

/// The partition offset of sub-step `substep` of `tick` with the motion model: z flips every
/// sub-step and x, y follow tick + substep as the one-step cycle follows the tick.
BlockOffset motion_pass_offset(const PlainRules& r, std::uint64_t tick, int substep) {
  const std::uint64_t phase = tick + std::uint64_t(substep);
  BlockOffset o{int((phase >> 1) & 1u), int((phase >> 2) & 1u), substep & 1};
  if (r.random_axis_order && cycle_swaps_axes(r.seed, tick)) {
    const int x = o.x;
    o.x = o.y;
    o.y = x;
  }
  return o;
}

/// The deterministic one-step rules on a block inside the grid: gather the 8 bytes, key,
/// transition, scatter by the permutation.
void paper_interior_block(std::uint8_t* base, std::size_t sy, std::size_t sz, const Lut& lut) {
  std::uint8_t* const cell[8] = {base,      base + 1,      base + sy,      base + sy + 1,
                                 base + sz, base + sz + 1, base + sz + sy, base + sz + sy + 1};
  BlockCells b{};
  for (int i = 0; i < 8; ++i) b[i] = *cell[i];
  const Transition t = lut[encode_key(b)];
  for (int i = 0; i < 8; ++i) *cell[destination(t, i)] = b[i];
}

/// Every block of one layer of one pass.
void plain_layer(std::span<std::uint8_t> grid, Int3 n, const PlainRules& r, BlockOffset o, std::uint64_t tick,
                 int substep, int layer) {
  const int z0 = 2 * layer - o.z;
  const std::size_t sy = std::size_t(n.x), sz = sy * std::size_t(n.y);
  const bool plain_rule = !r.motion() && !r.random_symmetry;
  for (int by = 0; by < block_count(n.y, o.y); ++by) {
    const int y0 = 2 * by - o.y;
    for (int bx = 0; bx < block_count(n.x, o.x); ++bx) {
      const int x0 = 2 * bx - o.x;
      const bool interior = x0 >= 0 && y0 >= 0 && z0 >= 0 && x0 + 1 < n.x && y0 + 1 < n.y && z0 + 1 < n.z;
      if (plain_rule && interior) {
        paper_interior_block(grid.data() + std::size_t(x0) + sy * std::size_t(y0) + sz * std::size_t(z0), sy, sz, *r.lut);
        continue;
      }
      const BlockAt at{x0, y0, z0, tick, substep};
      const Gathered g = gather(grid, n, at);
      scatter(grid, g, r.motion() ? motion_block(r, g.cells, at) : one_step_block(r, g.cells, at));
    }
  }
}

/// One pass (a tick, or a sub-step of one) over every layer, split over `threads` threads.
void plain_pass(std::span<std::uint8_t> grid, Int3 n, const PlainRules& r, BlockOffset o, std::uint64_t tick,
                int substep, int threads) {
  const int layers = block_count(n.z, o.z);
  if (threads <= 1) {
    for (int layer = 0; layer < layers; ++layer) plain_layer(grid, n, r, o, tick, substep, layer);
    return;
  }
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([=, &r] {
      for (int layer = layers * t / threads; layer < layers * (t + 1) / threads; ++layer)
        plain_layer(grid, n, r, o, tick, substep, layer);
    });
  for (auto& th : pool) th.join();
}

}  // namespace

PlainRules plain_rules(const RuleSet& rules, const Lut& lut, std::uint64_t seed) {
  PlainRules plain;
  plain.lut = &lut;
  plain.random_symmetry = rules.random_symmetry;
  plain.random_axis_order = rules.random_axis_order;
  plain.substeps = rules.motion.substeps;
  // The plain loop knows one grain, the shipped tables' granular state.
  const GrainMotion& grain = rules.materials[to_cell(Material::Granular)].grain;
  plain.topple_gain = grain.topple_gain;
  plain.roll_cost = grain.roll_cost;
  plain.roll_chance = grain.roll_chance;
  plain.seed = seed;
  return plain;
}

void plain_step(std::span<std::uint8_t> cells, Int3 size, const PlainRules& rules, std::uint64_t tick, int threads) {
  if (!rules.motion()) {
    plain_pass(cells, size, rules, block_offset(tick, rules.seed, rules.random_axis_order), tick, 0, threads);
    return;
  }
  for (int s = 0; s < rules.substeps; ++s)
    plain_pass(cells, size, rules, motion_pass_offset(rules, tick, s), tick, s, threads);
}

void plain_run(std::span<std::uint8_t> cells, Int3 size, const PlainRules& rules, std::uint64_t first_tick, int ticks,
               int threads) {
  for (int t = 0; t < ticks; ++t) plain_step(cells, size, rules, first_tick + std::uint64_t(t), threads);
}

}  // namespace granular::reference
