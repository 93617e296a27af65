#pragma once
/// @file plain_step.hpp
/// The plain per-block loop: the reference the fast CPU step is tested against and the baseline it
/// is measured against. It steps every preset on a byte per cell written as the rules read, with
/// none of the CPU kernels' devices (no result table, no packed keys, no skipping): per block,
/// gather the 8 cells (outside ones read as solid and are never written), give each cell its
/// gravity-and-flow code (void and gas 0, static 1, granular and liquid 2), look the transition of
/// those codes up in the Lut and scatter the cells by it, then run the fluid pass (liquids and
/// gases, fluid_block.hpp's file comment) on the block as a loop over arrays of cells, under the
/// block's random symmetry when the rule set draws one. With the motion model (motion.hpp) each
/// tick is MotionParams::substeps such passes, and each faller carries its motion level and phase.
///
/// The fluid pass here is a second implementation of the comment of granular/step/fluid_block.hpp,
/// written from the text, not from the code: it shares nothing with fluid::fluid_pass but the
/// random word block_random. Its readings of what the text leaves open are listed at
/// plain_fluid_pass.

#include <array>
#include <cstdint>
#include <span>

#include "granular/extend/block.hpp"
#include "granular/geometry.hpp"
#include "granular/extend/lut.hpp"
#include "granular/motion.hpp"
#include "granular/rule_set.hpp"

namespace granular::reference {

/// What the plain loop reads of one material (a row of RuleSet::materials).
struct PlainMaterial {
  Behaviour behaviour = Behaviour::Static;  ///< how the step treats it
  int density = 0;      ///< MaterialDef::density (void 0)
  int spread = 0;       ///< MaterialDef::spread, out of 256
  int topple_gain = 0;  ///< out of 256: chance that a faller toppling down a step gains a level
  int roll_cost = 0;    ///< out of 256: chance that a roll costs a level
  int roll_chance = 0;  ///< out of 256: chance that a moving faller blocked from below may roll
  int entrain = 0;      ///< out of 256: chance that a moving grain's roll or topple sets a grain at rest
                        ///< on a step edge of its block moving
  int flow_level = 0;   ///< the highest level a grain keeps after a roll or topple (0: no limit)
};

/// What the plain loop reads of a world: its table, the rule set's random variants, the motion
/// model's sub-steps, the material table, and the seed of its random draws.
struct PlainRules {
  const Lut* lut = nullptr;        ///< the transition table of the rule set
  bool random_symmetry = false;    ///< draw a horizontal symmetry per block (RuleSet::random_symmetry)
  bool random_axis_order = false;  ///< draw the offset order per cycle (RuleSet::random_axis_order)
  int substeps = 1;                ///< Margolus sub-steps per tick; above 1 the motion model is on
  bool columns = false;            ///< MotionParams::columns: wakes, followers, falling layers accelerate
  std::array<PlainMaterial, kMaterialCount> materials{};  ///< per state
  /// Without a motion model the Lut is indexed by materials: the state it is asked for in place of
  /// each gravity-and-flow code 0, 1, 2 (void, the first static and the first granular material),
  /// so that only gravity and flow are read from it, never its own fluid pass.
  std::array<std::uint8_t, 3> code_state{0, 1, 2};
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

/// Salt of the fluid pass's draws: block_random(seed ^ salt, step, x0, y0, z0) (fluid::kDrawSalt,
/// written out: the ASCII of "FluidDra").
inline constexpr std::uint64_t kPlainFluidDrawSalt = 0x466C756964447261ull;

/// The fluid pass on one block (cells in block order, cell i at block position i), as
/// fluid_block.hpp's comment specifies it: `mover[i]` says whether the cell at i takes part (may
/// start a move), `symmetry` is the block's horizontal symmetry (the pass runs in the frame where
/// cell i sits at horizontal_symmetry(symmetry)[i]), and byte i of `draws` is the chance draw of
/// block position i. With `levels`, bits 3..6 of a faller's byte are its motion level (a faller
/// that sinks drops to 0); without (the one-step rules) cells carry no level.
///
/// Readings of what the text leaves open:
///  * Columns are visited in the viewed frame's order 0..3 within each step, and the steps follow
///    one another over the whole block: step 1 (density) for every column, then the topple of a
///    faller that did not sink (1b) for every column, then 2, then 3 for every column, then 4.
///  * "A cell moves at most once per pass": a cell that has moved (started a move or been
///    exchanged by one) neither starts a move nor is exchanged again.
///  * 1b: "diagonally down" is the bottom cell of any other column, tried in the liquid spread's
///    order (x neighbour, y neighbour, diagonal); a void target under void is left to the first
///    pass's topple ("through water instead of void"); the faller that topples drops to level 0,
///    as one that sinks does (it moves through something denser than void).
///  * Without motion levels, two granular materials never pass each other (no level is above 0),
///    while a liquid taking part counts as moving in the liquid spread (it takes part at every
///    tick): the one-step rules' reading of "while it moves".
///  * The gas spread and the gas around a ceiling try the other columns in the liquid spread's
///    order; the gas around a ceiling takes no chance draw.
BlockCells plain_fluid_pass(const PlainRules& rules, const BlockCells& cells, const std::array<bool, 8>& mover,
                            int symmetry, std::uint64_t draws, bool levels);

/// One tick `tick` of the plain loop over the whole grid `cells` (x fastest, `size` extent), split
/// over `threads` std::threads by block layers (the result does not depend on `threads`).
void plain_step(std::span<std::uint8_t> cells, Int3 size, const PlainRules& rules, std::uint64_t tick,
                int threads = 1);

/// Ticks first_tick .. first_tick + ticks - 1 of the plain loop, in order.
void plain_run(std::span<std::uint8_t> cells, Int3 size, const PlainRules& rules, std::uint64_t first_tick, int ticks,
               int threads = 1);

}  // namespace granular::reference
