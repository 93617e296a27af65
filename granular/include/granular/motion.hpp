#pragma once
/// @file motion.hpp
/// The motion model: inertia and rolling for grains, carried in each cell's high bits.
///
/// A cell is one byte: bits 0..2 hold its material; for a grain, bits 3..6 hold its motion level and
/// bit 7 its phase (0 for every other material, but for a void that is a wake: kWakeBit). Under
/// MotionParams::trains a granular grain whose level bits hold kCarriedLevel is *carried* (a body in
/// free fall that the trains pass moves), and a void whose level bits hold it is *swept* (the cells
/// that body falls through in the tick). The level
/// is a fall speed: a grain at level v may move in a window of motion_window(v) of the tick's
/// Margolus sub-steps, so it falls up to that many cells per tick; the phase says whether that window
/// starts at sub-step 0 or 1 (the grain's layer in its block at sub-step 0, noted then).
/// Every block transition is a permutation, so a grain's level travels with it. World::read_region,
/// read_grid() and count() report materials only; World::hash() covers the whole byte.

#include <cstdint>

namespace granular {

/// Bits of a cell byte that hold its material.
inline constexpr std::uint8_t kMaterialMask = 7;
/// A grain's motion level sits in the bits above the material.
inline constexpr int kMotionShift = 3;
/// The motion level's bits once shifted down.
inline constexpr std::uint8_t kMotionLevelMask = 15;
/// A grain's phase bit: its window of sub-steps starts at sub-step 1 (else 0).
inline constexpr std::uint8_t kMotionPhaseBit = 0x80;

/// What a rule set's motion model does (RuleSet::motion). The default is no motion model: one
/// Margolus step per tick and no motion state, the paper's scheme.
struct MotionParams {
  int substeps = 1;  ///< Margolus sub-steps per tick (1: no motion model; else a multiple of 8 up to 32,
                     ///< so that sparse stepping's 8-step cycles fit in whole ticks)
  /// Grains in free fall fall as columns (a motion model's lever): the void a grain falling straight
  /// down leaves is a *wake* for one sub-step (kWakeBit and the grain's level), and the faller above a
  /// wake falls after it in the next sub-step, whatever its window, taking the wake's level if it is
  /// higher; every grain that falls straight down in the first sub-step of its window accelerates,
  /// whatever is beside it (without the lever, only a grain alone in its block's top layer does); and a
  /// grain that rolls or topples over a granular grain falling at level 2 or faster keeps its level
  /// (GrainMotion::flow_level caps a grain flowing over a surface, not one slipping past another inside
  /// a falling body). So a released block falls as a train of grains that all move as far per tick as
  /// its front, and grains against a wall fall as fast as the rest.
  bool columns = false;
  /// A falling body of grains stays whole (a lever of columns): a moving granular grain (level 1 or
  /// more) over a granular grain falling at least as fast waits for it instead of slipping around
  /// it, and after the last sub-step of every tick each column closes the gaps of its *trains* (grains
  /// of one level, each at most one tick's travel of that level above the one below it, only void
  /// between them; a train falling at level 2 or more over a tick's travel of void takes in moving
  /// grains of every level, at its own): every grain steps down onto the one below it and the voids
  /// go to the train's top (granular/step/column_trains.hpp). So a released block falls as a block,
  /// past the packing of 1 / (1 + v) that one-cell moves allow a column falling v cells a sub-step.
  /// An airborne train with a tick's travel of void under it is *carried*: the pass moves it that far
  /// each tick as one body and the block step reads it as a static material (granular/step/
  /// carried_cells.hpp), so a body in free fall costs a walk of its columns a tick, its inside sleeps,
  /// and it lands where the void under it ends. Needs substeps <= 24 (a carried grain's level bits
  /// hold kCarriedLevel). A DistributedWorld refuses it (a train may cross a slab).
  bool trains = false;
  /// Liquids feel the head of their body (a motion model's lever): each tick the backend computes a
  /// hydraulic head per coarse cell of 2 x 2 x 2 cells, the highest free surface of the liquid body
  /// the coarse cell belongs to (granular/step/head_field.hpp), and the block step lets a liquid
  /// under a head above a void's top move into it, sideways, up or down out of its body, at the
  /// speed that head gives. So connected vessels level, a column of water pours out from every row,
  /// and voids left in a body travel to its highest surface (docs/design/pressure.md). A world of
  /// such a rule set keeps the field beside its cells; one without a liquid never computes it. A
  /// DistributedWorld refuses it.
  bool pressure = false;
  /// Liquids keep a sideways velocity (a lever of pressure): each liquid cell carries one in a side
  /// plane beside the cell bytes, moved with the cells by the block step's permutations
  /// (granular/step/momentum.hpp). A liquid pushed out sideways by its head leaves at the speed the
  /// head gives, one that rolls off a surface or runs down its slope gathers speed, and each goes on
  /// along its velocity until a wall or a grain stops it, or hands it on to the liquid ahead: fronts
  /// run instead of diffusing. From sub-step 2 on, its sub-steps flip the x and y partition offsets
  /// with z in about 3 of 4 (motion::motion_offset), so a cell can move sideways about 3 cells in 4
  /// sub-steps; sub-steps 0 and 1, where grains at rest and flowing grains move, keep the default
  /// offsets, so sand behaves as without the lever. Needs pressure. A world of such a rule set keeps
  /// the plane while it holds liquid.
  bool momentum = false;
  /// Liquid under open sky moves as shallow water (a motion model's lever): after the last sub-step of
  /// every tick, each column's liquid above its ground (the cell over its highest cell that is
  /// neither void, gas nor liquid) is a shallow-water column, and the faces between neighbouring
  /// columns carry a velocity and a fraction of a cell in a *face plane* (4 int32 per column, part of
  /// the world's state: hash, snapshots). In 32 iterations a tick the faces accelerate down the
  /// surface steps, carry their momentum downstream and lose some to bed friction, and each whole
  /// cell a face carries moves from the top of one column to the top of the other
  /// (granular/step/shallow_water.hpp). So a released body of water runs out as a body, a pool levels
  /// within a few L / sqrt(g h), and a pool at rest stays at rest and costs nothing. Refused with
  /// pressure (the head's pushes and the pass work against each other); liquid under a cover moves
  /// by the block step alone (docs/design/shallow-water.md). A DistributedWorld refuses it.
  bool shallow = false;
  /// True when the rule set uses the motion model.
  constexpr bool enabled() const { return substeps > 1; }
  /// The highest motion level: a grain at it falls motion_window(max_level()) <= substeps - 1 cells
  /// per tick (the window must fit after a phase of 1).
  constexpr int max_level() const { return substeps / 2 < kMotionLevelMask ? substeps / 2 : kMotionLevelMask; }
};

/// How a granular material moves under a motion model (MaterialDef::grain): its friction levers.
/// Chances are out of 256 (0: never, 256: always).
struct GrainMotion {
  int topple_gain = 0;  ///< chance that a grain toppling down a step gains a level
  int roll_cost = 0;    ///< chance that a roll (a move onto a level neighbour) costs a level
  int roll_chance = 0;  ///< chance that a moving grain blocked from below is offered a roll to a level
                        ///< neighbour cell (0: never rolls)
  int entrain = 0;      ///< chance that a grain at rest on a step edge (a void beside it in its block's top
                        ///< layer, something under that void) is set moving (level 1) by a moving grain
                        ///< that rolls or topples in its block: a flowing layer erodes the slope it runs on
  int flow_level = 0;   ///< the highest motion level a grain keeps after it rolls or topples (1 ..
                        ///< kMotionLevelMask; 0: no limit): a grain flowing over a surface moves at most
                        ///< motion_window(flow_level) cells a tick, whatever speed it landed with (under
                        ///< MotionParams::columns, not over a grain falling at level 2 or faster)
};

/// The lowest motion level of a grain that falls rather than flows (MotionParams::columns): a grain
/// that rolls or topples over a granular grain this fast is inside a falling body, not on a surface
/// (it keeps its level), and a train whose first grain is this fast over a tick's travel of void is
/// airborne (granular/step/column_trains.hpp). A flowing grain keeps at most flow_level 1.
inline constexpr int kFallingLevel = 2;

/// The bit that, on a void cell (material 0), marks a wake (MotionParams::columns): the void a grain
/// falling straight down left in the last sub-step, with that grain's level in the motion level bits.
inline constexpr std::uint8_t kWakeBit = 0x80;

/// The level bits of a carried grain (MotionParams::trains; granular/step/carried_cells.hpp): above
/// every motion level of a rule set with trains (MotionParams::max_level() < kCarriedLevel).
inline constexpr int kCarriedLevel = kMotionLevelMask;

/// True when `cell` is a wake (MotionParams::columns).
constexpr bool is_wake(std::uint8_t cell) { return (cell & kMaterialMask) == 0 && (cell & kWakeBit) != 0; }

/// The sub-steps a grain at motion level `level` takes part in: 1 at rest and at level 1, then
/// 3, 5, 7, ... so that a grain falling from rest covers 1, 4, 9, ... cells after 1, 2, 3 ticks.
/// Always odd, so a grain falling at every one of its sub-steps stays in phase with the partition.
constexpr int motion_window(int level) { return level <= 1 ? 1 : 2 * level - 1; }

/// The material of a cell byte.
constexpr std::uint8_t cell_material(std::uint8_t cell) { return cell & kMaterialMask; }

/// The motion level of a cell byte.
constexpr int cell_motion(std::uint8_t cell) { return (cell >> kMotionShift) & kMotionLevelMask; }

/// `cell` with motion level `level` (0 .. kMotionLevelMask), its material and phase bit kept.
constexpr std::uint8_t with_motion(std::uint8_t cell, int level) {
  return std::uint8_t((cell & ~(kMotionLevelMask << kMotionShift)) | (std::uint32_t(level) << kMotionShift));
}

}  // namespace granular
