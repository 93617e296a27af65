#include "plain_step.hpp"

#include <array>
#include <algorithm>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "granular/material.hpp"

namespace granular::reference {

namespace {

/// What a cell outside the grid reads as.
constexpr std::uint8_t kOutsideCell = to_cell(Material::Solid);

/// The gravity-and-flow table codes (what the motion model's transition table is indexed by, 3 bits
/// per cell; without a motion model the Lut is asked for PlainRules::code_state of them).
constexpr std::uint8_t kCodeVoid = 0, kCodeObstacle = 1, kCodeGrain = 2, kCodeRoller = 3;

/// The motion level bits of a cell byte.
constexpr std::uint8_t kLevelBits = std::uint8_t(kMotionLevelMask << kMotionShift);

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
  BlockCells side{};  ///< the cells' side bytes (momentum; 0 outside the grid or without a side plane)
  std::size_t at[8] = {};
  bool inside[8] = {};
};

Gathered gather(std::span<const std::uint8_t> grid, Int3 n, const BlockAt& b, std::span<const std::uint8_t> side = {}) {
  Gathered g;
  for (int i = 0; i < 8; ++i) {
    const int x = b.x0 + (i & 1), y = b.y0 + ((i >> 1) & 1), z = b.z0 + ((i >> 2) & 1);
    g.inside[i] = x >= 0 && y >= 0 && z >= 0 && x < n.x && y < n.y && z < n.z;
    g.at[i] = g.inside[i] ? std::size_t(x) + std::size_t(n.x) * (std::size_t(y) + std::size_t(n.y) * std::size_t(z)) : 0;
    g.cells[i] = g.inside[i] ? grid[g.at[i]] : kOutsideCell;
    g.side[i] = g.inside[i] && !side.empty() ? side[g.at[i]] : 0;
  }
  return g;
}

void scatter(std::span<std::uint8_t> grid, const Gathered& g, const BlockCells& out) {
  for (int i = 0; i < 8; ++i)
    if (g.inside[i]) grid[g.at[i]] = out[i];
}

/// How the rules treat the material of a cell byte.
Behaviour behaviour_of(const PlainRules& r, std::uint8_t cell) { return r.materials[cell & kMaterialMask].behaviour; }

/// True when the cell's material is a void or a gas.
bool void_or_gas(const PlainRules& r, std::uint8_t cell) {
  const Behaviour b = behaviour_of(r, cell);
  return b == Behaviour::Void || b == Behaviour::Gas;
}

/// True when the cell is a liquid at motion level 0: a liquid that may be part of a body at rest.
bool resting_liquid(const PlainRules& r, std::uint8_t cell) {
  return behaviour_of(r, cell) == Behaviour::Liquid && cell_motion(cell) == 0;
}

/// True when a liquid whose head stands `excess` units above a cell's top pushes into it in sub-step
/// `substep`: while substep < k sqrt(excess / kPlainHeadUnit), k = 4 for a push up or down and 6 for
/// one sideways, compared squared in integers.
bool pushes_in(std::int32_t excess, int substep, bool vertical) {
  const std::int64_t k = vertical ? 4 : 6;
  return std::int64_t(substep) * substep * kPlainHeadUnit < k * k * std::int64_t(excess);
}

/// The motion level of a liquid pushed or fallen down out of its body under a head `excess` units
/// above the top of the cell it enters: floor(sqrt(excess / kPlainHeadUnit)) (at most 64) + 1, at
/// most `max_level`.
int pushed_out_level(std::int32_t excess, int max_level) {
  int root = 0;
  while (root < 64 && std::int64_t(root + 1) * (root + 1) * kPlainHeadUnit <= std::int64_t(excess)) ++root;
  return std::min(root + 1, max_level);
}

/// A velocity component of a side byte: axis 0 (x) from bits 0..3, axis 1 (y) from bits 4..7, each
/// a signed nibble.
int side_component(std::uint8_t side, int axis) {
  const int v = (side >> (4 * axis)) & 15;
  return v >= 8 ? v - 16 : v;
}

/// The side byte of velocity (x, y), each clamped to -kPlainTopSpeed .. kPlainTopSpeed.
std::uint8_t side_byte(int x, int y) {
  x = std::clamp(x, -kPlainTopSpeed, kPlainTopSpeed);
  y = std::clamp(y, -kPlainTopSpeed, kPlainTopSpeed);
  return std::uint8_t((x & 15) | ((y & 15) << 4));
}

/// `side` with its component along `axis` set to `v` (clamped).
std::uint8_t with_side_component(std::uint8_t side, int axis, int v) {
  return axis == 0 ? side_byte(v, side_component(side, 1)) : side_byte(side_component(side, 0), v);
}

/// The speed of `cells_per_tick` cells a tick: 7 is 3 substeps / 4 cells a tick (momentum's
/// schedule meets an x or y neighbour in about 3 of 4 sub-steps); rounded, at most 7.
int speed_of_cells(int cells_per_tick, int substeps) {
  const double speed = double(kPlainTopSpeed) * cells_per_tick / (3 * substeps / 4);
  return std::min(kPlainTopSpeed, int(speed + 0.5));
}

/// The coarse grid of a grid of `n` cells: one coarse cell per 2 x 2 x 2 cells, cut at the far faces.
Int3 coarse_extent(Int3 n) { return {(n.x + 1) / 2, (n.y + 1) / 2, (n.z + 1) / 2}; }

/// The heads of a block's cells by block position: each the head of its coarse cell in `heads`
/// (plain_heads of a grid of `n`), kPlainDry outside the grid.
std::array<std::int32_t, 8> heads_of_block(const std::vector<std::int32_t>& heads, Int3 n, const Gathered& g,
                                           const BlockAt& b) {
  const Int3 c = coarse_extent(n);
  std::array<std::int32_t, 8> out{};
  for (int i = 0; i < 8; ++i) {
    const int x = b.x0 + (i & 1), y = b.y0 + ((i >> 1) & 1), z = b.z0 + ((i >> 2) & 1);
    if (!g.inside[i]) {
      out[std::size_t(i)] = kPlainDry;
      continue;
    }
    const std::size_t x2 = std::size_t(x / 2), y2 = std::size_t(y / 2), z2 = std::size_t(z / 2);
    out[std::size_t(i)] = heads[x2 + std::size_t(c.x) * (y2 + std::size_t(c.y) * z2)];
  }
  return out;
}

/// True when the cell's material falls as a grain: granular or liquid.
bool is_faller(const PlainRules& r, std::uint8_t cell) {
  const Behaviour b = behaviour_of(r, cell);
  return b == Behaviour::Granular || b == Behaviour::Liquid;
}

/// The gravity-and-flow code of a cell: a liquid falls and topples as a grain, a gas is void to it.
std::uint8_t flow_code(const PlainRules& r, std::uint8_t cell) {
  switch (behaviour_of(r, cell)) {
    case Behaviour::Void:
    case Behaviour::Gas: return kCodeVoid;
    case Behaviour::Granular:
    case Behaviour::Liquid: return kCodeGrain;
    default: return kCodeObstacle;
  }
}

/// The block viewed under symmetry s: viewed[map[i]] = cells[i].
BlockCells view(const BlockCells& cells, int s) {
  const auto map = horizontal_symmetry(s);
  BlockCells viewed{};
  for (int i = 0; i < 8; ++i) viewed[map[i]] = cells[i];
  return viewed;
}

/// The block frame of a viewed block (the inverse of view).
BlockCells unview(const BlockCells& viewed, int s) {
  const auto map = horizontal_symmetry(s);
  BlockCells cells{};
  for (int i = 0; i < 8; ++i) cells[i] = viewed[map[i]];
  return cells;
}

/// True when a block holds a liquid or a gas.
bool holds_fluid_material(const PlainRules& r, const BlockCells& cells) {
  for (const std::uint8_t c : cells) {
    const Behaviour b = behaviour_of(r, c);
    if (b == Behaviour::Liquid || b == Behaviour::Gas) return true;
  }
  return false;
}

/// The one-step rules' fluid pass after gravity and flow: every cell takes part, every chance above
/// 0 is certain (all draws 0), no cell carries a motion level. A block of void, static and granular
/// cells alone is left as it is: without levels two granular materials never pass each other,
/// gravity has already dropped every grain that stood on void, and a topple through a fluid (1b)
/// needs one other than void, so the pass has nothing to move (the random scenes of test_plain_step
/// check this against the table too).
BlockCells one_step_fluid(const PlainRules& r, const BlockCells& flowed, int s) {
  if (!holds_fluid_material(r, flowed)) return flowed;
  std::array<bool, 8> everyone{};
  everyone.fill(true);
  return plain_fluid_pass(r, flowed, everyone, s, 0, false);
}

/// The block after a one-step rule set's tick: in the block's frame (its random symmetry s, or the
/// identity), gravity and flow by the Lut's transition of the block's codes, then the fluid pass.
BlockCells one_step_block(const PlainRules& r, const BlockCells& cells, const BlockAt& b) {
  const int s = r.random_symmetry ? int(block_random(r.seed, b.tick, b.x0, b.y0, b.z0) & 7u) : 0;
  const BlockCells viewed = view(cells, s);
  BlockCells asked{};
  for (int i = 0; i < 8; ++i) asked[i] = r.code_state[flow_code(r, viewed[i])];
  const BlockCells flowed = unview(apply_transition(viewed, (*r.lut)[encode_key(asked)]), s);
  return one_step_fluid(r, flowed, s);
}

/// Trains: a granular grain whose level bits are all set is carried (moved by the trains pass, a
/// solid to the block step).
bool plain_carried(const PlainRules& r, std::uint8_t cell) {
  return behaviour_of(r, cell) == Behaviour::Granular && cell_motion(cell) == kMotionLevelMask;
}

/// Trains: a void whose level bits are all set is swept (a carried train falls through it in the tick).
bool plain_swept(const PlainRules& r, std::uint8_t cell) {
  return behaviour_of(r, cell) == Behaviour::Void && cell_motion(cell) == kMotionLevelMask;
}

/// A top-layer cell i has only void beside it in the top layer (a gas is void to the first pass).
bool alone_in_top_layer(const PlainRules& r, const BlockCells& cells, int i) {
  for (int j = 4; j < 8; ++j)
    if (j != i && flow_code(r, cells[j]) != kCodeVoid) return false;
  return true;
}

/// The block after one sub-step of the motion model (motion.hpp, motion_block.hpp), then the fluid
/// pass (fluid_block.hpp); under pressure `heads` holds the head of each cell by block position
/// (heads_of_block), else it is null; under momentum `side` holds the cells' side bytes, which the
/// sub-step moves and updates with them, else it is null.
BlockCells motion_block(const PlainRules& r, BlockCells cells, const BlockAt& b,
                        const std::array<std::int32_t, 8>* heads, BlockCells* side = nullptr,
                        const std::array<bool, 8>& carried = {}) {
  const int s = b.substep;
  // Columns: a wake (a void with the wake bit) under a faller makes it a follower at the wake's level
  // if that is higher; every wake is cleared.
  bool follower[8] = {};
  if (r.columns)
    for (int i = 0; i < 4; ++i) {
      if ((cells[i] & kMaterialMask) != 0 || (cells[i] & kWakeBit) == 0) continue;
      const int wake_level = cell_motion(cells[i]);
      cells[i] = 0;
      if (!is_faller(r, cells[i + 4])) continue;
      follower[i + 4] = true;
      if (cell_motion(cells[i + 4]) < wake_level)
        cells[i + 4] = std::uint8_t((cells[i + 4] & ~(kMotionLevelMask << kMotionShift)) | (wake_level << kMotionShift));
    }
  // Sub-step 0: every faller notes its layer as its phase (top: 0, bottom: the phase bit).
  if (s == 0)
    for (int i = 0; i < 8; ++i)
      if (is_faller(r, cells[i]))
        cells[i] = std::uint8_t((cells[i] & ~kMotionPhaseBit) | (i < 4 ? kMotionPhaseBit : 0));
  const std::uint64_t step = b.tick * std::uint64_t(r.substeps) + std::uint64_t(s);
  const std::uint64_t random = block_random(r.seed, step, b.x0, b.y0, b.z0);
  // The level draw of top cell i (out of 256, in steps of 4) and its roll draw.
  auto level_draw = [&](int i) { return int((random >> (40 + 6 * (i - 4))) & 63u) * 4; };
  auto roll_draw = [&](int i) { return int((random >> (8 * (i - 3))) & 0xFFu); };

  // Who takes part: top-layer fallers inside their window (moving), and in sub-steps 0 and 1 the
  // bottom-layer gases (gas_turn).
  BlockCells code{};
  bool moving[8] = {}, gas_turn[8] = {};
  bool any_moving = false, any_gas_turn = false;
  for (int i = 0; i < 8; ++i) {
    code[i] = flow_code(r, cells[i]);
    if (i < 4) {
      // A bottom-layer faller never moves on its own; a bottom-layer gas takes part in sub-steps 0, 1.
      if (s < 2 && behaviour_of(r, cells[i]) == Behaviour::Gas) gas_turn[i] = any_gas_turn = true;
      continue;
    }
    if (code[i] != kCodeGrain) continue;
    const int level = cell_motion(cells[i]);
    const int window_start = (cells[i] & kMotionPhaseBit) ? 1 : 0;
    bool in_window = (s >= window_start && s < window_start + motion_window(level)) || follower[i];
    // Trains: a moving grain (level 1 or more) right above a grain at its level or faster waits for it.
    if (r.trains && level >= 1 && behaviour_of(r, cells[i]) == Behaviour::Granular &&
        behaviour_of(r, cells[i - 4]) == Behaviour::Granular && cell_motion(cells[i - 4]) >= level)
      in_window = false;
    if (!in_window) {
      code[i] = kCodeObstacle;  // too slow to move in this sub-step
    } else {
      moving[i] = any_moving = true;
      if (level > 0 && roll_draw(i) < r.materials[cells[i] & kMaterialMask].roll_chance) code[i] = kCodeRoller;
    }
  }
  // Under pressure every liquid at rest takes part too: it may start a pressure move in every sub-step.
  bool at_rest_liquid[8] = {};
  bool any_at_rest_liquid = false;
  if (heads != nullptr)
    for (int i = 0; i < 8; ++i)
      if (resting_liquid(r, cells[i])) at_rest_liquid[i] = any_at_rest_liquid = true;
  // Under momentum a liquid with a velocity takes part too: it glides.
  bool any_glider = false;
  if (side != nullptr)
    for (int i = 0; i < 8; ++i)
      any_glider = any_glider || (behaviour_of(r, cells[i]) == Behaviour::Liquid && (*side)[i] != 0);
  if (!any_moving && !any_gas_turn && !any_at_rest_liquid && !any_glider) return cells;  // its wakes cleared

  const int symmetry = r.random_symmetry ? int(random & 7u) : 0;
  const auto map = horizontal_symmetry(symmetry);
  int destination_of[8] = {0, 1, 2, 3, 4, 5, 6, 7};
  if (any_moving) {
    BlockCells viewed{};
    for (int i = 0; i < 8; ++i) viewed[map[i]] = code[i];
    const Transition t = (*r.lut)[encode_key(viewed)];
    for (int i = 0; i < 8; ++i) {
      const int viewed_destination = destination(t, map[i]);
      for (int j = 0; j < 8; ++j)
        if (map[j] == viewed_destination) destination_of[i] = j;
    }
  }

  const int max_level = MotionParams{.substeps = r.substeps}.max_level();
  auto fell_straight = [&](int j) { return destination_of[j] < 4 && (destination_of[j] & 3) == (j & 3); };
  // Entrainment: did a moving grain roll (to another top cell) or topple (down into another column)?
  bool flowed = false;
  for (int i = 4; i < 8; ++i) {
    const int to = destination_of[i];
    const bool rolled = to >= 4 && to != i, toppled = to < 4 && (to & 3) != (i & 3);
    if (moving[i] && cell_motion(cells[i]) > 0 && (rolled || toppled)) flowed = true;
  }
  BlockCells out{}, side_out{};
  std::array<std::uint8_t, 8> wake_left{};  // per top cell: the wake it leaves (0: none)
  std::array<bool, 8> mover{};  // who may start a move in the fluid pass: took part and stayed
  for (int i = 0; i < 8; ++i) {
    std::uint8_t cell = cells[i];
    const int to = destination_of[i];
    if (side != nullptr) side_out[to] = (*side)[i];
    if (moving[i]) {
      const PlainMaterial& mat = r.materials[cell & kMaterialMask];
      int level = cell_motion(cell);
      // Under momentum a liquid that rolls or topples runs on along its move at its level's speed.
      if (side != nullptr && mat.behaviour == Behaviour::Liquid && to != i && !fell_straight(i)) {
        const int speed = std::max(1, speed_of_cells(level > 0 ? motion_window(level) : 1, r.substeps));
        std::uint8_t v = side_out[to];
        for (int axis = 0; axis < 2; ++axis)
          if (((to ^ i) >> axis) & 1) v = with_side_component(v, axis, ((to >> axis) & 1) != 0 ? speed : -speed);
        side_out[to] = v;
      }
      const std::uint8_t phase = cell & kMotionPhaseBit;
      if (to < 4) {
        const bool straight_down = (to & 3) == (i & 3);
        if (straight_down) {
          // Gravity accelerates a grain in free fall: under columns every one that fell, else one alone
          // in the top layer.
          if (s == (phase ? 1 : 0) && (r.columns || alone_in_top_layer(r, cells, i))) ++level;
        } else if (level_draw(i) < mat.topple_gain) {
          ++level;
        }
        if (level > max_level) level = max_level;
      } else if (level > 0 && level_draw(i) < (to != i ? mat.roll_cost : kPlainStuckCost)) {
        --level;
      }
      // A grain that rolled or toppled keeps at most its material's flow level (0: no limit), unless
      // under columns the grain under it in the block is granular and falls at level 2 or faster: then
      // it slips past it inside a falling body.
      const bool rolled_or_toppled = to != i && !fell_straight(i);
      const bool in_falling_body = r.columns && (carried[i - 4] || (behaviour_of(r, cells[i - 4]) == Behaviour::Granular &&
                                                                    cell_motion(cells[i - 4]) >= kPlainFallingBodyLevel));
      if (rolled_or_toppled && !in_falling_body && mat.flow_level > 0 && level > mat.flow_level) level = mat.flow_level;
      // Under pressure a liquid that rolled or toppled joins its body at rest; one that fell straight
      // down from a coarse cell inside a body into one outside any leaves at least at the speed the
      // head of its own coarse cell gives above the top of the cell it fell into.
      if (heads != nullptr && mat.behaviour == Behaviour::Liquid) {
        const std::int32_t own = (*heads)[std::size_t(i)], below = (*heads)[std::size_t(i - 4)];
        if (rolled_or_toppled) level = 0;
        if (fell_straight(i) && !plain_outside_body(own) && plain_outside_body(below))
          level = std::max(level, pushed_out_level(own - (b.z0 + 1) * kPlainHeadUnit, max_level));
      }
      cell = std::uint8_t((cell & kMaterialMask) | (level << kMotionShift) | phase);
      if (r.columns && fell_straight(i)) wake_left[i] = std::uint8_t(kWakeBit | (level << kMotionShift));
    }
    out[to] = cell;
    if (to == i && (moving[i] || gas_turn[i])) mover[i] = true;
  }
  // After a roll or topple of a moving grain, a faller at rest that kept its top cell, with a void
  // top cell beside it over a cell that is not void, starts moving (level 1) with chance entrain / 256.
  if (flowed)
    for (int i = 4; i < 8; ++i) {
      if (destination_of[i] != i || !is_faller(r, out[i]) || cell_motion(out[i]) != 0) continue;
      bool edge = false;
      for (int j = 4; j < 8; ++j)
        if (j != i && flow_code(r, out[j]) == kCodeVoid && flow_code(r, out[j - 4]) != kCodeVoid) edge = true;
      if (edge && level_draw(i) < r.materials[out[i] & kMaterialMask].entrain)
        out[i] = std::uint8_t(out[i] | (1 << kMotionShift));
    }
  const std::uint64_t draws = block_random(r.seed ^ kPlainFluidDrawSalt, step, b.x0, b.y0, b.z0);
  // The pressure stage's movers: the liquids at rest that kept their place in the first pass.
  PlainPressure pressure;
  if (heads != nullptr) {
    pressure.heads = *heads;
    for (int i = 0; i < 8; ++i) pressure.movers[std::size_t(i)] = at_rest_liquid[i] && destination_of[i] == i;
    pressure.z0 = b.z0;
    pressure.substep = s;
    pressure.max_level = max_level;
  }
  PlainMomentum momentum;
  if (side != nullptr) {
    momentum.side = side_out;
    for (int i = 0; i < 8; ++i)
      momentum.gliders[std::size_t(i)] =
          destination_of[i] == i && behaviour_of(r, out[i]) == Behaviour::Liquid && side_out[i] != 0;
    momentum.substep = s;
    momentum.substeps = r.substeps;
  }
  BlockCells after = plain_fluid_pass(r, out, mover, symmetry, draws, true, heads != nullptr ? &pressure : nullptr,
                                      side != nullptr ? &momentum : nullptr);
  if (side != nullptr) *side = momentum.side;
  for (int i = 4; i < 8; ++i)
    if (wake_left[i] != 0 && after[i] == 0) after[i] = wake_left[i];
  return after;
}

/// The partition offset of sub-step `substep` of `tick` with the motion model: z flips every
/// sub-step and x, y follow tick + substep as the one-step cycle follows the tick. Under momentum,
/// from sub-step 2 on, x and y are instead chosen sub-step by sub-step: of the (x, y) not yet taken
/// with the same z since the last multiple of 8, the first in the order (0,0), (0,1), (1,0), (1,1)
/// that keeps the fewest of the last sub-step's x and y.
BlockOffset motion_pass_offset(const PlainRules& r, std::uint64_t tick, int substep) {
  const std::uint64_t phase = tick + std::uint64_t(substep);
  BlockOffset o{int((phase >> 1) & 1u), int((phase >> 2) & 1u), substep & 1};
  if (r.momentum && substep >= 2) {
    std::vector<std::pair<int, int>> xy;  // (x, y) of sub-steps 0 .. substep
    for (int s = 0; s < 2; ++s) xy.emplace_back(int(((tick + s) / 2) % 2), int(((tick + s) / 4) % 2));
    for (int s = 2; s <= substep; ++s) {
      const std::pair<int, int> last = xy.back();
      int best_kept = 99;
      std::pair<int, int> best{};
      for (const std::pair<int, int> c : {std::pair{0, 0}, std::pair{0, 1}, std::pair{1, 0}, std::pair{1, 1}}) {
        bool taken = false;
        for (int u = s - s % 8; u < s; ++u) taken = taken || (u % 2 == s % 2 && xy[std::size_t(u)] == c);
        const int kept = int(c.first == last.first) + int(c.second == last.second);
        if (!taken && kept < best_kept) {
          best_kept = kept;
          best = c;
        }
      }
      xy.push_back(best);
    }
    o.x = xy.back().first;
    o.y = xy.back().second;
  }
  if (r.random_axis_order && cycle_swaps_axes(r.seed, tick)) {
    const int x = o.x;
    o.x = o.y;
    o.y = x;
  }
  return o;
}

/// The deterministic one-step rules on a block inside the grid: gather the 8 bytes, key of their
/// codes, transition, scatter by the permutation, and the fluid pass when the block holds a fluid.
void paper_interior_block(std::uint8_t* base, std::size_t sy, std::size_t sz, const PlainRules& r) {
  std::uint8_t* const cell[8] = {base,      base + 1,      base + sy,      base + sy + 1,
                                 base + sz, base + sz + 1, base + sz + sy, base + sz + sy + 1};
  BlockCells b{}, asked{};
  for (int i = 0; i < 8; ++i) {
    b[i] = *cell[i];
    asked[i] = r.code_state[flow_code(r, b[i])];
  }
  const BlockCells out = one_step_fluid(r, apply_transition(b, (*r.lut)[encode_key(asked)]), 0);
  for (int i = 0; i < 8; ++i) *cell[i] = out[i];
}

/// Every block of one layer of one pass; `heads` is the tick's head field (plain_heads) under
/// pressure, else null; `side` the side plane under momentum, else empty.
void plain_layer(std::span<std::uint8_t> grid, Int3 n, const PlainRules& r, BlockOffset o, std::uint64_t tick,
                 int substep, int layer, const std::vector<std::int32_t>* heads, std::span<std::uint8_t> side) {
  const int z0 = 2 * layer - o.z;
  const std::size_t sy = std::size_t(n.x), sz = sy * std::size_t(n.y);
  const bool plain_rule = !r.motion() && !r.random_symmetry;
  for (int by = 0; by < block_count(n.y, o.y); ++by) {
    const int y0 = 2 * by - o.y;
    for (int bx = 0; bx < block_count(n.x, o.x); ++bx) {
      const int x0 = 2 * bx - o.x;
      const bool interior = x0 >= 0 && y0 >= 0 && z0 >= 0 && x0 + 1 < n.x && y0 + 1 < n.y && z0 + 1 < n.z;
      if (plain_rule && interior) {
        paper_interior_block(grid.data() + std::size_t(x0) + sy * std::size_t(y0) + sz * std::size_t(z0), sy, sz, r);
        continue;
      }
      const BlockAt at{x0, y0, z0, tick, substep};
      Gathered g = gather(grid, n, at, side);
      if (!r.motion()) {
        scatter(grid, g, one_step_block(r, g.cells, at));
        continue;
      }
      std::array<std::int32_t, 8> block_heads{};
      if (heads != nullptr) block_heads = heads_of_block(*heads, n, g, at);
      // Trains: carried grains and swept voids are stepped as a solid cell and keep their bytes; a
      // grain slipping over a carried grain slips past a falling body.
      const BlockCells kept = g.cells;
      bool hidden[8] = {};
      std::array<bool, 8> carried{};
      for (int i = 0; i < 8; ++i)
        if (r.trains && (plain_carried(r, kept[i]) || plain_swept(r, kept[i]))) {
          hidden[i] = true;
          carried[std::size_t(i)] = plain_carried(r, kept[i]);
          g.cells[i] = kOutsideCell;
        }
      BlockCells out = motion_block(r, g.cells, at, heads != nullptr ? &block_heads : nullptr, side.empty() ? nullptr : &g.side,
                                    carried);
      for (int i = 0; i < 8; ++i)
        if (hidden[i]) out[i] = kept[i];
      scatter(grid, g, out);
      if (!side.empty()) scatter(side, g, g.side);
    }
  }
}

/// One pass (a tick, or a sub-step of one) over every layer, split over `threads` threads; `heads` and
/// `side` as plain_layer reads them.
void plain_pass(std::span<std::uint8_t> grid, Int3 n, const PlainRules& r, BlockOffset o, std::uint64_t tick,
                int substep, int threads, const std::vector<std::int32_t>* heads = nullptr,
                std::span<std::uint8_t> side = {}) {
  const int layers = block_count(n.z, o.z);
  if (threads <= 1) {
    for (int layer = 0; layer < layers; ++layer) plain_layer(grid, n, r, o, tick, substep, layer, heads, side);
    return;
  }
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([=, &r] {
      for (int layer = layers * t / threads; layer < layers * (t + 1) / threads; ++layer)
        plain_layer(grid, n, r, o, tick, substep, layer, heads, side);
    });
  for (auto& th : pool) th.join();
}

}  // namespace

BlockCells plain_fluid_pass(const PlainRules& r, const BlockCells& cells, const std::array<bool, 8>& mover,
                            int symmetry, std::uint64_t draws, bool levels, const PlainPressure* pressure,
                            PlainMomentum* momentum) {
  // The block in its viewed frame: position map[i] holds block cell i, with whether it may start a
  // move and the draw of block position i. moved[p]: the cell now at p has moved in this pass.
  const auto map = horizontal_symmetry(symmetry);
  std::uint8_t cell[8] = {}, side[8] = {};
  bool may_start[8] = {}, moved[8] = {}, glides[8] = {};
  int draw[8] = {}, block_position[8] = {};
  for (int i = 0; i < 8; ++i) {
    cell[map[i]] = cells[i];
    may_start[map[i]] = mover[i];
    draw[map[i]] = int((draws >> (8 * i)) & 0xFFu);
    block_position[map[i]] = i;
    if (momentum != nullptr) {
      side[map[i]] = momentum->side[std::size_t(i)];
      glides[map[i]] = momentum->gliders[std::size_t(i)];
    }
  }
  // The viewed position of block position i, and the block axis (0: x, 1: y) between two viewed
  // positions of one layer that differ along one axis.
  auto viewed = [&](int i) { return map[i]; };
  auto axis_between = [&](int p, int q) { return (block_position[p] ^ block_position[q]) == 1 ? 0 : 1; };
  auto material = [&](int p) -> const PlainMaterial& { return r.materials[cell[p] & kMaterialMask]; };
  auto is = [&](int p, Behaviour b) { return material(p).behaviour == b; };
  auto density = [&](int p) { return material(p).density; };
  auto fluid = [&](int p) { return is(p, Behaviour::Void) || is(p, Behaviour::Liquid) || is(p, Behaviour::Gas); };
  auto faller = [&](int p) { return is(p, Behaviour::Granular) || is(p, Behaviour::Liquid); };
  auto level = [&](int p) { return levels ? cell_motion(cell[p]) : 0; };
  auto starts = [&](int p) { return may_start[p] && !moved[p]; };
  auto exchange = [&](int p, int q) {
    std::swap(cell[p], cell[q]);
    std::swap(side[p], side[q]);
    moved[p] = moved[q] = true;
  };
  // The other columns of column c in order of preference: the x neighbour, the y neighbour, the diagonal.
  auto other = [](int c, int k) { return c ^ k; };

  // 1. Density: a mobile cell above a lighter mobile one changes places with it; the top cell starts
  // it as a faller taking part, the bottom one as a gas taking part.
  for (int c = 0; c < 4; ++c) {
    const int top = c + 4, bottom = c;
    if (moved[top] || moved[bottom]) continue;
    if (is(top, Behaviour::Static) || is(bottom, Behaviour::Static)) continue;
    if (density(top) <= density(bottom)) continue;
    if (is(top, Behaviour::Granular) && is(bottom, Behaviour::Granular) && level(top) == 0 && level(bottom) == 0)
      continue;
    if (!((starts(top) && faller(top)) || (starts(bottom) && is(bottom, Behaviour::Gas)))) continue;
    exchange(top, bottom);
    if (levels && faller(bottom)) cell[bottom] = std::uint8_t(cell[bottom] & ~kLevelBits);  // it sank: level 0
  }
  // 1b. A faller taking part that did not sink topples diagonally down into a bottom cell of a
  // lighter fluid under a top cell of a lighter fluid: the grains' topple through water (a void cell
  // under void is the first pass's topple). It moves through something denser than void: level 0.
  for (int c = 0; c < 4; ++c) {
    const int p = c + 4;
    if (!starts(p) || !faller(p)) continue;
    for (int k = 1; k <= 3; ++k) {
      const int q = other(c, k), over = other(c, k) + 4;
      if (moved[q]) continue;
      const bool lighter = fluid(q) && fluid(over) && density(q) < density(p) && density(over) < density(p);
      if (!lighter || (is(q, Behaviour::Void) && is(over, Behaviour::Void))) continue;
      exchange(p, q);
      if (levels) cell[q] = std::uint8_t(cell[q] & ~kLevelBits);
      break;
    }
  }
  // 2. Liquid spread: a liquid in the top layer taking part, standing on a liquid, moves sideways with
  // chance spread / 256 into a top cell of void, or while it moves into one of any lighter fluid.
  for (int c = 0; c < 4; ++c) {
    const int p = c + 4;
    if (!starts(p) || !is(p, Behaviour::Liquid) || !is(c, Behaviour::Liquid)) continue;
    if (draw[p] >= material(p).spread) continue;
    const bool moves = levels && level(p) > 0;  // never without motion levels (the one-step rules)
    for (int k = 1; k <= 3; ++k) {
      const int q = other(c, k) + 4;
      if (moved[q]) continue;
      if (is(q, Behaviour::Void) || (moves && fluid(q) && density(q) < density(p))) {
        exchange(p, q);
        // Under momentum it gains a unit along each block axis of its move.
        if (momentum != nullptr)
          for (int axis = 0; axis < 2; ++axis) {
            const int from = block_position[p], to = block_position[q];
            if ((((from ^ to) >> axis) & 1) == 0) continue;
            const int sign = ((to >> axis) & 1) != 0 ? 1 : -1, now = side_component(side[q], axis);
            side[q] = with_side_component(side[q], axis, now * sign > 0 ? now + sign : sign);
          }
        break;
      }
    }
  }
  // 3. Gas spread: a gas in the bottom layer taking part, under a gas, moves sideways into a bottom
  // cell of a denser fluid with chance spread / 256.
  auto gas_spread = [&](int c) {
    const int p = c;
    if (!starts(p) || !is(p, Behaviour::Gas) || !is(c + 4, Behaviour::Gas)) return;
    if (draw[p] >= material(p).spread) return;
    for (int k = 1; k <= 3; ++k) {
      const int q = other(c, k);
      if (moved[q]) continue;
      if (fluid(q) && density(q) > density(p)) {
        exchange(p, q);
        return;
      }
    }
  };
  // 4. Gas around a ceiling: a gas in the bottom layer taking part that cannot rise (a static cell, a
  // grain or a gas above it) moves diagonally up into a top cell of another column when that cell and
  // the one below it are denser fluids.
  auto gas_around_ceiling = [&](int c) {
    const int p = c;
    if (!starts(p) || !is(p, Behaviour::Gas)) return;
    const int above = c + 4;
    if (!(is(above, Behaviour::Static) || is(above, Behaviour::Granular) || is(above, Behaviour::Gas))) return;
    for (int k = 1; k <= 3; ++k) {
      const int q = other(c, k) + 4, under = other(c, k);
      if (moved[q]) continue;
      if (fluid(q) && density(q) > density(p) && fluid(under) && density(under) > density(p)) {
        exchange(p, q);
        return;
      }
    }
  };
  for (int c = 0; c < 4; ++c) gas_spread(c);
  for (int c = 0; c < 4; ++c) gas_around_ceiling(c);
  // 5. Pressure: each void or gas that has not moved, in the viewed order, takes the liquid beside it
  // (x, then y neighbour), below it or above it whose head stands highest above its top, among those
  // the sub-step's gate lets push.
  if (pressure != nullptr) {
    std::int32_t head[8] = {};
    bool presses[8] = {};
    for (int i = 0; i < 8; ++i) {
      head[map[i]] = pressure->heads[std::size_t(i)];
      presses[map[i]] = pressure->movers[std::size_t(i)];
    }
    auto light = [&](int p) { return is(p, Behaviour::Void) || is(p, Behaviour::Gas); };
    for (int p = 0; p < 8; ++p) {
      if (moved[p] || !light(p)) continue;
      const std::int32_t top = (pressure->z0 + p / 4 + 1) * kPlainHeadUnit;  // the head that just fills the cell
      int from = -1;
      std::int32_t highest = top;
      // Under momentum a bottom cell under a liquid that carries a velocity takes that liquid first,
      // whatever the heads: it falls.
      const bool falls = momentum != nullptr && p < 4 && side[p + 4] != 0;
      const std::array<int, 3> order = falls ? std::array<int, 3>{p ^ 4, p ^ 1, p ^ 2} : std::array<int, 3>{p ^ 1, p ^ 2, p ^ 4};
      for (const int q : order) {
        const bool vertical = q == (p ^ 4);
        if (moved[q] || !presses[q] || !is(q, Behaviour::Liquid) || density(q) <= density(p)) continue;
        // A top cell over a void or a gas gives its liquid only to the cell under it.
        if (q >= 4 && q - 4 != p && light(q - 4)) continue;
        // Down into a cell inside a body only from a higher head than that cell's (or, falling, from any).
        if (vertical && q > p && !plain_outside_body(head[p]) && head[q] <= head[p] && !falls) continue;
        if (head[q] > highest && pushes_in(head[q] - top, pressure->substep, vertical)) {
          highest = head[q];
          from = q;
        }
      }
      if (from < 0) continue;
      exchange(from, p);
      // Under momentum a liquid pushed sideways leaves at 2 floor(sqrt(e)) + 1 cells a tick along
      // the push, nothing across it.
      if (momentum != nullptr && from != (p ^ 4)) {
        int root = 0;
        while (root < 64 && std::int64_t(root + 1) * (root + 1) * kPlainHeadUnit <= std::int64_t(highest - top)) ++root;
        const int axis = axis_between(from, p), sign = ((block_position[p] >> axis) & 1) != 0 ? 1 : -1;
        const int speed = speed_of_cells(2 * root + 1, momentum->substeps);
        side[p] = axis == 0 ? side_byte(sign * speed, 0) : side_byte(0, sign * speed);
      }
      // Pushed down out of its body (into a cell outside any body), a liquid leaves at the speed its
      // head gives.
      if (levels && from == p + 4 && plain_outside_body(head[p]))
        cell[p] = std::uint8_t((cell[p] & ~kLevelBits) |
                               (pushed_out_level(highest - top, pressure->max_level) << kMotionShift));
    }
  }
  // 6. Momentum: each glider that has not moved steps along its velocity, x then y.
  if (momentum != nullptr)
    for (int p = 0; p < 8; ++p) {
      if (moved[p] || !glides[p] || !is(p, Behaviour::Liquid)) continue;
      for (int axis = 0; axis < 2; ++axis) {
        const int v = side_component(side[p], axis);
        const bool high = ((block_position[p] >> axis) & 1) != 0;
        if (v == 0 || high == (v > 0)) continue;  // its neighbour along v lies in another block
        if (kPlainTopSpeed * momentum->substep >= std::abs(v) * momentum->substeps) continue;  // outside its window
        const int q = viewed(block_position[p] ^ (1 << axis));
        if (moved[q]) continue;
        if (fluid(q) && density(q) < density(p)) {
          exchange(p, q);
          break;
        }
        if (is(q, Behaviour::Liquid)) {
          const std::uint8_t handed = draw[q] < kPlainHandOnLoss ? with_side_component(side[p], axis, v - (v > 0 ? 1 : -1))
                                                                 : side[p];
          side[p] = side[q];
          side[q] = handed;
          moved[p] = moved[q] = true;
          break;
        }
        side[p] = with_side_component(side[p], axis, 0);
      }
    }
  BlockCells out{};
  for (int i = 0; i < 8; ++i) out[i] = cell[map[i]];
  if (momentum != nullptr)
    for (int i = 0; i < 8; ++i) momentum->side[std::size_t(i)] = side[map[i]];
  return out;
}

std::vector<std::int32_t> plain_heads(std::span<const std::uint8_t> cells, Int3 n, const PlainRules& r) {
  const Int3 c = coarse_extent(n);
  const std::size_t count = std::size_t(c.x) * std::size_t(c.y) * std::size_t(c.z);
  auto at = [&](int x, int y, int z) {
    return cells[std::size_t(x) + std::size_t(n.x) * (std::size_t(y) + std::size_t(n.y) * std::size_t(z))];
  };
  auto coarse = [&](int x, int y, int z) {
    return std::size_t(x / 2) + std::size_t(c.x) * (std::size_t(y / 2) + std::size_t(c.y) * std::size_t(z / 2));
  };
  // A cell of the body: a liquid at rest on the floor or on something other than a void or a gas.
  auto in_body = [&](int x, int y, int z) {
    return resting_liquid(r, at(x, y, z)) && (z == 0 || !void_or_gas(r, at(x, y, z - 1)));
  };
  // Seeds, and joined[a][k]: coarse cell k is joined to its neighbour one step up axis a (x, y, z).
  std::vector<std::int32_t> heads(count, kPlainDry);
  std::array<std::vector<bool>, 3> joined{std::vector<bool>(count), std::vector<bool>(count), std::vector<bool>(count)};
  for (int z = 0; z < n.z; ++z)
    for (int y = 0; y < n.y; ++y)
      for (int x = 0; x < n.x; ++x) {
        if (!in_body(x, y, z)) continue;
        const std::size_t k = coarse(x, y, z);
        heads[k] = std::max(heads[k], kPlainSunk);
        if (z + 1 < n.z && void_or_gas(r, at(x, y, z + 1))) heads[k] = std::max(heads[k], (z + 1) * kPlainHeadUnit);
        // A cell on the upper face of its coarse cell (odd coordinate) with a body cell across it.
        if (x % 2 == 1 && x + 1 < n.x && in_body(x + 1, y, z)) joined[0][k] = true;
        if (y % 2 == 1 && y + 1 < n.y && in_body(x, y + 1, z)) joined[1][k] = true;
        if (z % 2 == 1 && z + 1 < n.z && in_body(x, y, z + 1)) joined[2][k] = true;
      }
  // Sweeps. Walking every coarse cell in increasing index order walks each line of an axis up that
  // axis in sequence (a line's cells read and write only each other), and decreasing order down it.
  const std::size_t stride[3] = {1, std::size_t(c.x), std::size_t(c.x) * std::size_t(c.y)};
  const int extent[3] = {c.x, c.y, c.z};
  auto coordinate = [&](std::size_t k, int a) { return int(k / stride[a] % std::size_t(extent[a])); };
  for (int round = 0; round < kPlainSweepRounds; ++round)
    for (int a = 0; a < 3; ++a) {
      for (std::size_t k = 0; k < count; ++k)
        if (coordinate(k, a) > 0 && joined[std::size_t(a)][k - stride[a]])
          heads[k] = std::max(heads[k], heads[k - stride[a]] - kPlainWetStep);
      for (std::size_t k = count; k-- > 0;)
        if (coordinate(k, a) + 1 < extent[a] && joined[std::size_t(a)][k])
          heads[k] = std::max(heads[k], heads[k + stride[a]] - kPlainWetStep);
    }
  // Out into the dry coarse cells: `here` outside any body takes the head of `from`, the cell before
  // it on the walk (a body's or one carried out), less a dry step and marked odd.
  auto carry_out = [&](std::size_t here, std::size_t from) {
    if (heads[from] <= kPlainSunk || !plain_outside_body(heads[here])) return;
    const std::int32_t even = heads[from] % 2 != 0 ? heads[from] - 1 : heads[from];
    heads[here] = std::max(heads[here], (even - kPlainDryStep) + 1);
  };
  for (int round = 0; round < kPlainDryRounds; ++round)
    for (int a = 0; a < 3; ++a) {
      for (std::size_t k = 0; k < count; ++k)
        if (coordinate(k, a) > 0) carry_out(k, k - stride[a]);
      if (a == 2) continue;  // never down: a liquid leaving its body downwards falls free
      for (std::size_t k = count; k-- > 0;)
        if (coordinate(k, a) + 1 < extent[a]) carry_out(k, k + stride[a]);
    }
  return heads;
}

PlainRules plain_rules(const RuleSet& rules, const Lut& lut, std::uint64_t seed) {
  PlainRules plain;
  plain.lut = &lut;
  plain.random_symmetry = rules.random_symmetry;
  plain.random_axis_order = rules.random_axis_order;
  plain.substeps = rules.motion.substeps;
  plain.columns = rules.motion.columns;
  plain.trains = rules.motion.trains;
  plain.pressure = rules.motion.pressure;
  plain.momentum = rules.motion.momentum;
  plain.shallow = rules.motion.shallow;
  bool have_static = false, have_granular = false, have_liquid = false;
  for (int s = 0; s < kMaterialCount; ++s) {
    const MaterialDef& d = rules.materials[std::size_t(s)];
    PlainMaterial& m = plain.materials[std::size_t(s)];
    m.behaviour = d.behaviour;
    m.density = d.density;
    m.spread = d.spread;
    m.topple_gain = d.grain.topple_gain;
    m.roll_cost = d.grain.roll_cost;
    m.roll_chance = d.grain.roll_chance;
    m.entrain = d.grain.entrain;
    m.flow_level = d.grain.flow_level;
    if (d.behaviour == Behaviour::Void) plain.code_state[kCodeVoid] = std::uint8_t(s);
    if (d.behaviour == Behaviour::Static && !have_static) {
      plain.code_state[kCodeObstacle] = std::uint8_t(s);
      have_static = true;
    }
    if (d.behaviour == Behaviour::Granular && !have_granular) {
      plain.code_state[kCodeGrain] = std::uint8_t(s);
      have_granular = true;
    }
    have_liquid = have_liquid || d.behaviour == Behaviour::Liquid;
  }
  // Without a motion model the Lut is keyed by materials, so gravity and flow are read from it at
  // keys of a void, a static and a granular material; a table with a liquid but no granular
  // material has no such key for a liquid's code.
  if (!plain.motion() && have_liquid && !have_granular)
    throw std::invalid_argument("plain loop: rule set '" + rules.name +
                                "' has a liquid but no granular material to read its gravity and flow as");
  plain.seed = seed;
  return plain;
}

/// Trains, after a tick, in every column bottom up. A train starts at a granular grain moving at a
/// level L; it is airborne when L >= 2 with at least motion_window(L) voids right under it. The next
/// moving granular grain above, with only void between, joins it when that gap is at most
/// motion_window of the faster of the two levels and it moves at L or the train is airborne: it
/// takes level L and swaps places with the cell right above the train's top, which becomes a plain
/// void. Carried trains: an airborne train with motion_window(min(L + 1, highest)) voids right under
/// it is carried (its grains' level bits all set and phase bit clear, and the level bits of that many
/// voids under it set: its sweep).
/// A carried grain right over a sweep falls through it with the grains of its train, at the level
/// whose window is the sweep's length, and it is carried on (a new sweep under it) if the voids under
/// the old sweep give the next tick's travel, else it lands (level L, still airborne). A sweep with
/// anything but a carried grain on it becomes plain voids; a carried grain that no airborne train
/// takes in becomes a grain at level 2. A grain at rest over an airborne train joins it when the void
/// between them is at most motion_window(min(L + 1, highest)). A carried train whose sweep ends less
/// than its next travel above an airborne train has caught it: its grains join that train.
void plain_close_trains(std::span<std::uint8_t> cells, Int3 n, const PlainRules& r) {
  const int highest = std::min(r.substeps / 2, int(kMotionLevelMask));
  auto granular = [&](std::uint8_t c) { return behaviour_of(r, c) == Behaviour::Granular; };
  auto plain_void = [&](std::uint8_t c) { return behaviour_of(r, c) == Behaviour::Void && !plain_swept(r, c); };
  auto with_level = [](std::uint8_t c, int level) { return std::uint8_t((c & ~kLevelBits) | (level << kMotionShift)); };
  auto next_level = [&](int level) { return std::min(level + 1, highest); };
  for (int y = 0; y < n.y; ++y)
    for (int x = 0; x < n.x; ++x) {
      auto at = [&](int z) -> std::uint8_t& {
        return cells[std::size_t(x) + std::size_t(n.x) * (std::size_t(y) + std::size_t(n.y) * std::size_t(z))];
      };
      // Sweeps without a carried grain right above them are released first.
      for (int z = 0; z < n.z;) {
        if (!plain_swept(r, at(z))) {
          ++z;
          continue;
        }
        int k = z;
        while (k < n.z && plain_swept(r, at(k))) ++k;
        if (k == n.z || !plain_carried(r, at(k)))
          for (int j = z; j < k; ++j) at(j) = std::uint8_t(at(j) & kMaterialMask);
        z = k;
      }
      // The trains, bottom up: `top` is the highest grain of the current train (-1: none), `from`
      // where it was before it moved, `under` the plain voids right under the next cell.
      int top = -1, from = -1, level = 0, under = 0;
      bool airborne = false, carried = false;
      for (int z = 0; z < n.z; ++z) {
        bool caught = false;
        if (plain_swept(r, at(z))) {
          // A carried train over its sweep [z, k): its lowest grain falls to z, unless the voids under
          // the sweep are fewer than its next travel and an airborne train lies under them: then it
          // has caught that train, the sweep is void again and its grains join that train.
          int k = z;
          while (plain_swept(r, at(k))) ++k;
          const int sweep_level = std::min((k - z + 1) / 2, highest);
          if (top >= 0 && airborne && under < motion_window(next_level(sweep_level))) {
            for (int j = z; j < k; ++j) at(j) = std::uint8_t(at(j) & kMaterialMask);
            under += k - z;
            z = k;
            caught = true;
          } else {
            level = sweep_level;
            const int next = next_level(level);
            carried = under >= motion_window(next);
            const std::uint8_t grain = at(k), gap = at(z);
            for (int j = z; j < k; ++j) at(j) = std::uint8_t(at(j) & kMaterialMask);
            at(z) = carried ? grain : with_level(grain, level);
            at(k) = std::uint8_t(gap & kMaterialMask);
            if (carried)
              for (int j = z - motion_window(next); j < z; ++j) at(j) = std::uint8_t((at(j) & kMaterialMask) | kLevelBits);
            airborne = true;
            top = z;
            from = k;
            under = k - z;
            z = k;
            continue;
          }
        }
        if (plain_void(at(z))) {
          ++under;
          continue;
        }
        const int below = under;
        under = 0;
        const bool is_granular = granular(at(z));
        const int space = z - from - 1;  // void between it and the train's highest grain, as they were
        // Does it join the train under it?
        bool joins = false;
        if (top >= 0 && is_granular) {
          const int own = cell_motion(at(z));
          if (plain_carried(r, at(z)))
            joins = airborne && (caught || space <= motion_window(level));  // it rides on that train
          else if (own == 0)
            joins = airborne && space <= motion_window(next_level(level));  // at rest, within its next travel
          else
            joins = (own == level || airborne) && space <= motion_window(std::max(level, own));
        }
        if (!joins) {
          if (plain_carried(r, at(z))) at(z) = with_level(at(z), kPlainFallingBodyLevel);  // no train carries it
          if (!is_granular || cell_motion(at(z)) < 1) {
            top = -1;
            continue;
          }
          // The first grain of a train.
          top = from = z;
          level = cell_motion(at(z));
          airborne = level >= kPlainFallingBodyLevel && below >= motion_window(level);
          carried = airborne && below >= motion_window(next_level(level));
          if (carried) {
            at(z) = std::uint8_t((at(z) & kMaterialMask) | kLevelBits);  // carried: no phase
            for (int j = z - motion_window(next_level(level)); j < z; ++j)
              at(j) = std::uint8_t((at(j) & kMaterialMask) | kLevelBits);
          }
          continue;
        }
        // It joins: it trades places with the cell right above the train's top.
        const int to = top + 1;
        const std::uint8_t joined = carried ? std::uint8_t((at(z) & kMaterialMask) | kLevelBits) : with_level(at(z), level);
        const std::uint8_t gap = at(to);
        at(z) = std::uint8_t(gap & kMaterialMask);
        at(to) = joined;
        under = z - to;
        top = to;
        from = z;
      }
    }
}

void plain_shallow_pass(std::span<std::uint8_t> cells, Int3 n, const PlainRules& r, std::span<std::int32_t> faces) {
  // The constants of shallow_water.hpp, written out.
  constexpr int kIterations = 32;
  constexpr std::int64_t kCell = 32768;            // volume units a cell
  constexpr std::int64_t kSpeed = 65536;           // velocity units a cell a tick
  constexpr std::int64_t kPush = kSpeed * 2 / 32;  // g dt: 2 cells a tick^2 over 1/32 tick
  constexpr std::int64_t kTop = std::int64_t(1) << 30;
  const std::size_t nx = std::size_t(n.x), ny = std::size_t(n.y), columns = nx * ny;
  if (faces.size() != 4 * columns) throw std::invalid_argument("plain_shallow_pass: the face plane needs 4 values a column");
  std::int32_t* u[2] = {faces.data(), faces.data() + columns};
  std::int32_t* f[2] = {faces.data() + 2 * columns, faces.data() + 3 * columns};
  auto at = [&](std::size_t c, int z) -> std::uint8_t& { return cells[c + columns * std::size_t(z)]; };
  auto is_liquid = [&](std::uint8_t c) { return behaviour_of(r, c) == Behaviour::Liquid; };
  auto is_open = [&](std::uint8_t c) {
    const Behaviour b = behaviour_of(r, c);
    return b == Behaviour::Void || b == Behaviour::Gas;
  };
  // The column's ground: over its highest cell that is neither open nor liquid.
  auto ground_of = [&](std::size_t c) {
    for (int z = n.z - 1; z >= 0; --z)
      if (!is_open(at(c, z)) && !is_liquid(at(c, z))) return z + 1;
    return 0;
  };
  // A static cell: neither open, liquid nor falling (a ceiling can be only that).
  auto is_static = [&](std::uint8_t c) {
    const Behaviour b = behaviour_of(r, c);
    return b != Behaviour::Void && b != Behaviour::Gas && b != Behaviour::Liquid && b != Behaviour::Granular;
  };
  // The column's body: the liquid cells from the ground up to below `roof`, each at most 2 open
  // cells above the one below it (the ground for the first); returns its highest cell (-1: none)
  // and counts it.
  auto body_of = [&](std::size_t c, int ground, int roof, int& count) {
    int top = ground - 1;
    count = 0;
    for (int z = ground; z < roof && z - top - 1 <= 2; ++z)
      if (is_liquid(at(c, z))) {
        top = z;
        ++count;
      }
    return count > 0 ? top : -1;
  };
  auto neighbour = [&](std::size_t c, int a) -> std::ptrdiff_t {
    const std::size_t x = c % nx, y = c / nx;
    if (a == 0) return x + 1 < nx ? std::ptrdiff_t(c + 1) : -1;
    return y + 1 < ny ? std::ptrdiff_t(c + nx) : -1;
  };
  auto behind = [&](std::size_t c, int a) -> std::ptrdiff_t {
    const std::size_t x = c % nx, y = c / nx;
    if (a == 0) return x > 0 ? std::ptrdiff_t(c - 1) : -1;
    return y > 0 ? std::ptrdiff_t(c - nx) : -1;
  };
  // Each column's room for the tick: [ground, roof). Under open sky the roof is the grid's top; a
  // column with no liquid there takes its highest covered body instead: the liquid from a ground up
  // to a static cell (covered), if it has one.
  // But a column beside liquid under open sky whose top is at or above the column's own ground
  // under open sky stays dry under open sky, so water runs over it.
  std::vector<int> ground(columns), roof(columns), depth(columns), open_top(columns);
  std::vector<char> covered(columns, 0);
  for (std::size_t c = 0; c < columns; ++c) {
    int count = 0;
    open_top[c] = body_of(c, ground_of(c), n.z, count);
  }
  for (std::size_t c = 0; c < columns; ++c) {
    ground[c] = ground_of(c);
    roof[c] = n.z;
    int count = 0;
    if (body_of(c, ground[c], n.z, count) >= 0) continue;
    bool overrun = false;
    for (int a = 0; a < 2; ++a)
      for (const std::ptrdiff_t m : {behind(c, a), neighbour(c, a)})
        overrun = overrun || (m >= 0 && open_top[std::size_t(m)] >= ground[c]);
    if (overrun) continue;
    for (int z = ground[c] - 1; z >= 0; --z) {
      if (!is_static(at(c, z))) continue;
      int below = z - 1;
      while (below >= 0 && (is_open(at(c, below)) || is_liquid(at(c, below)))) --below;
      if (body_of(c, below + 1, z, count) < 0) continue;
      ground[c] = below + 1;
      roof[c] = z;
      covered[c] = 1;
      break;
    }
  }
  constexpr std::int64_t kNone = std::numeric_limits<std::int64_t>::min();
  std::vector<std::int64_t> level(columns);
  std::vector<std::int32_t> next_u[2] = {std::vector<std::int32_t>(columns), std::vector<std::int32_t>(columns)};
  std::vector<std::int64_t> volume[2] = {std::vector<std::int64_t>(columns), std::vector<std::int64_t>(columns)};
  // The height two columns' rooms share above the higher ground.
  auto shared = [&](std::size_t c, std::size_t m) {
    return std::max(0, std::min(roof[c], roof[m]) - std::max(ground[c], ground[m]));
  };
  for (int it = 0; it < kIterations; ++it) {
    for (std::size_t c = 0; c < columns; ++c) body_of(c, ground[c], roof[c], depth[c]);
    // A pipe: a covered column more than half full.
    auto pipe = [&](std::size_t c) { return covered[c] && 2 * depth[c] > roof[c] - ground[c]; };
    for (std::size_t c = 0; c < columns; ++c) {
      level[c] = (std::int64_t(ground[c]) + depth[c]) * kCell;
      for (int a = 0; a < 2; ++a) {
        level[c] -= f[a][c];
        if (const std::ptrdiff_t b = behind(c, a); b >= 0) level[c] += f[a][std::size_t(b)];
      }
    }
    // A pipe's level is its head: along each line, from the first columns that are not pipes on
    // either side (through faces that share room, at most 512 faces away), interpolated by the sum
    // of 65536 / shared height over the faces to each; the mean of the two lines that find an end.
    // (An end is never a pipe, so the levels written here are never read here.)
    for (std::size_t c = 0; c < columns; ++c) {
      if (!pipe(c)) continue;
      std::int64_t line[2];
      for (int a = 0; a < 2; ++a) {
        std::int64_t end_level[2] = {0, 0}, weight[2] = {0, 0};
        bool found[2] = {false, false};
        for (int side = 0; side < 2; ++side) {
          std::size_t here = c;
          for (int k = 0; k < 512; ++k) {
            const std::ptrdiff_t next = side == 0 ? behind(here, a) : neighbour(here, a);
            if (next < 0 || shared(here, std::size_t(next)) == 0) break;
            weight[side] += 65536 / shared(here, std::size_t(next));
            if (!pipe(std::size_t(next))) {
              found[side] = true;
              end_level[side] = level[std::size_t(next)];
              break;
            }
            here = std::size_t(next);
          }
        }
        line[a] = found[0] && found[1]
                      ? end_level[0] + (end_level[1] - end_level[0]) * weight[0] / (weight[0] + weight[1])
                  : found[0] ? end_level[0]
                  : found[1] ? end_level[1]
                             : kNone;
      }
      level[c] = line[0] == kNone ? line[1] : line[1] == kNone ? line[0] : (line[0] + line[1]) / 2;
    }
    // The depths of face (c, a) above the higher ground: {its own column, the next}; under a cover
    // up to the shared room's top only, and none through a face without shared room or beside a
    // pipe without a head.
    auto depths = [&](std::size_t c, int a) {
      const std::size_t m = std::size_t(neighbour(c, a));
      const std::int64_t g = std::int64_t(std::max(ground[c], ground[m])) * kCell;
      if (!covered[c] && !covered[m]) return std::pair<std::int64_t, std::int64_t>{level[c] - g, level[m] - g};
      if (shared(c, m) == 0 || level[c] == kNone || level[m] == kNone) return std::pair<std::int64_t, std::int64_t>{0, 0};
      const std::int64_t top = g + std::int64_t(shared(c, m)) * kCell;
      return std::pair<std::int64_t, std::int64_t>{std::min(level[c], top) - g, std::min(level[m], top) - g};
    };
    auto passes = [&](std::size_t c, int a) {
      const auto [p, q] = depths(c, a);
      return p > 0 || q > 0;
    };
    auto upwind = [&](std::size_t c, int a, std::int64_t v) {
      const auto [p, q] = depths(c, a);
      return std::max<std::int64_t>(0, v > 0 ? p : v < 0 ? q : std::max(p, q));
    };
    for (std::size_t c = 0; c < columns; ++c)
      for (int a = 0; a < 2; ++a) {
        const std::ptrdiff_t m = neighbour(c, a);
        if (m < 0 || !passes(c, a)) {
          next_u[a][c] = 0;
          volume[a][c] = 0;
          continue;
        }
        std::int64_t v = u[a][c] + kPush * (level[c] - level[std::size_t(m)]) / kCell;
        const std::int64_t h = upwind(c, a, v > 0 ? 1 : v < 0 ? -1 : 0);
        const std::ptrdiff_t up = v > 0 ? behind(c, a) : v < 0 ? neighbour(std::size_t(m), a) >= 0 ? m : -1 : -1;
        if (up >= 0 && h > 0) {
          const std::int32_t w = u[a][std::size_t(up)];
          if (w != 0 && (w > 0) == (v > 0)) {
            const std::int64_t rate_num = std::abs(std::int64_t(w)) * upwind(std::size_t(up), a, w);
            const std::int64_t rate_den = kSpeed * kIterations * h;
            v = rate_num >= rate_den ? w : v + (w - v) * rate_num / rate_den;
          }
        }
        const std::int64_t cells_deep = std::max<std::int64_t>(1, h / kCell);
        // Less on deep water (beyond 16 cells) when the flow runs at half a cell a tick or faster.
        v -= v * 16 / (256 * (std::abs(v) < kSpeed / 2 ? 16 : std::max<std::int64_t>(16, cells_deep)));
        const std::int64_t stop = std::max<std::int64_t>(1, 4096 / (cells_deep * cells_deep));
        v = std::abs(v) <= stop ? 0 : v > 0 ? v - stop : v + stop;
        v = std::clamp(v, -kTop, kTop);
        next_u[a][c] = std::int32_t(v);
        volume[a][c] = f[a][c] + v * upwind(c, a, v) / (kSpeed * kIterations);
      }
    // A column whose outflow exceeds its depth scales its outflows to its depth.
    std::vector<std::pair<std::int64_t, std::int64_t>> scale(columns, {0, 0});
    for (std::size_t c = 0; c < columns; ++c) {
      std::int64_t out = 0;
      for (int a = 0; a < 2; ++a) {
        out += std::max<std::int64_t>(0, volume[a][c]);
        if (const std::ptrdiff_t b = behind(c, a); b >= 0) out += std::max<std::int64_t>(0, -volume[a][std::size_t(b)]);
      }
      if (out > std::int64_t(depth[c]) * kCell) scale[c] = {std::int64_t(depth[c]) * kCell, out};
    }
    std::vector<std::int32_t> whole[2] = {std::vector<std::int32_t>(columns, 0), std::vector<std::int32_t>(columns, 0)};
    for (std::size_t c = 0; c < columns; ++c)
      for (int a = 0; a < 2; ++a) {
        std::int64_t v = volume[a][c];
        if (v != 0) {
          const std::size_t donor = v > 0 ? c : std::size_t(neighbour(c, a));
          if (scale[donor].second != 0) v = v * scale[donor].first / scale[donor].second;
        }
        // The nearest whole cell, a half towards none.
        std::int64_t k = std::abs(v) / kCell;
        if (std::abs(v) - k * kCell > kCell / 2) ++k;
        k = v < 0 ? -k : k;
        whole[a][c] = std::int32_t(k);
        f[a][c] = std::int32_t(v - k * kCell);
        u[a][c] = next_u[a][c];
      }
    // The moves: even x faces, odd x, even y, odd y.
    for (int phase = 0; phase < 4; ++phase) {
      const int a = phase / 2;
      for (std::size_t c = 0; c < columns; ++c) {
        const std::size_t along = a == 0 ? c % nx : c / nx;
        if (int(along % 2) != phase % 2 || whole[a][c] == 0) continue;
        const std::size_t m = std::size_t(neighbour(c, a));
        const std::size_t from = whole[a][c] > 0 ? c : m, to = whole[a][c] > 0 ? m : c;
        for (int left = std::abs(whole[a][c]); left > 0; --left) {
          int count = 0;
          const int source = body_of(from, ground[from], roof[from], count);
          const int top = body_of(to, ground[to], roof[to], count);
          const int target = top >= 0 ? top + 1 : ground[to];
          if (source >= 0 && target >= roof[to] && covered[to] && 2 * count > roof[to] - ground[to]) {
            // Into a full pipe: the face keeps half its velocity and drops what it could not move.
            f[a][c] = 0;
            u[a][c] /= 2;
            break;
          }
          if (source < 0 || target >= roof[to]) {
            u[a][c] = 0;
            f[a][c] = 0;
            break;
          }
          const std::uint8_t liquid = at(from, source), space = at(to, target);
          at(to, target) = std::uint8_t(liquid & kMaterialMask);
          at(from, source) = std::uint8_t(space & kMaterialMask);
        }
      }
    }
  }
}

void plain_step(std::span<std::uint8_t> cells, Int3 size, const PlainRules& rules, std::uint64_t tick, int threads,
                std::span<std::uint8_t> side, std::span<std::int32_t> faces) {
  if (!rules.motion()) {
    plain_pass(cells, size, rules, block_offset(tick, rules.seed, rules.random_axis_order), tick, 0, threads);
    return;
  }
  // Under pressure, the tick's heads from its cells before sub-step 0.
  std::vector<std::int32_t> heads;
  if (rules.pressure) heads = plain_heads(cells, size, rules);
  for (int s = 0; s < rules.substeps; ++s)
    plain_pass(cells, size, rules, motion_pass_offset(rules, tick, s), tick, s, threads,
               rules.pressure ? &heads : nullptr, rules.momentum ? side : std::span<std::uint8_t>());
  if (rules.trains) plain_close_trains(cells, size, rules);
  if (rules.shallow) plain_shallow_pass(cells, size, rules, faces);
}

void plain_run(std::span<std::uint8_t> cells, Int3 size, const PlainRules& rules, std::uint64_t first_tick, int ticks,
               int threads, std::span<std::uint8_t> side, std::span<std::int32_t> faces) {
  for (int t = 0; t < ticks; ++t) plain_step(cells, size, rules, first_tick + std::uint64_t(t), threads, side, faces);
}

}  // namespace granular::reference
