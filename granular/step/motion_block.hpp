#pragma once
/// @file motion_block.hpp
/// One block of one sub-step of the motion model (granular/motion.hpp), as constexpr functions on
/// plain integers: the CPU kernels and the CUDA kernels (nvcc --expt-relaxed-constexpr) compile
/// this very code, which is what makes the two backends bit-identical.
///
/// A tick of a motion rule set runs MotionParams::substeps Margolus sub-steps. Sub-step s of tick
/// t uses the partition offset motion_offset(t, s): z flips every sub-step, and the sub-step in
/// which grains at rest take part (s = t & 1) walks all 8 offsets over 8 ticks, as the one-step
/// cycle does. Per block:
///  1. Each cell gets a code for the table from its material's behaviour (StepMaterials): void 0
///     (void and every gas), obstacle 1 (every static material), grain 2 (every granular and liquid
///     one: a faller). A faller in the top layer that is outside its window this sub-step (it is too slow
///     to move now) reads as an obstacle; one inside its window with a motion level above 0 reads,
///     with chance roll_chance / 256 (its material's GrainMotion), as a roller (3), which the table lets roll sideways onto the
///     top of a neighbour column one cell lower. Bottom-layer grains never move on their own, so
///     their code is always 2.
///  2. The key is viewed under the block's random symmetry, looked up in the motion table (motion_rule's
///     transitions at 2 bits per cell, kMotionTableKeys), and the permutation is mapped back: cell i
///     goes to position dest[i].
///  3. The 8 bytes are permuted with their motion levels, and each grain that took part updates
///     its level: one that fell straight down gains 1 in the first sub-step of its window when
///     nothing is beside it in the top layer (gravity accelerates free grains, not a dense flow);
///     one that toppled down a step gains 1 with chance topple_gain / 256; one that was blocked
///     from below loses 1 with chance roll_cost / 256 if it rolled, kStuckCost / 256 if its block
///     had no room. So a moving grain runs on down slopes steeper than the balance of gains and
///     costs and stops on shallower ones, whatever the pile's size: the friction lever.
///  4. On a block holding a liquid, a gas or two granular materials, the fluid pass
///     (fluid_block.hpp) moves what gravity and flow left: density order, liquid and gas spread. Its
///     movers are the fallers that took part and stayed, and in sub-steps 0 and 1 the bottom-layer
///     gases (a gas rises at most 2 cells per tick and has no motion state); its draws come from
///     block_random(seed ^ fluid::kDrawSalt, t * substeps + s, x0, y0, z0).
/// A grain's window is motion_window(level) sub-steps from its phase: in sub-step 0 every grain
/// notes its layer (top: phase 0, bottom: phase 1, where it is top one sub-step later), so a grain
/// starting from rest falls 1, 4, 9, ... cells after 1, 2, 3 ticks whichever layer it starts in,
/// and a grain at rest keeps the same phase tick after tick.
/// The random word is block_random(seed, t * substeps + s, x0, y0, z0); its low 3 bits pick the
/// symmetry, byte k (k = 1..4) the roll draw of top cell k + 3, and 6 bits from bit 40 + 6 (i - 4)
/// the level draw of top cell i (as a multiple of 4 out of 256).

#include <cstdint>

#include "granular/block.hpp"
#include "granular/motion.hpp"
#include "step/block_bytes.hpp"
#include "step/fluid_block.hpp"
#include "step/paper_rule.hpp"
#include "step/step_materials.hpp"

namespace granular::motion {

/// Chance out of 256 that a moving grain blocked from below with no room to roll in its block
/// loses a level (so a grain stuck in a pit comes to rest, and its brick can sleep).
inline constexpr int kStuckCost = 64;

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

/// The partition offset of sub-step `substep` of tick `tick` (see the file comment); with
/// `random_axis_order`, x and y are exchanged on the 8-tick cycles cycle_swaps_axes draws.
constexpr BlockOffset motion_offset(std::uint64_t tick, int substep, std::uint64_t seed, bool random_axis_order) {
  const std::uint64_t phase = tick + std::uint64_t(substep);
  BlockOffset o{int((phase >> 1) & 1u), int((phase >> 2) & 1u), substep & 1};
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
  bool random_symmetry = false; ///< draw a horizontal symmetry per block
  StepMaterials materials;      ///< the rule set's material table (codes, grains, grain motion)
};

/// The SubStep of sub-step `substep` of tick `tick` for a rule set's motion model.
constexpr SubStep sub_step(const MotionParams& motion, const StepMaterials& materials, std::uint64_t seed,
                           std::uint64_t tick, int substep, bool random_symmetry) {
  return SubStep{seed, tick, substep, motion.substeps, random_symmetry, materials};
}

/// The phase a grain in cell i of a block takes at sub-step 0, as its bit: 0 in the top layer (its
/// window starts at once), kMotionPhaseBit in the bottom layer (it is in a top layer from sub-step 1).
constexpr std::uint32_t rest_phase(int i) { return i >= 4 ? 0u : kMotionPhaseBit; }

/// The bytes with every grain's phase set as at sub-step 0 (rest_phase).
constexpr std::uint64_t with_phases(std::uint64_t bytes, const StepMaterials& materials) {
  std::uint64_t out = 0;
  for (int i = 0; i < 8; ++i) {
    std::uint32_t byte = std::uint32_t(bytes >> (8 * i)) & 0xFFu;
    if (materials.is_faller(byte & kMaterialMask)) byte = (byte & ~std::uint32_t(kMotionPhaseBit)) | rest_phase(i);
    out |= std::uint64_t(byte) << (8 * i);
  }
  return out;
}

/// The phase bits of a block whose cells are all grains at rest, at partition z offset `offset_z`
/// (rest_phase of each cell's layer at sub-step 0): set in the layer that is the bottom one there.
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
  // is the bottom one (rest_phase): this layer when offset_z is 0, else the other.
  const std::uint64_t bottom = rest_phase_bits(offset_z);
  all_at_rest = (bytes & (kEveryByte * std::uint64_t(kMotionLevelMask << kMotionShift))) == 0 &&
                (bytes & (kEveryByte * 0x80u)) == (grains & bottom);
  return key;
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

/// True when the top-layer cell i of a block has only void beside it in the top layer: a grain
/// there that falls is in free fall and gains speed, while one that moves down in contact with
/// others (a dense flow) does not.
constexpr bool laterally_free(std::uint64_t bytes, int i, const StepMaterials& materials) {
  for (int j = 4; j < 8; ++j)
    if (j != i && materials.code((bytes >> (8 * j)) & kMaterialMask) != kCodeVoid) return false;
  return true;
}

/// The block's 8 bytes (cell i in byte i) after sub-step `m` (see the file comment). `load(k)`
/// reads the motion table's entry of motion table key k (kMotionTableKeys; a plain read on the CPU,
/// a read-only cache load on a GPU).
template <class Load>
constexpr std::uint64_t step_block(std::uint64_t bytes, const SubStep& m, int x0, int y0, int z0, Load load) {
  const StepMaterials& mats = m.materials;
  const int s = m.substep;
  if (s == 0) bytes = with_phases(bytes, mats);
  // Which cells take part: top-layer fallers inside their window, and in sub-steps 0 and 1 bottom-
  // layer gases. Only they ever start a move or change, so a block without one is left as it is
  // before its random word is drawn.
  unsigned takes_part = 0;
  for (int i = 4; i < 8; ++i) {
    const std::uint32_t byte = std::uint32_t(bytes >> (8 * i)) & 0xFFu;
    if (!mats.is_faller(byte & kMaterialMask)) continue;
    const int level = int((byte >> kMotionShift) & kMotionLevelMask);
    const int start = (byte & kMotionPhaseBit) ? 1 : 0;
    if (s >= start && s - start < motion_window(level)) takes_part |= 1u << i;
  }
  unsigned gas_turn = 0;
  if (s < 2 && mats.gases != 0)
    for (int i = 0; i < 4; ++i)
      if (mats.is_gas(std::uint32_t(bytes >> (8 * i)) & kMaterialMask)) gas_turn |= 1u << i;
  if ((takes_part | gas_turn) == 0) return bytes;
  const std::uint64_t random = block_random(m.seed, m.tick * std::uint64_t(m.substeps) + std::uint64_t(s), x0, y0, z0);
  BlockKey key = 0;
  std::uint32_t present = 0;  // bit m for each material m in the block (the same after any permutation)
  for (int i = 0; i < 8; ++i) {
    const std::uint32_t byte = std::uint32_t(bytes >> (8 * i)) & 0xFFu;
    const std::uint32_t material = byte & kMaterialMask;
    present |= 1u << material;
    std::uint32_t code = mats.code(material);
    if (code == kCodeGrain && i >= 4) {
      // A top-layer grain outside its window is too slow to move now: an obstacle.
      if (((takes_part >> i) & 1u) == 0)
        code = kCodeObstacle;
      else if (((byte >> kMotionShift) & kMotionLevelMask) > 0 &&
               int((random >> (8 * (i - 3))) & 0xFFu) < int(mats.roll_chance[material]))
        code = kCodeRoller;
    }
    key |= code << (3 * i);
  }
  // The symmetry as arithmetic on cell indices (no arrays: a GPU keeps everything in registers).
  const int symmetry = m.random_symmetry ? int(random & 7u) : 0;
  std::uint32_t viewed = 0;  // the motion table key of the block in the drawn frame
  for (int i = 0; i < 8; ++i) viewed |= ((key >> (3 * i)) & 3u) << (2 * symmetry_image(i, symmetry));
  const Transition t = takes_part != 0 ? load(viewed) : kIdentityTransition;
  const int max_level = MotionParams{.substeps = m.substeps}.max_level();
  std::uint64_t out = 0;
  const bool fluid_pass = mats.fluid_pass_applies(present);
  const unsigned may_start = fluid_pass ? takes_part | gas_turn : 0u;
  unsigned movers = 0;  // who may start a move in the fluid pass: cells that took part and stayed
  for (int i = 0; i < 8; ++i) {
    const int dest = symmetry_preimage(destination(t, symmetry_image(i, symmetry)), symmetry);
    if (dest == i) movers |= may_start & (1u << i);
    std::uint32_t byte = std::uint32_t(bytes >> (8 * i)) & 0xFFu;
    if ((takes_part >> i) & 1u) {
      const std::uint32_t material = byte & kMaterialMask;
      int level = int((byte >> kMotionShift) & kMotionLevelMask);
      const std::uint32_t phase = byte & kMotionPhaseBit;
      const int draw = int((random >> (40 + 6 * (i - 4))) & 63u) * 4;
      if (dest < 4) {
        if ((dest & 3) == (i & 3)) {
          if (s == (phase ? 1 : 0) && laterally_free(bytes, i, mats)) ++level;
        } else if (draw < int(mats.topple_gain[material])) {
          ++level;
        }
        if (level > max_level) level = max_level;
      } else if (level > 0 && draw < (dest != i ? int(mats.roll_cost[material]) : kStuckCost)) {
        --level;
      }
      byte = material | (std::uint32_t(level) << kMotionShift) | phase;
    }
    out |= std::uint64_t(byte) << (8 * dest);
  }
  if (!fluid_pass) return out;
  const std::uint64_t draws =
      block_random(m.seed ^ fluid::kDrawSalt, m.tick * std::uint64_t(m.substeps) + std::uint64_t(s), x0, y0, z0);
  return fluid::fluid_pass<true>(out, movers, symmetry, draws, mats);
}

}  // namespace granular::motion
