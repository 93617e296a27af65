#pragma once
/// @file motion_block.hpp
/// One block of one sub-step of the motion model (granular/motion.hpp), as constexpr functions on
/// plain integers: the CPU kernels and the CUDA kernels (nvcc --expt-relaxed-constexpr) compile
/// this very code, which is what makes the two backends bit-identical.
///
/// A tick of a motion rule set runs MotionParams::substeps Margolus sub-steps. Sub-step s of tick
/// t uses the partition offset motion_offset(t, s): z flips every sub-step (from sub-step 2, x and
/// y in about 3 of 4 under MotionParams::momentum), and the sub-step in which grains at rest take
/// part (s = t & 1) walks all 8 offsets over 8 ticks, as the one-step cycle does. Per block:
///  0. Under MotionParams::columns, each wake in the bottom layer (the void a grain falling straight
///     down left in the last sub-step) is cleared, and the faller above it takes part in this sub-step
///     whatever its window, at the wake's level if that is higher than its own.
///  1. Each cell gets a code for the table from its material's behaviour (StepMaterials): void 0
///     (void and every gas), obstacle 1 (every static material), grain 2 (every granular and liquid
///     one: a faller). A faller in the top layer that is outside its window this sub-step (it is too slow
///     to move now) reads as an obstacle; one inside its window with a motion level above 0 reads,
///     with chance roll_chance / 256 (its material's GrainMotion), as a roller (3), which the table lets roll sideways onto the
///     top of a neighbour column one cell lower. Bottom-layer grains never move on their own, so
///     their code is always 2.
///  2. The block's random symmetry and its key (2 bits per cell) pick one of the motion entries
///     (MotionEntry: motion_rule's transition of the key seen under the symmetry, kMotionTableKeys
///     keys, mapped back to the block's own frame as a byte gather, with where each top cell went).
///  3. The 8 bytes are permuted with their motion levels, and each grain that took part updates
///     its level: one that fell straight down gains 1 in the first sub-step of its window when
///     nothing is beside it in the top layer (gravity accelerates free grains, not a dense flow),
///     under MotionParams::columns whatever is beside it (every grain that falls is in free fall);
///     one that toppled down a step gains 1 with chance topple_gain / 256; one that was blocked
///     from below loses 1 with chance roll_cost / 256 if it rolled, kStuckCost / 256 if its block
///     had no room. So a moving grain runs on down slopes steeper than the balance of gains and
///     costs and stops on shallower ones, whatever the pile's size: the friction lever. One that
///     rolled or toppled keeps at most its material's GrainMotion::flow_level, except under
///     MotionParams::columns over a grain falling at kFallingLevel or faster (in_falling_body).
///     A grain at rest in the top layer on a step edge is set moving (level 1) with chance
///     GrainMotion::entrain / 256 when a moving grain rolled or toppled in its block (entrain_step_edges).
///  4. On a block holding a liquid, a gas or two granular materials, the fluid pass
///     (fluid_block.hpp) moves what gravity and flow left: density order, liquid and gas spread. Its
///     movers are the fallers that took part and stayed, and in sub-steps 0 and 1 the bottom-layer
///     gases (a gas rises at most 2 cells per tick and has no motion state); its draws come from
///     block_random(seed ^ fluid::kDrawSalt, t * substeps + s, x0, y0, z0).
///  5. Under MotionParams::columns, each top cell whose grain fell straight down and that holds a
///     plain void now becomes a wake: kWakeBit and the grain's level, for the next sub-step.
/// Under MotionParams::momentum the block's side bytes (momentum.hpp) move with its cells in 3 and
/// 4, a liquid that rolled or toppled in 3 takes the velocity of its move at the speed of its level,
/// and a liquid with a velocity takes part in 4 whatever its window.
/// A grain's window is motion_window(level) sub-steps from its phase: in sub-step 0 every grain
/// notes its layer (top: phase 0, bottom: phase 1, where it is top one sub-step later), so a grain
/// starting from rest falls 1, 4, 9, ... cells after 1, 2, 3 ticks whichever layer it starts in,
/// and a grain at rest keeps the same phase tick after tick.
/// The random word is block_random(seed, t * substeps + s, x0, y0, z0); its low 3 bits pick the
/// symmetry, byte k (k = 1..4) the roll draw of top cell k + 3, and 6 bits from bit 40 + 6 (i - 4)
/// the level draw of top cell i (as a multiple of 4 out of 256).

#include <cstdint>

#include "granular/extend/block.hpp"
#include "granular/motion.hpp"
#include "step/block_bytes.hpp"
#include "step/fluid_block.hpp"
#include "step/head_field.hpp"
#include "step/momentum.hpp"
#include "step/paper_rule.hpp"
#include "step/step_materials.hpp"

namespace granular::motion {

/// Chance out of 256 that a moving grain blocked from below with no room to roll in its block
/// loses a level (so a grain stuck in a pit comes to rest, and its brick can sleep).
inline constexpr int kStuckCost = 64;

/// True when `under`, the cell under a top cell in its block before the move, is a granular grain
/// falling at kFallingLevel or faster, or a carried grain (a static material at a motion level:
/// carried::falling_static): under MotionParams::columns the grain over it that rolls or topples is
/// slipping past it inside a falling body, and keeps its level (no flow level).
constexpr bool in_falling_body(const StepMaterials& mats, std::uint32_t under) {
  return (mats.is_granular(under & kMaterialMask) || mats.code(under & kMaterialMask) == kCodeObstacle) &&
         int((under >> kMotionShift) & kMotionLevelMask) >= kFallingLevel;
}

/// The motion model's block rule on a key of table codes (3 bits per cell, block.hpp order):
/// the paper's gravity and flow (rules::paper_rule) with rollers moving as grains, then roll (a
/// roller that has not moved goes to the top cell of another column when that cell is void and the
/// one below it is not; preference: the x neighbour, then y, then the diagonal). Codes 1 and 4..7
/// are obstacles and never move. On codes 0..2 this is the paper's rule.
constexpr Transition motion_rule(BlockKey key) {
  BlockKey as_grains = key;
  for (int i = 0; i < 8; ++i)
    if (((key >> (3 * i)) & 7u) == kCodeRoller) as_grains ^= (kCodeRoller ^ kCodeGrain) << (3 * i);
  const Transition fall = rules::paper_rule(as_grains);
  std::uint32_t state[8] = {}, from[8] = {};  // after gravity and flow: the code at p, and where it came from
  for (int i = 0; i < 8; ++i) {
    state[destination(fall, i)] = (key >> (3 * i)) & 7u;
    from[destination(fall, i)] = std::uint32_t(i);
  }
  // Gravity and flow only move grains down into the bottom layer, so a roller still in the top
  // layer has not moved; one that rolls is marked so it does not roll again.
  bool rolled[8] = {};
  for (int column = 0; column < 4; ++column) {
    const int top = column + 4;
    if (state[top] != kCodeRoller || rolled[top]) continue;
    for (int flip = 1; flip <= 3; ++flip) {
      const int target = (column ^ flip) + 4;
      if (state[target] == kCodeVoid && state[target - 4] != kCodeVoid) {
        const std::uint32_t s = state[top], f = from[top];
        state[top] = state[target];
        from[top] = from[target];
        state[target] = s;
        from[target] = f;
        rolled[target] = true;
        break;
      }
    }
  }
  Transition transition = 0;
  for (int p = 0; p < 8; ++p) transition |= Transition(p) << (3 * from[p]);
  return transition;
}

/// Keys of the motion table: a block's 8 table codes (all below 4) at 2 bits per cell, block order.
/// The table (256 KiB) is motion_rule's transition table at those keys, small enough to stay in a
/// CPU's or a GPU's cache, where the full table of 3-bit keys (64 MiB) is not.
inline constexpr std::uint32_t kMotionTableKeys = 1u << 16;

/// The full table's key (3 bits per cell) of motion table key `compact` (2 bits per cell).
constexpr BlockKey full_code_key(std::uint32_t compact) {
  BlockKey key = 0;
  for (int i = 0; i < 8; ++i) key |= ((compact >> (2 * i)) & 3u) << (3 * i);
  return key;
}

/// What the step looks up for a block: the motion table's transition of the block's key under one
/// of the 8 horizontal symmetries, mapped back to the block's own frame, in the form the step
/// applies at once. Nibble p (its low 3 bits) names the cell whose byte goes to position p (a
/// gather, gather_bytes); the nibbles' high bits say where each top-layer cell 4 + k went: bit 3 +
/// 8 k and bit 7 + 8 k hold its MotionMove.
using MotionEntry = std::uint32_t;

/// Entries per symmetry: one per motion table key; entry (symmetry << 16) | key (kMotionEntries in all).
inline constexpr std::uint32_t kMotionEntries = 8 * kMotionTableKeys;

/// The entry of a block where nothing moves.
inline constexpr MotionEntry kStillEntry = 0x76543210u;

/// Where a top-layer cell went in a block's transition.
enum MotionMove : std::uint32_t {
  kStayed = 0,    ///< it kept its place
  kRolled = 1,    ///< to another column's top cell
  kFell = 2,      ///< straight down, to its own column's bottom cell
  kToppled = 3,   ///< diagonally down, to another column's bottom cell
};

/// The motion table key of a block of motion table key `key` seen under symmetry `symmetry`
/// (block.hpp: cell i at position symmetry_image(i, symmetry)).
constexpr std::uint32_t viewed_motion_key(std::uint32_t key, int symmetry) {
  std::uint32_t viewed = 0;
  for (int i = 0; i < 8; ++i) viewed |= ((key >> (2 * i)) & 3u) << (2 * symmetry_image(i, symmetry));
  return viewed;
}

/// The entry of a block whose transition seen under symmetry `symmetry` is `viewed` (the motion
/// table's transition at viewed_motion_key).
constexpr MotionEntry motion_entry(Transition viewed, int symmetry) {
  MotionEntry entry = 0;
  for (int i = 0; i < 8; ++i) {
    const int dest = symmetry_preimage(destination(viewed, symmetry_image(i, symmetry)), symmetry);
    entry |= MotionEntry(i) << (4 * dest);
    if (i < 4) continue;
    const std::uint32_t move = dest >= 4 ? (dest == i ? kStayed : kRolled) : ((dest & 3) == (i & 3) ? kFell : kToppled);
    entry |= ((move & 1u) << (3 + 8 * (i - 4))) | ((move >> 1) << (7 + 8 * (i - 4)));
  }
  return entry;
}

/// Entry `index` of the motion entries ((symmetry << 16) | key) of a motion table whose transition at
/// motion table key k is `transition(k)`.
template <class TransitionOf>
constexpr MotionEntry motion_entry_at(std::uint32_t index, TransitionOf transition) {
  const int symmetry = int(index >> 16);
  return motion_entry(transition(viewed_motion_key(index & 0xFFFFu, symmetry)), symmetry);
}

/// The partition offset of sub-step `substep` of tick `tick` (see the file comment); with
/// `random_axis_order`, x and y are exchanged on the 8-tick cycles cycle_swaps_axes draws.
///
/// With `flipping` (MotionParams::momentum) sub-steps 0 and 1 keep the default offsets (x and y
/// from bits 1 and 2 of tick + s), so the grains at rest and those flowing at level 1, which move
/// only in those two, meet the default schedule; from sub-step 2 on, each sub-step takes, among the
/// x and y its run of 8 sub-steps (s = 0..7, 8..15, ...) has not yet used with its z, the pair that
/// flips most of x and y from the sub-step before (ties: the lower x, then the lower y). A cell then
/// meets its neighbour along x and y in its block in about 6 of every 8 sub-steps, where the
/// default gives 4 of 8 along x and 2 of 8 along y, and every run of 8 still takes all 8 offsets,
/// which sparse stepping needs.
constexpr BlockOffset motion_offset(std::uint64_t tick, int substep, std::uint64_t seed, bool random_axis_order,
                                    bool flipping = false) {
  const std::uint64_t phase = tick + std::uint64_t(substep);
  BlockOffset o{int((phase >> 1) & 1u), int((phase >> 2) & 1u), substep & 1};
  if (flipping && substep >= 2) {
    // (x, y) as 2 x + y; used[z]: those the run of 8 has taken with z.
    unsigned prev = ((unsigned(tick + 1) >> 1 & 1u) << 1) | (unsigned(tick + 1) >> 2 & 1u);
    unsigned used[2] = {1u << (((unsigned(tick) >> 1 & 1u) << 1) | (unsigned(tick) >> 2 & 1u)), 1u << prev};
    for (int s = 2; s <= substep; ++s) {
      if (s % 8 == 0) used[0] = used[1] = 0;
      unsigned& taken = used[s & 1];
      unsigned best = 0, fewest_kept = 3;
      for (unsigned c = 0; c < 4; ++c) {
        const unsigned kept = unsigned((c >> 1) == (prev >> 1)) + unsigned((c & 1u) == (prev & 1u));
        if ((taken >> c & 1u) == 0 && kept < fewest_kept) {
          best = c;
          fewest_kept = kept;
        }
      }
      prev = best;
      taken |= 1u << best;
    }
    o.x = int(prev >> 1);
    o.y = int(prev & 1u);
  }
  if (random_axis_order && cycle_swaps_axes(seed, tick)) {
    const int x = o.x;
    o.x = o.y;
    o.y = x;
  }
  return o;
}

/// What one sub-step of the motion model needs besides the cells.
struct SubStep {
  std::uint64_t seed = 0;       ///< world seed
  std::uint64_t tick = 0;       ///< the tick
  int substep = 0;              ///< this sub-step, 0 .. substeps - 1
  int substeps = 2;             ///< MotionParams::substeps (the highest level follows from it)
  bool columns = false;         ///< MotionParams::columns: grains in free fall fall as columns
  bool trains = false;          ///< MotionParams::trains: a fast grain waits behind one falling as fast
  bool random_symmetry = false; ///< draw a horizontal symmetry per block
  StepMaterials materials;      ///< the rule set's material table (codes, grains, grain motion)

  /// The step's number across ticks, tick * substeps + substep: what its random words are drawn at.
  constexpr std::uint64_t step() const { return tick * std::uint64_t(substeps) + std::uint64_t(substep); }
  /// block_seed_key of the block random words (seed) and of the fluid pass's draws (seed ^ kDrawSalt).
  std::uint64_t random_key = 0, draw_key = 0;
  /// block_position_offset of the world's domain origin (0 for a whole world).
  std::uint64_t origin = 0;
};

/// The SubStep of sub-step `substep` of tick `tick` for a rule set's motion model, in a world whose
/// domain origin packs to `origin` (block_position_offset).
constexpr SubStep sub_step(const MotionParams& motion, const StepMaterials& materials, std::uint64_t seed,
                           std::uint64_t tick, int substep, bool random_symmetry, std::uint64_t origin = 0) {
  return SubStep{seed,      tick,           substep,         motion.substeps, motion.columns, motion.trains,
                 random_symmetry, materials, block_seed_key(seed), block_seed_key(seed ^ fluid::kDrawSalt), origin};
}

/// The phase bits of a block whose cells are all grains, as sub-step 0 sets them, at partition z
/// offset `offset_z`: a grain takes phase 0 in the top layer of its block at sub-step 0 (its window
/// starts at once) and kMotionPhaseBit in the bottom layer (it is in a top layer from sub-step 1), so
/// the bits are set in the layer that is the bottom one at sub-step 0 (rest_phase_bits(0) at sub-step 0).
constexpr std::uint64_t rest_phase_bits(int offset_z) {
  return offset_z == 0 ? 0x0000000080808080ull : 0x8080808000000000ull;
}

/// The key of a block's materials with every grain as code 2 and every obstacle as 1 (what the
/// inert-key table is asked about), and whether every grain in it is at rest: level 0, and the
/// phase sub-step 0 gives it (a block at offset z `offset_z` has its bottom layer at sub-step 0's
/// parity when offset_z is 0, else its top layer). A block whose grains are all at rest and whose
/// key is inert stays as it is in every sub-step, whatever the draws: at rest no grain is a
/// roller, a grain outside its window only turns into an obstacle, which never lets a block move
/// that would not move anyway, a grain at rest that stays keeps level 0, and sub-step 0 rewrites
/// each phase with the value it has.
constexpr BlockKey rest_key(std::uint64_t bytes, int offset_z, const StepMaterials& materials, bool& all_at_rest) {
  const BlockKey key = materials.code_key(pack_key(bytes & (kEveryByte * kMaterialMask)));
  // 0x80 in the bytes whose code is a grain's (the codes here are 0..2, so after the exclusive or
  // only a grain's byte is 0, and the borrow of a 0 byte never turns a neighbour's 2 or 3 into 0).
  const std::uint64_t x = unpack_key(key) ^ (kEveryByte * kCodeGrain);
  const std::uint64_t grains = (x - kEveryByte) & ~x & (kEveryByte * 0x80u);
  // At rest: no motion level, and the phase bit set exactly in the grains whose layer at sub-step 0
  // is the bottom one (rest_phase_bits): this layer when offset_z is 0, else the other.
  const std::uint64_t bottom = rest_phase_bits(offset_z);
  all_at_rest = (bytes & (kEveryByte * std::uint64_t(kMotionLevelMask << kMotionShift))) == 0 &&
                (bytes & (kEveryByte * 0x80u)) == (grains & bottom);
  return key;
}

/// 0x80 in each byte of `bytes` that is a wake (kWakeBit on a void: MotionParams::columns).
constexpr std::uint64_t wake_bytes(std::uint64_t bytes) {
  const std::uint64_t solid = ((bytes & (kEveryByte * kMaterialMask)) + kEveryByte * 0x7Fu) & (kEveryByte * 0x80u);
  return bytes & (kEveryByte * kWakeBit) & ~solid;
}

/// The largest, over a block's 8 bytes, of 2 L + start for a faller at motion level L whose window
/// starts at sub-step `start` (its phase bit): step_block lets such a faller take part in a sub-step
/// s >= 2 only when s + 2 <= 2 L + start, so no cell of a block whose value is below s + 2 takes part
/// in sub-step s, and the block stays as it is. Bytes without motion state (bits 3..7 zero: void,
/// gases, static materials) add 0. Under MotionParams::columns a wake adds 31 (with_wakes): the
/// faller above it takes part in the next sub-step whatever its window, so the bricks around a
/// moving column stay in the tick.
constexpr std::uint32_t reach_of(std::uint64_t bytes, bool with_wakes = false) {
  // Per byte 2 L + start (below 32), a wake 31, then the largest byte by halving: a >= b where the
  // borrow-free (a | 0x80) - b keeps its 0x80 bit.
  std::uint64_t r = ((bytes >> 2) & (kEveryByte * 0x1Eu)) | ((bytes >> 7) & kEveryByte);
  if (with_wakes) r |= (wake_bytes(bytes) >> 7) * 0x1Fu;
  for (int shift = 32; shift >= 8; shift /= 2) {
    const std::uint64_t other = r >> shift;
    const std::uint64_t keep = ((((r | (kEveryByte * 0x80u)) - other) >> 7) & kEveryByte) * 0xFFu;
    r = (r & keep) | (other & ~keep);
  }
  return std::uint32_t(r & 0xFFu);
}

/// The bytes of a block full of the table's first granular material, every grain at rest (level
/// 0, the phase rest_key asks for at partition z offset `offset_z`): its key is uniform, so inert, and
/// it is quiet. 0 (a void block, quiet too) when the table has no granular material.
constexpr std::uint64_t rest_block(const StepMaterials& materials, int offset_z) {
  for (std::uint32_t m = 0; m < kMaterialCount; ++m)
    if (materials.is_granular(m))
      return m * kEveryByte | rest_phase_bits(offset_z);
  return 0;
}

/// `bytes` with the wakes of `wakes` (byte k: the wake top cell 4 + k left, 0 if none) written into the
/// top cells they name that hold a plain void (a cell something else moved into keeps it).
constexpr std::uint64_t leave_wakes(std::uint64_t bytes, std::uint32_t wakes) {
  for (int k = 0; k < 4; ++k) {
    const std::uint32_t wake = (wakes >> (8 * k)) & 0xFFu;
    if (wake != 0 && ((bytes >> (32 + 8 * k)) & 0xFFu) == 0) bytes |= std::uint64_t(wake) << (32 + 8 * k);
  }
  return bytes;
}

/// `out` (a block's bytes after its move, the entry `entry` applied to bytes of table codes `codes`)
/// with each grain at rest in the top layer that kept its place and stands on a step edge (a top
/// cell beside it is void and the cell under that one is not) set moving, at level 1, with chance
/// GrainMotion::entrain / 256 of its material, drawn from its level draw (bits 40 + 6 k of `random`
/// for top cell 4 + k, which a grain that kept its place at level 0 never uses otherwise). step_block
/// calls it when a moving grain rolled or toppled in the block: a flowing layer erodes the slope it
/// runs on, so an avalanche spreads over the slope and stops at the angle where moving grains stop.
template <class ByteOps>
constexpr std::uint64_t entrain_step_edges(std::uint64_t out, std::uint64_t codes, MotionEntry entry,
                                           std::uint64_t random, const StepMaterials& mats) {
  const std::uint64_t out_codes = ByteOps::gather(codes, entry & 0x77777777u);
  for (int k = 0; k < 4; ++k) {
    const int p = 4 + k;
    if (((entry >> (4 * p)) & 7u) != std::uint32_t(p)) continue;
    const std::uint64_t byte = (out >> (8 * p)) & 0xFFu;
    if (((mats.entrained >> (byte & kMaterialMask)) & 1u) == 0 || ((byte >> kMotionShift) & kMotionLevelMask) != 0)
      continue;
    bool edge = false;
    for (int flip = 1; flip <= 3; ++flip) {
      const int q = k ^ flip;
      edge = edge || (((out_codes >> (8 * (4 + q))) & 0xFFu) == kCodeVoid && ((out_codes >> (8 * q)) & 0xFFu) != kCodeVoid);
    }
    if (edge && int((random >> (40 + 6 * k)) & 63u) * 4 < int(mats.entrain[byte & kMaterialMask]))
      out |= std::uint64_t(1u << kMotionShift) << (8 * p);
  }
  return out;
}

/// The block's 8 bytes (cell i in byte i) after sub-step `m` (see the file comment). `load(k)`
/// reads entry k of the motion entries (kMotionEntries; a plain read on the CPU, a read-only cache
/// load on a GPU); ByteOps does the per-cell lookups and the byte gather (PortableByteOps, or a
/// Platform's own). The cells are worked on as words of 8 bytes, 4 at a time per layer where the
/// step's conditions allow it, which is what keeps a block's instructions few on a GPU.
/// `kColumns` must be m.columns: the lever is compiled in or out, so a kernel without it keeps its
/// registers and instructions (step_block picks it at run time, for callers that do not care).
/// `heads` (MotionParams::pressure; null without) holds the head (head_field.hpp) of each cell of
/// the block by block position: the fluid pass's pressure stage reads it, and every liquid of the
/// block that kept its place may start a pressure move, in every sub-step.
/// `side` (MotionParams::momentum; null without) holds the block's side bytes (momentum.hpp): they
/// move with the cells, a liquid that rolls or topples takes the velocity of its move, and the fluid
/// pass moves each liquid with a velocity that kept its place along it.
template <bool kColumns, class ByteOps = PortableByteOps, class Load>
constexpr std::uint64_t step_block_as(std::uint64_t bytes, const SubStep& m, int x0, int y0, int z0, Load load,
                                      const std::int32_t* heads = nullptr, std::uint64_t* side = nullptr) {
  const StepMaterials& mats = m.materials;
  const int s = m.substep;
  const std::uint64_t props = ByteOps::lookup(mats.cell_props, bytes);  // byte i: material i's cell_props
  const std::uint64_t fallers = (props >> 2) & kEveryByte;              // 1 in each faller's byte
  // Wakes (MotionParams::columns): a sub-step only ever finds them in its blocks' bottom layer, where
  // the last one left them. Each is cleared; the faller above it follows (1 in byte k of `follow` for
  // top cell 4 + k) and takes the wake's level if it is higher.
  std::uint32_t follow = 0;
  if constexpr (kColumns) {
    const std::uint32_t wakes = std::uint32_t(wake_bytes(bytes));
    if (wakes != 0) {
      const std::uint32_t bottom = std::uint32_t(bytes);
      follow = (wakes >> 7) & std::uint32_t(fallers >> 32);
      bytes &= ~std::uint64_t((wakes >> 7) * 0xFFu);
      for (int k = 0; k < 4; ++k) {
        if (((follow >> (8 * k)) & 1u) == 0) continue;
        const std::uint32_t wake_level = (bottom >> (8 * k + kMotionShift)) & kMotionLevelMask;
        const std::uint64_t top_byte = (bytes >> (32 + 8 * k)) & 0xFFu;
        if (((top_byte >> kMotionShift) & kMotionLevelMask) < wake_level)
          bytes = (bytes & ~(std::uint64_t(kMotionLevelMask << kMotionShift) << (32 + 8 * k))) |
                  (std::uint64_t(wake_level << kMotionShift) << (32 + 8 * k));
      }
    }
  }
  if (s == 0) bytes = (bytes & ~(fallers << 7)) | ((fallers << 7) & rest_phase_bits(0));
  // Which cells take part (1 in their byte): top-layer fallers inside their window, and in sub-steps 0
  // and 1 bottom-layer gases. Only they ever start a move or change, so a block without one is left as
  // it is before its random word is drawn. A top faller at level L with phase start (0 or 1) is in its
  // window at sub-step s > start when 2 L + start >= s + 2 (s - start < motion_window(L)), and always
  // at s = start; in sub-step 0 every top faller's start is 0.
  const std::uint32_t top = std::uint32_t(bytes >> 32);
  const std::uint32_t top_fallers = std::uint32_t(fallers >> 32);
  std::uint32_t part = top_fallers;
  if (s > 0) {
    const std::uint32_t start = (top >> 7) & 0x01010101u;
    const std::uint32_t reach = ((top >> 2) & 0x1E1E1E1Eu) | start;  // 2 L + start, at most 31 per byte
    const std::uint32_t late = ((reach + 0x01010101u * std::uint32_t(0x80 - (s + 2))) >> 7) & 0x01010101u;
    part &= late | (s == 1 ? start : 0u) | follow;
  }
  // Under MotionParams::trains a moving top grain (level 1 or more) over a grain falling at least as
  // fast (the cell below it in the block) waits for it: it falls with it, it does not slip around it.
  if (kColumns && m.trains)
    for (int k = 0; k < 4; ++k) {
      const std::uint32_t above = (top >> (8 * k)) & 0xFFu, below = std::uint32_t(bytes >> (8 * k)) & 0xFFu;
      const int level = int((above >> kMotionShift) & kMotionLevelMask);
      if (level >= 1 && mats.is_granular(above & kMaterialMask) && mats.is_granular(below & kMaterialMask) &&
          int((below >> kMotionShift) & kMotionLevelMask) >= level)
        part &= ~(1u << (8 * k));
    }
  const std::uint32_t gases = s < 2 && mats.gases != 0 ? std::uint32_t(props >> 3) & 0x01010101u : 0u;
  // Under pressure, every liquid at rest of the block (bit p for cell p, head::at_rest_liquid): the
  // pressure stage moves them in every sub-step.
  std::uint32_t pressed = 0;
  if (heads != nullptr)
    for (int p = 0; p < 8; ++p) pressed |= (head::at_rest_liquid(mats, std::uint32_t(bytes >> (8 * p)) & 0xFFu) ? 1u : 0u) << p;
  // Under momentum, every liquid with a sideways velocity (bit p for cell p).
  auto gliders = [&](std::uint64_t cells) {
    std::uint32_t g = 0;
    if (side != nullptr)
      for (int p = 0; p < 8; ++p)
        g |= (byte_at(*side, p) != 0 && mats.is_liquid(byte_at(cells, p) & kMaterialMask) ? 1u : 0u) << p;
    return g;
  };
  if ((part | gases | pressed | gliders(bytes)) == 0) return bytes;
  const std::uint64_t random = block_random_keyed(m.random_key, m.step(), x0, y0, z0, m.origin);
  const int symmetry = m.random_symmetry ? int(random & 7u) : 0;
  // The table codes: a top faller outside its window is too slow to move now, an obstacle (code 2 ->
  // 1); one inside it with a motion level above 0 is, with chance roll_chance / 256, a roller (2 -> 3).
  const std::uint64_t codes = props & (kEveryByte * kPropCode);
  std::uint32_t top_codes = std::uint32_t(codes >> 32) - (top_fallers & ~part);
  for (int k = 0; k < 4; ++k) {
    const std::uint32_t byte = (top >> (8 * k)) & 0xFFu;
    if (((part >> (8 * k)) & 1u) != 0 && ((byte >> kMotionShift) & kMotionLevelMask) > 0 &&
        int((random >> (8 * (k + 1))) & 0xFFu) < int(mats.roll_chance[byte & kMaterialMask]))
      top_codes += 1u << (8 * k);
  }
  std::uint64_t packed = (codes & 0xFFFFFFFFull) | (std::uint64_t(top_codes) << 32);  // to 2 bits per cell
  packed = (packed | (packed >> 6)) & 0x000F000F000F000Full;
  packed = (packed | (packed >> 12)) & 0x000000FF000000FFull;
  const std::uint32_t key = std::uint32_t(packed | (packed >> 24)) & 0xFFFFu;
  const MotionEntry entry = part != 0 ? load((std::uint32_t(symmetry) << 16) | key) : kStillEntry;
  // Each top cell that took part updates its level by where it went (MotionMove).
  std::uint32_t occupied = std::uint32_t(codes >> 32);  // top cells that are not void: bit k for cell 4 + k
  occupied = (occupied | (occupied >> 1)) & 0x01010101u;
  occupied = (occupied | (occupied >> 7) | (occupied >> 14) | (occupied >> 21)) & 15u;
  const int max_level = MotionParams{.substeps = m.substeps}.max_level();
  auto move_of = [&](int k) { return ((entry >> (3 + 8 * k)) & 1u) | ((entry >> (6 + 8 * k)) & 2u); };
  std::uint32_t new_top = top;
  std::uint32_t wakes_left = 0;  // byte k: the wake top cell 4 + k leaves if it fell, else 0
  bool flowed = false;           // a moving grain rolled or toppled (GrainMotion::entrain)
  int slid[4] = {};              // under momentum: the speed of a liquid in top cell 4 + k that rolled or toppled
  for (int k = 0; k < 4; ++k) {
    if (((part >> (8 * k)) & 1u) == 0) continue;
    const std::uint32_t byte = (top >> (8 * k)) & 0xFFu;
    const std::uint32_t material = byte & kMaterialMask, phase = byte & kMotionPhaseBit;
    int level = int((byte >> kMotionShift) & kMotionLevelMask);
    const std::uint32_t move = move_of(k);
    if (side != nullptr && (move == kRolled || move == kToppled) && mats.is_liquid(material)) {
      const int speed = momentum::speed_of(level > 0 ? motion_window(level) : 1, m.substeps);
      slid[k] = speed > 0 ? speed : 1;  // it moved: at least the lowest speed
    }
    flowed = flowed || (level > 0 && (move == kRolled || move == kToppled));
    const int draw = int((random >> (40 + 6 * k)) & 63u) * 4;
    if (move == kFell) {
      // Gravity accelerates a grain in free fall, in the first sub-step of its window: one with nothing
      // beside it in the top layer, or under MotionParams::columns every grain that fell.
      if (s == (phase ? 1 : 0) && (kColumns || (occupied & ~(1u << k)) == 0)) ++level;
    } else if (move == kToppled) {
      if (draw < int(mats.topple_gain[material])) ++level;
    } else if (level > 0 && draw < (move == kRolled ? int(mats.roll_cost[material]) : kStuckCost)) {
      --level;
    }
    if (move >= kFell && level > max_level) level = max_level;
    if ((move == kRolled || move == kToppled) && level > int(mats.flow_level[material]) &&
        !(kColumns && in_falling_body(mats, std::uint32_t(bytes >> (8 * k)) & 0xFFu)))
      level = mats.flow_level[material];
    // Under pressure a liquid that rolled or toppled moves over a surface: it joins its body at rest
    // (level 0), and the head moves it from there. One that falls out of its body (from a coarse cell
    // of a body into one outside any) leaves at least at the speed its head gives (Torricelli).
    if (heads != nullptr && (move == kRolled || move == kToppled) && mats.is_liquid(material)) level = 0;
    if (heads != nullptr && move == kFell && mats.is_liquid(material) && !head::outside_body(heads[4 + k]) &&
        head::outside_body(heads[k])) {
      const int exit = head::exit_level(heads[4 + k] - (z0 + 1) * head::kUnit, max_level);
      if (exit > level) level = exit;
    }
    const std::uint32_t updated = material | (std::uint32_t(level) << kMotionShift) | phase;
    new_top = (new_top & ~(0xFFu << (8 * k))) | (updated << (8 * k));
    if (kColumns && move == kFell) wakes_left |= (kWakeBit | (std::uint32_t(level) << kMotionShift)) << (8 * k);
  }
  std::uint64_t out = ByteOps::gather((bytes & 0xFFFFFFFFull) | (std::uint64_t(new_top) << 32), entry & 0x77777777u);
  if (side != nullptr) {
    *side = ByteOps::gather(*side, entry & 0x77777777u);
    // A liquid that rolled or toppled moves on sideways along its move.
    for (int p = 0; p < 8; ++p) {
      const int from = int((entry >> (4 * p)) & 7u);
      if (from < 4 || slid[from - 4] == 0) continue;
      std::uint32_t v = byte_at(*side, p);
      for (int axis = 0; axis < 2; ++axis)
        if (((p ^ from) >> axis) & 1)
          v = momentum::with_component(v, axis, (((p >> axis) & 1) != 0 ? 1 : -1) * slid[from - 4]);
      *side = with_byte(*side, p, v);
    }
  }
  if (flowed && mats.entrained != 0) out = entrain_step_edges<ByteOps>(out, codes, entry, random, mats);
  // The fluid pass, on a block holding a liquid, a gas or two granular materials.
  if (!mats.fluid_pass_applies(present_materials<ByteOps>(bytes))) return kColumns ? leave_wakes(out, wakes_left) : out;
  // Its movers: the cells that took part and kept their place (nibble p of the entry is p).
  std::uint32_t stayed = (entry & 0x77777777u) ^ kStillEntry;
  stayed = ~(stayed | (stayed >> 1) | (stayed >> 2)) & 0x11111111u;
  stayed = (stayed | (stayed >> 3)) & 0x03030303u;
  stayed = (stayed | (stayed >> 6)) & 0x000F000Fu;
  stayed = (stayed | (stayed >> 12)) & 0xFFu;
  std::uint32_t took_part = (part << 4) | gases;  // 1 in byte k for cell 4 + k, in byte j for cell j
  took_part = (took_part | (took_part >> 7) | (took_part >> 14) | (took_part >> 21)) & 0xFFu;
  const std::uint64_t draws = block_random_keyed(m.draw_key, m.step(), x0, y0, z0, m.origin);
  const std::uint64_t passed =
      fluid::fluid_pass<true>(out, took_part & stayed, symmetry, draws, mats, heads,
                              heads != nullptr ? pressed & stayed : 0u, z0, s, max_level, side,
                              side != nullptr ? gliders(out) & stayed : 0u, m.substeps);
  return kColumns ? leave_wakes(passed, wakes_left) : passed;
}

/// step_block_as with the lever chosen by m.columns.
template <class ByteOps = PortableByteOps, class Load>
constexpr std::uint64_t step_block(std::uint64_t bytes, const SubStep& m, int x0, int y0, int z0, Load load) {
  return m.columns ? step_block_as<true, ByteOps>(bytes, m, x0, y0, z0, load)
                   : step_block_as<false, ByteOps>(bytes, m, x0, y0, z0, load);
}

}  // namespace granular::motion
