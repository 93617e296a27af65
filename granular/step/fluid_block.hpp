#pragma once
/// @file fluid_block.hpp
/// The fluid pass: what liquids and gases do in a block after gravity and flow (paper_rule, and the
/// motion model's table) have moved the grains. That first pass sees a liquid as a grain (it falls,
/// topples and, under a motion model, accelerates and rolls as one) and a gas as void (grains and
/// liquids fall through it). This pass then moves, in this order, in the block's (symmetry-)viewed frame:
///  1. Density: in each column, a mobile cell above a lighter mobile one changes places with it
///     (MaterialDef::density; void is 0). The top cell starts the move when it is a faller (granular
///     or liquid) taking part in the step, so sand sinks through water and water through oil; the
///     bottom cell starts it when it is a gas taking part, so gas rises through void and liquid. Two
///     granular materials pass each other only while one of them moves (motion level above 0), so a
///     bed of sand and gravel sorts by density only while it is shaken (under a motion model: the
///     one-step rules have no motion levels, so their grains never pass each other). A faller that sinks here
///     drops to motion level 0: it moves through something denser than void at a speed of its own.
///     A faller taking part that did not sink topples diagonally down into a bottom cell of a lighter
///     fluid under a top cell of a lighter fluid (the grains' topple, through water instead of void),
///     so sand poured into water heaps on the bottom instead of standing as a pillar.
///  2. Liquid spread: a liquid in the top layer taking part, standing on a liquid, moves sideways
///     (preference: the x neighbour, then y, then the diagonal) with chance MaterialDef::spread / 256:
///     into a top cell of void, or while it moves (motion level above 0, so never under the one-step
///     rules) of any lighter fluid. A liquid
///     standing on a grain or a static cell does not, so a pool on a floor spreads to one layer and
///     stops, and a settled pool is inert. A liquid surface whose top layer is partly filled keeps
///     moving: its cells cannot tell a bump of one cell from the partial layer of a level surface.
///  3. Gas spread: a gas in the bottom layer taking part, under a gas, moves sideways into a bottom
///     cell of a denser fluid with chance spread / 256 (the mirror of 2: a gas pocket spreads to one
///     layer under a ceiling).
///  4. Gas around a ceiling: a gas in the bottom layer taking part that cannot rise (a static cell, a
///     grain or a gas above it) moves diagonally up into a top cell of another column when that cell
///     and the one below it are denser fluids (the mirror of the grains' topple).
///  5. Pressure (MotionParams::pressure; the caller passes each cell's head, head_field.hpp): each
///     void or gas cell, in the viewed frame's order, takes the liquid beside it in its layer (the
///     x neighbour, then y), below it or above it with the highest head, when that head stands above
///     the cell's own top (head > kUnit (z + 1)), the liquid is denser and may start a move
///     (`press_movers`: liquids at rest that kept their place) and the excess head allows a push in
///     this sub-step (head::pushes). A top cell over a void moves only down into it; a void inside
///     a body is filled from above only where the head above is higher than at the void, or (under
///     momentum) where the liquid above carries a velocity, which it then takes first. So a
///     liquid under the head of a higher surface of its body rises into void, leaves a void that
///     travels up the head to the highest surface, pours out sideways from under its surface, and
///     levels; one pushed down out of its body takes the motion level of its exit speed
///     (head::exit_level). No draw: the stage moves the same cells whatever the random words, so a
///     block it leaves as it is stays so while the heads stay (the backend wakes the bricks where a
///     move may start).
///  6. Momentum (MotionParams::momentum; the caller passes the block's side bytes, momentum.hpp):
///     every move above exchanges the side bytes with the cells; a liquid the pressure stage pushes
///     sideways leaves at the speed its head gives (2 sqrt(e) + 1 cells a tick), and one that spreads
///     in step 2 gains a unit along its move. Then each liquid with a velocity that kept its place
///     (`glide_movers`) steps along it, x then y, in the window of its speed: into a lighter fluid
///     beside it, or into a liquid, which takes its velocity in exchange for its own, losing a unit
///     with chance kHandOnLoss / 256; a static cell or a grain in the way zeroes that component.
/// Each step walks the block's columns in the viewed frame's order 0..3, and a move's targets in the
/// order x neighbour, y neighbour, diagonal. A cell moves at most once per pass (neither starting nor
/// taking a second move), and only cells the caller names as movers start a move. A faller that
/// moves in step 1 or 1b drops to motion level 0. Every move is an exchange of two cells, so the
/// pass is a permutation: each material is conserved.
///
/// What the block cannot express: a cell holds one material, so a liquid does not seep into the
/// pores of a sand bed (there are none at this scale); it stands on loose sand as on a floor, and
/// sand poured into it sinks through it, displacing it upward.

#include <cstdint>

#include "granular/extend/block.hpp"
#include "granular/motion.hpp"
#include "step/block_bytes.hpp"
#include "step/head_field.hpp"
#include "step/momentum.hpp"
#include "step/paper_rule.hpp"
#include "step/step_materials.hpp"

namespace granular::fluid {

/// Salt of the block random word of the fluid pass's chance draws (block_random(seed ^ salt, ...)).
inline constexpr std::uint64_t kDrawSalt = 0x466C756964447261ull;

/// The material of byte p of a block.
constexpr std::uint32_t material_at(std::uint64_t bytes, int p) { return std::uint32_t(bytes >> (8 * p)) & kMaterialMask; }

/// The bytes with bytes p and q exchanged.
constexpr std::uint64_t exchange(std::uint64_t bytes, int p, int q) {
  const std::uint64_t a = (bytes >> (8 * p)) & 0xFFu, b = (bytes >> (8 * q)) & 0xFFu;
  const std::uint64_t cleared = bytes & ~((0xFFull << (8 * p)) | (0xFFull << (8 * q)));
  return cleared | (a << (8 * q)) | (b << (8 * p));
}

/// True when a cell of material `m` above one of material `below` (both in one column) may change
/// places with it in the density step, given who may start the move: `top_moves` (the top cell is a
/// mover) and `bottom_moves`. `levels` says whether either cell has a motion level above 0.
constexpr bool sinks(const StepMaterials& mats, std::uint32_t m, std::uint32_t below, bool top_moves, bool bottom_moves,
                     bool levels) {
  if (mats.code(m) == kCodeObstacle || mats.code(below) == kCodeObstacle) return false;  // a static cell
  if (mats.density[m] <= mats.density[below]) return false;
  if (mats.is_granular(m) && mats.is_granular(below) && !levels) return false;
  return (top_moves && mats.is_faller(m)) || (bottom_moves && mats.is_gas(below));
}

/// True when a faller of material `m` in the top layer may topple diagonally into a bottom cell of
/// material `target` under a top cell of material `above`: both are fluids lighter than it (void
/// itself is the first pass's topple; this one lets sand heap under water).
constexpr bool topples_into(const StepMaterials& mats, std::uint32_t m, std::uint32_t target, std::uint32_t above) {
  return mats.is_fluid(target) && mats.is_fluid(above) && mats.density[target] < mats.density[m] &&
         mats.density[above] < mats.density[m] && !(mats.is_void(target) && mats.is_void(above));
}

/// The fluid pass on a block's bytes (see the file comment). `movers` has bit p set when the cell at
/// p may start a move (the caller decides who takes part in this step). `symmetry` is the block's
/// horizontal symmetry (block.hpp: view position symmetry_image(p, s) holds cell p). `draws` holds
/// one chance draw per cell (byte p for the cell at p; a move with chance c happens when the draw is
/// below c, so 0 in every byte makes every chance above 0 certain). With `kLevels`, bits 3..6 of a
/// byte are a faller's motion level, set to 0 when it moves in step 1 or 1b; without, the high bits are
/// carried along untouched (a table build tags each byte with its cell index there).
/// `heads` (MotionParams::pressure; null for none) holds each cell's head (head_field.hpp) by block
/// position, `press_movers` the cells that may start a pressure move, `z0` the block's lowest z,
/// `substep` the sub-step and `max_level` the motion model's top level.
/// `side` (MotionParams::momentum; null for none) holds the block's side bytes (momentum.hpp, byte p
/// for the cell at p): every move exchanges them with the cells, the stages above set a liquid's
/// velocity, and stage 6 moves the liquids of `glide_movers` along it; `substeps` is the tick's
/// sub-step count.
template <bool kLevels>
constexpr std::uint64_t fluid_pass(std::uint64_t bytes, std::uint32_t movers, int symmetry, std::uint64_t draws,
                                   const StepMaterials& mats, const std::int32_t* heads = nullptr,
                                   std::uint32_t press_movers = 0, int z0 = 0, int substep = 0,
                                   int max_level = 0, std::uint64_t* side = nullptr, std::uint32_t glide_movers = 0,
                                   int substeps = 0) {
  constexpr std::uint64_t kLevelBits = std::uint64_t(kMotionLevelMask) << kMotionShift;
  auto at = [&](int view) { return symmetry_preimage(view, symmetry); };
  auto level_above_zero = [&](int p) { return kLevels && ((bytes >> (8 * p)) & kLevelBits) != 0; };
  auto draw_allows = [&](int p, std::uint32_t m) { return int((draws >> (8 * p)) & 0xFFu) < int(mats.spread[m]); };
  std::uint32_t moved = 0;  // cells this pass has moved: they neither start nor take a move again
  auto starts = [&](int p) { return ((movers & ~moved) >> p) & 1u; };
  auto free = [&](int p) { return ((moved >> p) & 1u) == 0; };
  auto move = [&](int p, int q) {
    bytes = exchange(bytes, p, q);
    if (side != nullptr) *side = exchange(*side, p, q);
    moved |= (1u << p) | (1u << q);
  };
  auto side_of = [&](int p) { return side != nullptr ? byte_at(*side, p) : 0u; };
  auto set_side = [&](int p, std::uint32_t v) {
    if (side != nullptr) *side = with_byte(*side, p, v);
  };
  // A liquid that moved from `p` to `q` in its layer speeds up along that move by one (gravity down the
  // surface it left), each axis of the move.
  auto speed_up = [&](int p, int q) {
    std::uint32_t v = side_of(q);
    for (int axis = 0; axis < 2; ++axis) {
      if (((p ^ q) >> axis & 1) == 0) continue;
      const int sign = ((q >> axis) & 1) != 0 ? 1 : -1;
      const int now = momentum::component(v, axis);
      v = momentum::with_component(v, axis, now * sign > 0 ? now + sign : sign);
    }
    set_side(q, v);
  };
  // 1. Density, column by column.
  for (int column = 0; column < 4; ++column) {
    const int top = at(column + 4), bottom = at(column);
    const std::uint32_t m = material_at(bytes, top), below = material_at(bytes, bottom);
    const bool levels = level_above_zero(top) || level_above_zero(bottom);
    if (!sinks(mats, m, below, starts(top) != 0, starts(bottom) != 0, levels)) continue;
    move(top, bottom);
    if constexpr (kLevels) bytes &= ~(kLevelBits << (8 * bottom));
  }
  // 1b. A faller that could not sink topples diagonally down into a lighter fluid.
  for (int column = 0; column < 4; ++column) {
    const int top = at(column + 4);
    const std::uint32_t m = material_at(bytes, top);
    if (starts(top) == 0 || !mats.is_faller(m)) continue;
    for (int flip = 1; flip <= 3; ++flip) {
      const int target = at(column ^ flip), above = at((column ^ flip) + 4);
      if (free(target) && topples_into(mats, m, material_at(bytes, target), material_at(bytes, above))) {
        move(top, target);
        if constexpr (kLevels) bytes &= ~(kLevelBits << (8 * target));
        break;
      }
    }
  }
  // 2. Liquid spread in the top layer.
  for (int column = 0; column < 4; ++column) {
    const int top = at(column + 4), bottom = at(column);
    const std::uint32_t m = material_at(bytes, top), below = material_at(bytes, bottom);
    const bool moving = level_above_zero(top);  // never without motion levels (the one-step rules)
    if (starts(top) == 0 || !mats.is_liquid(m) || !mats.is_liquid(below) || !draw_allows(top, m)) continue;
    for (int flip = 1; flip <= 3; ++flip) {
      const int target = at((column ^ flip) + 4);
      const std::uint32_t t = material_at(bytes, target);
      if (free(target) && mats.is_fluid(t) && mats.density[t] < mats.density[m] && (moving || mats.is_void(t))) {
        move(top, target);
        speed_up(top, target);
        break;
      }
    }
  }
  // A gas in the bottom layer that cannot rise: a static cell, a grain or a gas above it.
  auto capped_gas = [&](int column) {
    const int bottom = at(column);
    const std::uint32_t m = material_at(bytes, bottom), above = material_at(bytes, at(column + 4));
    return starts(bottom) != 0 && mats.is_gas(m) && !(mats.is_fluid(above) && mats.density[above] > mats.density[m]);
  };
  // 3. Gas spread under gas in the bottom layer.
  for (int column = 0; column < 4; ++column) {
    const int bottom = at(column);
    const std::uint32_t m = material_at(bytes, bottom);
    if (!capped_gas(column) || !mats.is_gas(material_at(bytes, at(column + 4))) || !draw_allows(bottom, m)) continue;
    for (int flip = 1; flip <= 3; ++flip) {
      const int target = at(column ^ flip);
      const std::uint32_t t = material_at(bytes, target);
      if (free(target) && mats.is_fluid(t) && mats.density[t] > mats.density[m]) {
        move(bottom, target);
        break;
      }
    }
  }
  // 4. Gas around a ceiling: diagonally up into a column whose two cells are denser fluids.
  for (int column = 0; column < 4; ++column) {
    const int bottom = at(column);
    const std::uint32_t m = material_at(bytes, bottom);
    if (!capped_gas(column)) continue;
    for (int flip = 1; flip <= 3; ++flip) {
      const int target_top = at((column ^ flip) + 4), target_bottom = at(column ^ flip);
      const std::uint32_t t = material_at(bytes, target_top), u = material_at(bytes, target_bottom);
      if (free(target_top) && mats.is_fluid(t) && mats.density[t] > mats.density[m] && mats.is_fluid(u) &&
          mats.density[u] > mats.density[m]) {
        move(bottom, target_top);
        break;
      }
    }
  }
  // 5. Pressure: each void or gas takes the liquid beside, below or above it whose head stands highest
  // above its top.
  if (heads != nullptr)
    for (int view = 0; view < 8; ++view) {
      const int b = at(view);
      const std::uint32_t t = material_at(bytes, b);
      if (!free(b) || !mats.is_fluid(t) || mats.is_liquid(t)) continue;
      const std::int32_t top = (z0 + (b >> 2) + 1) * head::kUnit;  // the head that just fills the cell
      int from = -1;
      std::int32_t highest = top;
      // Under momentum a void under a liquid that carries a velocity takes that liquid first, whatever
      // the heads: a liquid on the move falls into the void under it (the column of a burst dam slumps
      // instead of frothing), while the voids under liquid at rest travel up the head as without it.
      const bool falls = side != nullptr && view < 4 && side_of(at(view ^ 4)) != 0;
      for (int k = 0; k < 3; ++k) {
        const int flip = falls ? (k == 0 ? 4 : k) : (1 << k);  // above first, else x, y, then below or above
        const int a = at(view ^ flip);
        const std::uint32_t m = material_at(bytes, a);
        if (!free(a) || ((press_movers >> a) & 1u) == 0 || !mats.is_liquid(m) || mats.density[t] >= mats.density[m]) continue;
        if (a >= 4 && a - 4 != b) {  // a top cell over a void or a gas moves only down into it
          const std::uint32_t under = material_at(bytes, a - 4);
          if (mats.is_fluid(under) && !mats.is_liquid(under)) continue;
        }
        // Down into a void of the body only where the head is higher above it than at the void: a
        // void travels up the head, towards the body's highest surface (a bubble in a pool rises; a
        // void in the rising leg of a U-tube sinks).
        const bool down = flip == 4 && view < 4;
        if (down && !head::outside_body(heads[b]) && heads[a] <= heads[b] && !falls) continue;
        if (heads[a] > highest && head::pushes(heads[a] - top, substep, flip == 4)) {
          highest = heads[a];
          from = a;
        }
      }
      if (from < 0) continue;
      move(from, b);
      // Pushed sideways, a liquid leaves at the speed its head gives (Torricelli: sqrt(2 g e) = 2 sqrt(e)
      // cells a tick), plus one.
      if (side != nullptr && (from ^ b) < 4) {
        const int axis = (from ^ b) == 1 ? 0 : 1, sign = ((b >> axis) & 1) != 0 ? 1 : -1;
        const int speed = momentum::speed_of(2 * head::root_cells(highest - top) + 1, substeps);
        set_side(b, momentum::with_component(0u, axis, sign * speed));
      }
      // Pushed down out of its body (into a coarse cell outside any body), a liquid leaves at the
      // speed its head gives (Torricelli).
      if (kLevels && from == b + 4 && head::outside_body(heads[b])) {
        const std::uint64_t level = std::uint64_t(head::exit_level(highest - top, max_level)) << kMotionShift;
        bytes = (bytes & ~(kLevelBits << (8 * b))) | (level << (8 * b));
      }
    }
  // 6. Momentum: each liquid of `glide_movers` with a sideways velocity steps along it, x then y, in
  // the window of its speed: into a lighter fluid (it glides), or into a liquid, which takes its
  // velocity in exchange for its own (the push runs on through a body at one cell a step); a
  // static cell or a grain in the way stops that component.
  if (side != nullptr)
    for (int view = 0; view < 8; ++view) {
      const int b = at(view);
      if (!free(b) || ((glide_movers >> b) & 1u) == 0) continue;
      const std::uint32_t m = material_at(bytes, b);
      if (!mats.is_liquid(m)) continue;
      for (int axis = 0; axis < 2; ++axis) {
        const std::uint32_t v = side_of(b);
        const int c = momentum::component(v, axis);
        if (c == 0 || (((b >> axis) & 1) != 0) == (c > 0)) continue;  // its neighbour along c is in another block
        if (!momentum::in_window(c > 0 ? c : -c, substep, substeps)) continue;
        const int q = b ^ (1 << axis);
        if (!free(q)) continue;
        const std::uint32_t t = material_at(bytes, q);
        if (mats.is_fluid(t) && mats.density[t] < mats.density[m]) {
          move(b, q);
          break;
        }
        if (mats.is_liquid(t)) {
          // The push loses one speed unit with chance kHandOnLoss / 256 (the liquid's viscosity).
          const std::uint32_t w = side_of(q);
          const bool loses = int((draws >> (8 * q)) & 0xFFu) < momentum::kHandOnLoss;
          set_side(q, loses ? momentum::with_component(v, axis, c > 0 ? c - 1 : c + 1) : v);
          set_side(b, w);
          moved |= (1u << b) | (1u << q);
          break;
        }
        set_side(b, momentum::with_component(v, axis, 0));
      }
    }
  return bytes;
}

/// True when the fluid pass could change a block of these bytes for some choice of movers, symmetry
/// and draws (given its grains' motion levels): the fluid half of a block's quiet test.
constexpr bool may_move(std::uint64_t bytes, const StepMaterials& mats) {
  constexpr std::uint64_t kLevelBits = std::uint64_t(kMotionLevelMask) << kMotionShift;
  for (int column = 0; column < 4; ++column) {
    const int top = column + 4, bottom = column;
    const std::uint32_t m = material_at(bytes, top), below = material_at(bytes, bottom);
    const bool levels = ((bytes >> (8 * top)) & kLevelBits) != 0 || ((bytes >> (8 * bottom)) & kLevelBits) != 0;
    if (sinks(mats, m, below, true, true, levels)) return true;
    if (mats.is_faller(m))
      for (int other = 0; other < 4; ++other)
        if (other != bottom && topples_into(mats, m, material_at(bytes, other), material_at(bytes, other + 4))) return true;
    const bool moving = ((bytes >> (8 * top)) & kLevelBits) != 0;
    if (mats.is_liquid(m) && mats.is_liquid(below) && mats.spread[m] > 0)
      for (int other = 4; other < 8; ++other) {
        const std::uint32_t t = material_at(bytes, other);
        if (other != top && mats.is_fluid(t) && mats.density[t] < mats.density[m] &&
            (moving || mats.is_void(t)))
          return true;
      }
    if (mats.is_gas(below)) {
      const bool capped = !(mats.is_fluid(m) && mats.density[m] > mats.density[below]);
      if (!capped) continue;
      for (int other = 0; other < 4; ++other) {
        if (other == bottom) continue;
        const std::uint32_t t = material_at(bytes, other + 4), u = material_at(bytes, other);
        const bool denser_below = mats.is_fluid(u) && mats.density[u] > mats.density[below];
        if (mats.is_gas(m) && mats.spread[below] > 0 && denser_below) return true;
        if (denser_below && mats.is_fluid(t) && mats.density[t] > mats.density[below]) return true;
      }
    }
  }
  return false;
}

/// The one-step rules' transition of a block of materials (`key`, 3 bits per cell): gravity and flow
/// (rules::paper_rule on the table codes) then the fluid pass with every cell a mover and every chance
/// above 0 certain, in the table's own frame (the step applies the random symmetry around the lookup).
constexpr Transition one_step_transition(BlockKey key, const StepMaterials& mats) {
  const Transition first = rules::paper_rule(mats.code_key(key));
  if (!mats.fluid_pass_applies(present_materials(unpack_key(key)))) return first;
  // The bytes after the first pass, each tagged with the cell it came from (bits 3..5).
  std::uint64_t bytes = 0;
  for (int i = 0; i < 8; ++i)
    bytes |= std::uint64_t(((key >> (3 * i)) & 7u) | (std::uint32_t(i) << 3)) << (8 * destination(first, i));
  bytes = fluid_pass<false>(bytes, 0xFFu, 0, 0, mats);
  Transition t = 0;
  for (int p = 0; p < 8; ++p) t |= Transition(p) << (3 * ((bytes >> (8 * p + 3)) & 7u));
  return t;
}

}  // namespace granular::fluid
