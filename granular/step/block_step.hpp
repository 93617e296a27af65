#pragma once
/// @file block_step.hpp
/// The one block step: what a block's 8 cell bytes become in one (sub-)step, for every backend and
/// every path (CPU dense and sparse, CUDA dense, fused pair, recording and sparse kernels). Each path
/// walks its blocks its own way and asks a Rule for each block; the Rule is one of two policies:
///  * OneStepRule: a rule set without a motion model. The bytes hold materials only; the block's key
///    is looked up in the result table (per key, the key after its transition), under the block's
///    random symmetry when the rule set draws one.
///  * MotionRule: one sub-step of the motion model (motion_block.hpp, motion::step_block).
/// Both take a Platform policy for what differs between host and device: how a table entry is read
/// (a plain load, or a read-only cache load), how a key is viewed under a symmetry (byte tables on
/// the CPU, a per-cell loop on a GPU). Everything else is plain constexpr integer arithmetic
/// compiled by the host compiler and by nvcc (--expt-relaxed-constexpr), which is what makes every
/// path bit-identical.
///
/// A Rule also says what sparse stepping needs: quiet() (the block cannot keep its brick awake,
/// inert_keys.hpp) and steps_uniform() (a block of 8 equal bytes may change; a path may skip such a
/// block only when it says no). StepRules holds what every Rule is made from, and with_rule builds
/// the Rule of one (sub-)step and hands it to the path.

#include <cstdint>
#include <type_traits>

#include "granular/extend/block.hpp"
#include "granular/geometry.hpp"
#include "granular/motion.hpp"
#include "step/block_bytes.hpp"
#include "step/carried_cells.hpp"
#include "step/fluid_block.hpp"
#include "step/head_field.hpp"
#include "step/inert_keys.hpp"
#include "step/motion_block.hpp"
#include "step/step_materials.hpp"

namespace granular {

/// Everything the Rules of a world's (sub-)steps are made from (the tables live where the backend
/// keeps them: host memory for the CPU, device memory for a GPU).
struct StepRules {
  const BlockKey* result = nullptr;        ///< per key, the key after its transition (one-step rules)
  const motion::MotionEntry* transitions = nullptr; ///< the motion entries (motion model only, motion_table.hpp)
  const std::uint64_t* inert = nullptr;    ///< inert-key bits (sparse stepping with random variants)
  std::uint64_t seed = 0;                  ///< world seed
  bool random_symmetry = false;            ///< RuleSet::random_symmetry
  bool random_axis_order = false;          ///< RuleSet::random_axis_order
  MotionParams motion;                     ///< RuleSet::motion
  StepMaterials materials;                 ///< RuleSet::materials as the step reads it
  std::uint64_t origin = 0;                ///< block_position_offset of WorldDef::domain_origin
  const std::int32_t* heads = nullptr;     ///< the head field (MotionParams::pressure, head_field.hpp), where
                                           ///< the backend keeps it; null while the grid holds no liquid
                                           ///< (the Rules without pressure step such a grid the same)
  Int3 grid{};                             ///< the grid's extent (the head field's coarse cells follow from it)
  bool side = false;                       ///< the path carries a side plane (MotionParams::momentum, momentum.hpp):
                                           ///< set with heads, while the grid holds liquid
};

/// The byte operations of a Platform: its own (Platform::ByteOps, e.g. a GPU's byte permute), or
/// the portable ones (PortableByteOps); both give the same bytes.
template <class Platform>
struct PlatformByteOps {
  using type = PortableByteOps;  ///< the portable ones
};

/// A Platform that brings its own byte operations.
template <class Platform>
  requires requires { typename Platform::ByteOps; }
struct PlatformByteOps<Platform> {
  using type = typename Platform::ByteOps;  ///< the Platform's own
};

/// The byte operations the block step uses on `Platform`.
template <class Platform>
using ByteOpsOf = typename PlatformByteOps<Platform>::type;

/// A rule set without a motion model, for one tick.
template <bool kRandom, class Platform>
struct OneStepRule {
  const BlockKey* result;       ///< per key, the key after its transition
  const std::uint64_t* inert;   ///< inert-key bits (kRandom with sparse stepping)
  std::uint64_t seed;           ///< world seed
  std::uint64_t tick;           ///< the tick
  BlockOffset offset;           ///< the tick's partition offset
  std::uint32_t outside;        ///< the state a cell outside the grid reads as
  std::uint64_t origin;         ///< block_position_offset of the world's domain origin

  /// No motion model.
  static constexpr bool kMotion = false;
  /// No side plane: a path calls step(bytes, ...).
  static constexpr bool kStepsSide = false;
  /// Cell bytes hold materials only.
  static constexpr std::uint64_t kCellMask = 7 * kEveryByte;

  /// A block of 8 equal bytes never changes: every permutation of it is itself.
  constexpr bool steps_uniform(std::uint32_t) const { return false; }

  /// No motion windows, so no brick reach (brick_reach.hpp): sparse stepping walks every awake brick.
  static constexpr bool kReach = false;

  /// The key of the block at (x0, y0, z0) after the tick (`key` its key now).
  constexpr BlockKey next_key(BlockKey key, int x0, int y0, int z0) const {
    if constexpr (kRandom) {
      const int s = int(block_random_keyed(block_seed_key(seed), tick, x0, y0, z0, origin) & 7u);
      return Platform::unview(Platform::load(result + Platform::view(key, s)), s);
    } else {
      return Platform::load(result + key);
    }
  }

  /// The block's bytes after the tick.
  constexpr std::uint64_t step(std::uint64_t bytes, int x0, int y0, int z0) const {
    return unpack_key(next_key(pack_key(bytes), x0, y0, z0));
  }

  /// True when no variant of the rule changes the block (`before`, `after` the tick): then it
  /// cannot keep its brick awake. Without random variants, iff the rule left it as it was.
  constexpr bool quiet(std::uint64_t before, std::uint64_t after) const {
    if constexpr (kRandom)
      return is_inert(inert, pack_key(before));
    else
      return before == after;
  }
};

/// One sub-step of a rule set's motion model; `kColumns` is its MotionParams::columns, `kPressure`
/// its MotionParams::pressure, `kSide` its MotionParams::momentum (with kPressure): the Rule steps a
/// block's side bytes (momentum.hpp) with its cell bytes.
template <class Platform, bool kColumns, bool kPressure = false, bool kSide = false>
struct MotionRule {
  const motion::MotionEntry* table;///< the motion entries (motion_table.hpp)
  const std::uint64_t* inert;   ///< inert-key bits (sparse stepping)
  motion::SubStep sub;          ///< seed, tick, sub-step, materials
  BlockOffset offset;           ///< the sub-step's partition offset
  std::uint32_t outside;        ///< the state a cell outside the grid reads as
  std::uint64_t resting_grains;  ///< the bytes of a block full of the table's first granular material
                                 ///< at rest at this offset (rest_block); quiet at once
  const std::int32_t* heads;    ///< the head field (kPressure)
  Int3 grid;                    ///< the grid's extent (kPressure)

  /// The motion model.
  static constexpr bool kMotion = true;
  /// The Rule steps a side plane with the cells: a path calls step(bytes, side, ...).
  static constexpr bool kStepsSide = kSide;
  /// Cell bytes hold a grain's motion state above its material.
  static constexpr std::uint64_t kCellMask = ~std::uint64_t(0);

  /// A block of 8 equal faller bytes (granular or liquid) may change (sub-step 0 sets the phases of its
  /// two layers apart), and so may one of wakes (they are cleared); one of any other material never
  /// does (a gas has no denser fluid to pass).
  /// Under MotionParams::trains a block of 8 carried grains never changes (the block step reads them
  /// as a static material) and one of 8 swept voids is stepped, which keeps its brick awake
  /// (carried_cells.hpp).
  constexpr bool steps_uniform(std::uint32_t byte) const {
    if (hides()) {
      if (carried::is_carried(sub.materials, std::uint8_t(byte))) return false;
      if (carried::is_swept(sub.materials, std::uint8_t(byte))) return true;
    }
    return sub.materials.is_faller(byte & kMaterialMask) || (kColumns && is_wake(std::uint8_t(byte)));
  }

  /// True when carried trains may hide cells from the block step (MotionParams::trains).
  constexpr bool hides() const { return kColumns && sub.trains; }

  /// 0xFF in each byte of `bytes` the block step reads as a static material (carried_cells.hpp).
  constexpr std::uint64_t hidden(std::uint64_t bytes) const { return hides() ? carried::hidden_mask(bytes) : 0u; }

  /// Bricks keep a reach (brick_reach.hpp): a sub-step leaves out a brick near which nothing can move.
  static constexpr bool kReach = true;

  /// What a block stepped in this sub-step (`before`, `after`) adds to its owner brick's reach
  /// (motion::reach_of): every block in sub-steps 0 and 1, where every brick is stepped, and later a
  /// block that changed (a faller that did not move, and whose level did not change, is counted already).
  /// Under pressure a block holding a liquid adds 31: the pressure stage moves liquids at rest in
  /// every sub-step, so the bricks around them never idle.
  constexpr std::uint32_t reach_added(std::uint64_t before, std::uint64_t after) const {
    if (sub.substep >= 2 && before == after) return 0u;
    if (const std::uint64_t mask = hidden(after); mask != 0) after = carried::hide(after, mask, sub.materials);
    // Under pressure a liquid at rest may move in any sub-step: its brick and their neighbours step in all.
    if (kPressure && (present_materials<ByteOpsOf<Platform>>(after) & sub.materials.liquids) != 0) return 31u;
    return motion::reach_of(after, kColumns);
  }

  /// True in a sub-step where a brick may be idle (from sub-step 2 on: every brick steps in 0 and 1).
  constexpr bool may_idle() const { return sub.substep >= 2; }

  /// True when the sub-step leaves every block of a brick as it is, `nearby` being the largest reach
  /// of the brick and its 26 neighbours (brick_reach.hpp).
  constexpr bool idle(std::uint32_t nearby) const { return may_idle() && nearby < std::uint32_t(sub.substep) + 2u; }

  /// True in the tick's first sub-step, where each stepped brick's reach starts anew.
  constexpr bool reach_restarts() const { return sub.substep == 0; }

  /// The block's bytes after the sub-step. After sub-step 1 only a top-layer grain at a motion level
  /// of 2 or more takes part (motion_window), or one over a wake, so a block without either is left
  /// at once.
  constexpr std::uint64_t step(std::uint64_t bytes, int x0, int y0, int z0) const {
    std::uint64_t none = 0;
    return step(bytes, none, x0, y0, z0);
  }

  /// The block's bytes after the sub-step, and (kSide) its side bytes `side` with them. Hidden cells
  /// (carried_cells.hpp) are stepped as a static material (carried::hide_for_step) and keep their bytes.
  constexpr std::uint64_t step(std::uint64_t bytes, std::uint64_t& side, int x0, int y0, int z0) const {
    const std::uint64_t mask = hidden(bytes);
    if (mask == 0) return step_seen(bytes, side, x0, y0, z0);
    const std::uint64_t after = step_seen(carried::hide_for_step(bytes, mask, sub.materials), side, x0, y0, z0);
    return (after & ~mask) | (bytes & mask);
  }

  /// step() of a block whose hidden cells read as a static material.
  constexpr std::uint64_t step_seen(std::uint64_t bytes, std::uint64_t& side, int x0, int y0, int z0) const {
    if (sub.substep >= 2 && ((bytes >> 32) & 0x70707070u) == 0 &&
        (!kColumns || motion::wake_bytes(bytes & 0xFFFFFFFFull) == 0) &&
        (!kPressure || (present_materials<ByteOpsOf<Platform>>(bytes) & sub.materials.liquids) == 0))
      return bytes;
    const auto load = [this](std::uint32_t k) { return Platform::load(table + k); };
    if constexpr (kPressure) {
      if ((present_materials<ByteOpsOf<Platform>>(bytes) & sub.materials.liquids) != 0) {
        std::int32_t block_heads[8];
        block_heads_at(x0, y0, z0, block_heads);
        return motion::step_block_as<kColumns, ByteOpsOf<Platform>>(bytes, sub, x0, y0, z0, load, block_heads,
                                                                    kSide ? &side : nullptr);
      }
    }
    return motion::step_block_as<kColumns, ByteOpsOf<Platform>>(bytes, sub, x0, y0, z0, load);
  }

  /// The head of each cell of the block at (x0, y0, z0) by block position (head::kDry outside the grid).
  constexpr void block_heads_at(int x0, int y0, int z0, std::int32_t* out) const {
    const Int3 coarse = head::coarse_size(grid);
    for (int p = 0; p < 8; ++p) {
      const int x = x0 + (p & 1), y = y0 + ((p >> 1) & 1), z = z0 + (p >> 2);
      const bool inside = x >= 0 && y >= 0 && z >= 0 && x < grid.x && y < grid.y && z < grid.z;
      out[p] = inside ? Platform::load(heads + head::coarse_of_cell(coarse, x, y, z)) : head::kDry;
    }
  }

  /// True when the block stays as it is in every sub-step whatever the draws (motion::rest_key, and
  /// fluid::may_move for its liquids and gases): then it cannot keep its brick awake. A block that
  /// changed in this sub-step (`after`) is not.
  constexpr bool quiet(std::uint64_t before, std::uint64_t after) const {
    if (before != after) return false;
    if (before == resting_grains) return true;  // the inside of a heap: the commonest quiet block
    if (const std::uint64_t mask = hidden(before); mask != 0) {
      if (carried::carried_unsettled(before, mask, sub.materials)) return false;
      before = carried::hide(before, mask, sub.materials);
    }
    bool at_rest = false;
    const BlockKey key = motion::rest_key(before, offset.z, sub.materials, at_rest);
    if (!at_rest || !is_inert(inert, key)) return false;
    const StepMaterials& mats = sub.materials;
    return !mats.fluid_pass_applies(present_materials<ByteOpsOf<Platform>>(before)) || !fluid::may_move(before, mats);
  }
};

/// Steps are numbered across ticks: step n is sub-step n % substeps of tick n / substeps (without a
/// motion model, tick n). The sparse cycle of 8 steps ends after every step n with n % 8 == 7.
constexpr int substeps_of(const StepRules& r) { return r.motion.enabled() ? r.motion.substeps : 1; }

/// The partition offset of step `n`.
constexpr BlockOffset step_offset(const StepRules& r, std::uint64_t n) {
  if (!r.motion.enabled()) return block_offset(n, r.seed, r.random_axis_order);
  const int substeps = r.motion.substeps;
  return motion::motion_offset(n / std::uint64_t(substeps), int(n % std::uint64_t(substeps)), r.seed,
                               r.random_axis_order, r.motion.momentum);
}

/// The partition offset of sub-step `substep` of tick `tick` (substep 0 without a motion model).
constexpr BlockOffset step_offset(const StepRules& r, std::uint64_t tick, int substep) {
  return step_offset(r, tick * std::uint64_t(substeps_of(r)) + std::uint64_t(substep));
}

/// The Rule of step `n` of type `Rule` (the type with_step picks for `r`).
template <class Rule>
constexpr Rule make_rule(const StepRules& r, std::uint64_t n) {
  const BlockOffset offset = step_offset(r, n);
  if constexpr (Rule::kMotion) {
    const int substeps = r.motion.substeps;
    return Rule{r.transitions, r.inert,
                motion::sub_step(r.motion, r.materials, r.seed, n / std::uint64_t(substeps), int(n % std::uint64_t(substeps)),
                                 r.random_symmetry, r.origin),
                offset, r.materials.outside, motion::rest_block(r.materials, offset.z), r.heads, r.grid};
  } else {
    return Rule{r.result, r.inert, r.seed, n, offset, r.materials.outside, r.origin};
  }
}

/// Calls fn(type_tag) with a value of the Rule type of `r`'s steps: one instantiation of the
/// caller's path per Rule type.
template <class Platform, class Fn>
constexpr void with_rule_type(const StepRules& r, Fn&& fn) {
  const bool pressure = r.motion.enabled() && r.motion.pressure && r.heads != nullptr;
  if (pressure && r.side && r.motion.columns)
    fn(static_cast<MotionRule<Platform, true, true, true>*>(nullptr));
  else if (pressure && r.side)
    fn(static_cast<MotionRule<Platform, false, true, true>*>(nullptr));
  else if (pressure && r.motion.columns)
    fn(static_cast<MotionRule<Platform, true, true>*>(nullptr));
  else if (pressure)
    fn(static_cast<MotionRule<Platform, false, true>*>(nullptr));
  else if (r.motion.enabled() && r.motion.columns)
    fn(static_cast<MotionRule<Platform, true>*>(nullptr));
  else if (r.motion.enabled())
    fn(static_cast<MotionRule<Platform, false>*>(nullptr));
  else if (r.random_symmetry)
    fn(static_cast<OneStepRule<true, Platform>*>(nullptr));
  else
    fn(static_cast<OneStepRule<false, Platform>*>(nullptr));
}

/// Builds the Rule of step `n` and calls fn(rule).
template <class Platform, class Fn>
constexpr void with_step(const StepRules& r, std::uint64_t n, Fn&& fn) {
  with_rule_type<Platform>(r, [&](auto* tag) { fn(make_rule<std::remove_pointer_t<decltype(tag)>>(r, n)); });
}

/// Builds the Rules of steps `n` and `n + 1` and calls fn(first, second).
template <class Platform, class Fn>
constexpr void with_step_pair(const StepRules& r, std::uint64_t n, Fn&& fn) {
  with_rule_type<Platform>(r, [&](auto* tag) {
    using Rule = std::remove_pointer_t<decltype(tag)>;
    fn(make_rule<Rule>(r, n), make_rule<Rule>(r, n + 1));
  });
}

/// Builds the Rule of sub-step `substep` of tick `tick` (substep 0 without a motion model) and calls
/// fn(rule).
template <class Platform, class Fn>
constexpr void with_rule(const StepRules& r, std::uint64_t tick, int substep, Fn&& fn) {
  with_step<Platform>(r, tick * std::uint64_t(substeps_of(r)) + std::uint64_t(substep), fn);
}

}  // namespace granular
