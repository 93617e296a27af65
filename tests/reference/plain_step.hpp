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
///
/// Under MotionParams::pressure each tick starts with the head field (plain_heads, a second
/// implementation of granular/step/head_field.hpp) solved from the cells at the start of the tick,
/// and the fluid pass of every sub-step ends with the pressure stage (PlainPressure). In the first
/// pass of a sub-step under pressure, a liquid that rolls or topples takes level 0 (it joins its body
/// at rest), and one that falls straight down from a coarse cell inside a body into one outside any
/// takes at least the level of its exit speed: floor(sqrt(e)) + 1 (at most the top level), e the
/// head of its own coarse cell above the top of the cell it falls into, in cells.
///
/// Under MotionParams::momentum every cell carries a side byte (a liquid's sideways velocity, from
/// granular/step/momentum.hpp's and fluid_block.hpp's comments): the first pass moves it with its
/// cell; a liquid that rolls or topples takes, along each axis its move crosses, the velocity of its
/// level before the move (motion_window(level) cells a tick, 1 at level 0) in the move's direction;
/// every liquid with a velocity that kept its place in the first pass is a glider of the fluid pass
/// (PlainMomentum), and a block with one is stepped even when nothing else in it takes part.

#include <array>
#include <climits>
#include <cstdint>
#include <span>
#include <vector>

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
  bool trains = false;             ///< MotionParams::trains: fast grains wait behind grains falling as fast,
                                   ///< and every tick each column's falling trains close their gaps
  bool pressure = false;           ///< MotionParams::pressure: a head per coarse cell moves liquids at rest
  bool momentum = false;           ///< MotionParams::momentum: liquids carry a sideways velocity in a side plane
  bool shallow = false;            ///< MotionParams::shallow: after each tick, open liquid moves as shallow water
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

/// The lowest level of a granular grain that falls rather than flows under columns: a grain that
/// rolls or topples over one this fast keeps its level (no flow level), and a train whose first grain
/// is this fast over a tick's travel of void is airborne.
inline constexpr int kPlainFallingBodyLevel = 2;

/// Salt of the fluid pass's draws: block_random(seed ^ salt, step, x0, y0, z0) (fluid::kDrawSalt,
/// written out: the ASCII of "FluidDra").
inline constexpr std::uint64_t kPlainFluidDrawSalt = 0x466C756964447261ull;

/// Head units per cell of height (head::kUnit, written out).
inline constexpr std::int32_t kPlainHeadUnit = 1024;
/// The head of a coarse cell without liquid at rest (head::kDry, written out).
inline constexpr std::int32_t kPlainDry = INT32_MIN;
/// The seed of a coarse cell whose liquid at rest has no free surface (head::kSunk, written out).
inline constexpr std::int32_t kPlainSunk = -(1 << 30);
/// Rounds of the head solve through the liquid, each a sweep along +x, -x, +y, -y, +z, -z
/// (head::kSweepRounds).
inline constexpr int kPlainSweepRounds = 3;
/// Rounds of the head solve out into the dry coarse cells, each a sweep along +x, -x, +y, -y, +z
/// (head::kDryRounds).
inline constexpr int kPlainDryRounds = 2;
/// Head units a step between two joined coarse cells costs (head::kWetStep).
inline constexpr std::int32_t kPlainWetStep = 2;
/// Head units a step into a dry coarse cell costs (head::kDryStep: a quarter cell).
inline constexpr std::int32_t kPlainDryStep = 256;

/// True when a head of plain_heads lies outside any body: kPlainDry, or carried out of a body (odd).
constexpr bool plain_outside_body(std::int32_t h) { return h == kPlainDry || h % 2 != 0; }

/// The head field of `cells` (x fastest, `size` extent) under `rules`, as head_field.hpp's comment
/// and CpuHeadField::solve specify it: one head per coarse cell of 2 x 2 x 2 cells (coarse cell
/// (i, j, k) at index i + cx (j + cy k), cx = (size.x + 1) / 2, ...). A cell belongs to the body when
/// it is a liquid at motion level 0 on the grid's floor or on a cell that is neither a void nor a
/// gas. A coarse cell without such a cell is kPlainDry; one with some starts at the highest z + 1
/// (in kPlainHeadUnit) of its body cells with a void or a gas above them inside the grid, or at
/// kPlainSunk when none has. Two face-neighbouring coarse cells are joined when a body cell on one
/// side of their common face has a body cell across it. kPlainSweepRounds rounds of six sweeps then
/// carry each head to the joined neighbour less kPlainWetStep when that is higher, each sweep one
/// sequential walk along every line of coarse cells in its direction. kPlainDryRounds rounds of five
/// sweeps (no -z) follow: a coarse cell outside any body (plain_outside_body) takes the head of the
/// one before it on the walk, with its lowest bit cleared, less kPlainDryStep and made odd, when
/// that is higher; a head at or below kPlainSunk carries nothing, and a body's head never changes.
std::vector<std::int32_t> plain_heads(std::span<const std::uint8_t> cells, Int3 size, const PlainRules& rules);

/// What the pressure stage of the fluid pass (stage 5 of fluid_block.hpp's comment) reads of a block.
struct PlainPressure {
  std::array<std::int32_t, 8> heads{};  ///< by block position: the head of the cell's coarse cell
                                        ///< (kPlainDry outside the grid)
  std::array<bool, 8> movers{};         ///< by block position: may start a pressure move
  int z0 = 0;                           ///< the block's lowest z
  int substep = 0;                      ///< the sub-step (the pushes' gates)
  int max_level = 0;                    ///< the motion model's top level (a pushed-out liquid's cap)
};

/// What the momentum stages of the fluid pass (fluid_block.hpp's comment, stage 6 and the velocities
/// of stages 2 and 5) read and write of a block under MotionParams::momentum.
struct PlainMomentum {
  std::array<std::uint8_t, 8> side{};  ///< by block position: the cell's velocity (x in bits 0..3, y in
                                       ///< bits 4..7, signed nibbles -7..7); moves with the cell
  std::array<bool, 8> gliders{};       ///< by block position: a liquid with a velocity that kept its place
  int substep = 0;                     ///< the sub-step (a speed's window)
  int substeps = 0;                    ///< sub-steps per tick
};

/// The largest speed of a velocity component (momentum::kTopSpeed, written out).
inline constexpr int kPlainTopSpeed = 7;
/// Chance out of 256 that a velocity handed on to a liquid ahead loses a unit (momentum::kHandOnLoss).
inline constexpr int kPlainHandOnLoss = 32;

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
/// With `pressure` (MotionParams::pressure), stage 5 follows, as fluid::fluid_pass gives it: each
/// void or gas cell that has not moved, in the viewed frame's order, takes the liquid denser than
/// it that has not moved, may start a pressure move, and stands beside it (x, then y neighbour),
/// below it, or above it, whose head is the highest one above the cell's top ((z + 1)
/// kPlainHeadUnit) among those the sub-step's gate lets push (sub-step s < 4 sqrt(e) up or down,
/// < 6 sqrt(e) sideways, e the excess head in cells; the first in that order on a tie). A top cell
/// over a void or a gas gives its liquid only to the cell under it. A liquid above a cell whose
/// coarse cell is inside a body (not plain_outside_body) pushes down into it only when its head is
/// higher than that cell's. A liquid pushed down into a cell outside any body takes the level
/// floor(sqrt(e)) + 1 (at most max_level); any other keeps its level.
/// With `momentum` (MotionParams::momentum), every exchange carries the two cells' velocities with
/// them; a liquid the liquid spread moves gains a unit along each axis of its move (a component of
/// the other sign, or 0, becomes one unit along the move); one the pressure stage pushes sideways
/// gets the velocity 2 floor(sqrt(e)) + 1 cells a tick along the push (speed: that times 7 /
/// (substeps / 2), rounded, at most 7) and 0 across it; then stage 6: each glider that has not
/// moved, in the viewed frame's order, tries its x component, then its y component (axes of the
/// block, not of the viewed frame): a component whose sign points out of the block, or outside its
/// window (sub-step s with 7 s >= |v| substeps), is passed over; the neighbour along it, if it has
/// not moved, is taken when it is a fluid lighter than the glider (an exchange), handed the velocity
/// when it is a liquid (the two cells swap velocities and both count as moved; the handed one
/// loses a unit towards 0 when the neighbour's draw is below kPlainHandOnLoss), and otherwise (a
/// static cell or a grain) the component becomes 0.
BlockCells plain_fluid_pass(const PlainRules& rules, const BlockCells& cells, const std::array<bool, 8>& mover,
                            int symmetry, std::uint64_t draws, bool levels, const PlainPressure* pressure = nullptr,
                            PlainMomentum* momentum = nullptr);

/// The shallow-water pass of MotionParams::shallow over `cells` (x fastest, `size` extent), as
/// granular/step/shallow_water.hpp's comment gives it, with the face plane `faces` (4 size.x size.y
/// values: the x faces' velocities, the y faces', the x faces' fractions, the y faces'; x fastest),
/// which it updates. Written from that comment and the constants' documentation, with the pass's
/// integer formulas written out: every iteration finds each column's ground and body by walking
/// it, and every move walks the donor and the receiver from their ground for the top of their body.
/// Its readings of the text: a face's upstream face is the face of the same axis behind it along
/// its velocity (after gravity), and it counts only when it moves the same way; the depth a face
/// rubs on is its upwind depth in whole cells, at least 1.
void plain_shallow_pass(std::span<std::uint8_t> cells, Int3 size, const PlainRules& rules, std::span<std::int32_t> faces);

/// One tick `tick` of the plain loop over the whole grid `cells` (x fastest, `size` extent), split
/// over `threads` std::threads by block layers (the result does not depend on `threads`). Under
/// MotionParams::momentum `side` is the side plane (one byte per cell, laid out as `cells`; empty:
/// every velocity 0 and none kept); without, it is ignored. Under MotionParams::shallow `faces` is
/// the face plane (plain_shallow_pass; it must hold 4 size.x size.y values), and the pass ends the tick.
void plain_step(std::span<std::uint8_t> cells, Int3 size, const PlainRules& rules, std::uint64_t tick,
                int threads = 1, std::span<std::uint8_t> side = {}, std::span<std::int32_t> faces = {});

/// Ticks first_tick .. first_tick + ticks - 1 of the plain loop, in order (`side` and `faces` as
/// plain_step's).
void plain_run(std::span<std::uint8_t> cells, Int3 size, const PlainRules& rules, std::uint64_t first_tick, int ticks,
               int threads = 1, std::span<std::uint8_t> side = {}, std::span<std::int32_t> faces = {});

}  // namespace granular::reference
