#pragma once
/// @file plain_step.hpp
/// The plain per-block loop: the reference the fast CPU step is tested against and the baseline it
/// is measured against. It steps every preset on a byte per cell written as the rules read, with
/// none of the CPU kernels' devices (no result table, no packed keys, no skipping): per block,
/// gather the 8 cells (outside ones read as solid and are never written), build the key, look the
/// transition up in the Lut, and scatter the cells by the permutation, under the block's random
/// symmetry when the rule set draws one. With the motion model (motion.hpp) each tick is
/// MotionParams::substeps such passes, and each cell carries its motion level and phase.

#include <cstdint>
#include <span>

#include "granular/block.hpp"
#include "granular/geometry.hpp"
#include "granular/lut.hpp"
#include "granular/motion.hpp"
#include "granular/rule_set.hpp"

namespace granular::reference {

/// What the plain loop reads of a world: its table, the rule set's random variants, the motion
/// model's parameters (those of the granular material), and the seed of its random draws.
struct PlainRules {
  const Lut* lut = nullptr;        ///< the transition table of the rule set
  bool random_symmetry = false;    ///< draw a horizontal symmetry per block (RuleSet::random_symmetry)
  bool random_axis_order = false;  ///< draw the offset order per cycle (RuleSet::random_axis_order)
  int substeps = 1;                ///< Margolus sub-steps per tick; above 1 the motion model is on
  int topple_gain = 0;             ///< out of 256: chance that a grain toppling down a step gains a level
  int roll_cost = 0;               ///< out of 256: chance that a roll costs a level
  int roll_chance = 0;             ///< out of 256: chance that a moving grain blocked from below may roll
  std::uint64_t seed = 0;          ///< WorldDef::seed
  /// True when the motion model is on.
  bool motion() const { return substeps > 1; }
};

/// The PlainRules of a world with rule set `rules`, table `lut` (which must outlive the result) and
/// `seed`: the only place that knows where a RuleSet keeps what the plain loop reads.
PlainRules plain_rules(const RuleSet& rules, const Lut& lut, std::uint64_t seed);

/// Chance out of 256 that a moving grain blocked from below with no room in its block loses a
/// level (the motion model's cost of being stuck).
inline constexpr int kPlainStuckCost = 64;

/// One tick `tick` of the plain loop over the whole grid `cells` (x fastest, `size` extent), split
/// over `threads` std::threads by block layers (the result does not depend on `threads`).
void plain_step(std::span<std::uint8_t> cells, Int3 size, const PlainRules& rules, std::uint64_t tick,
                int threads = 1);

/// Ticks first_tick .. first_tick + ticks - 1 of the plain loop, in order.
void plain_run(std::span<std::uint8_t> cells, Int3 size, const PlainRules& rules, std::uint64_t first_tick, int ticks,
               int threads = 1);

}  // namespace granular::reference
