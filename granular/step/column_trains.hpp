#pragma once
/// @file column_trains.hpp
/// MotionParams::trains: after the last sub-step of every tick, each column of the grid closes the
/// gaps in its falling trains, so a falling body keeps its packing. One function per column, on plain
/// integers, that the CPU backend and the CUDA kernel both call (the plain loop writes it again).
///
/// Why: grains move only into voids and a void rises one cell per sub-step, so within a tick a column
/// falling at v cells per sub-step holds at most 1 / (1 + v) of its cells (motion-model.md). A train
/// is what those sub-steps leave of a body of grains falling together: grains of one motion level in
/// one column, each at most one tick's travel at that level above the one below it, with only void
/// between them. Closing it moves each gap's void to the train's top (every grain steps down onto the
/// one below it, in order), so the body falls on as one. It is a permutation of the column: every
/// material is conserved exactly, and a grain moves down by the gaps below it in its train only.
/// An *airborne* train (its first grain at level kFallingLevel or more, over at least one tick's
/// travel of void) is a body in free fall, whose grains all fall alike: a grain of any moving level
/// joins it (its gap at most one tick's travel at the faster of the two levels) and takes its level.
/// Otherwise the sub-steps' windows split a falling column into trains of neighbouring levels whose
/// gaps never close (a 32- to 64-cell block kept 0.63 to 0.68 of its packing; docs/accuracy/
/// columns-default.md).
/// An airborne train with a tick's travel at its next level of void under it is *carried*
/// (carried_cells.hpp): its grains are hidden from the block step, the cells it will fall through are
/// swept, and at the next tick's end it falls through its sweep in one move and gains a level, as
/// long as the void under it allows the next tick's travel; when it does not, the train lands: its
/// grains take its level again and the block step moves them. So a body in free fall costs one walk
/// of its columns a tick instead of a block step of each of its bricks in every sub-step.

#include <cstdint>

#include "granular/motion.hpp"
#include "step/carried_cells.hpp"
#include "step/step_materials.hpp"

namespace granular::trains {

/// The lowest motion level of a train's grains: they are moving.
inline constexpr int kMemberLevel = 1;

/// The level a train at `level` falls at in the next tick (one more, at most `max_level`).
constexpr int next_level(int level, int max_level) { return level < max_level ? level + 1 : max_level; }

/// The level of a train whose sweep is `swept` cells long (carried::sweep_level), at most `max_level`.
constexpr int sweep_level_of(int swept, int max_level) {
  return carried::sweep_level(swept) < max_level ? carried::sweep_level(swept) : max_level;
}

/// One column's walk, bottom up. A train starts at a granular grain at motion level L >= kMemberLevel;
/// it is airborne when L >= kFallingLevel and at least motion_window(L) plain void cells lie right
/// under that grain (down to the grid's floor at most). The next grain above joins it when it is
/// granular and moving, only void lies between them, that gap is at most motion_window of the faster
/// of the two levels (the distance it falls in a tick), and its level is L or the train is airborne;
/// anything else ends the train, and a grain that does not join starts the next. A joining grain
/// takes level L (its phase bit kept) and moves down to the cell above the train's top; that cell's
/// void moves up to where the grain was, its level and wake bits cleared. A granular grain at rest
/// over an airborne train joins it too when the void between them is at most the train's travel in
/// the next tick, motion_window(min(L + 1, max_level)): it falls with it, as the block step's faller
/// over a wake follows it.
///
/// Carried trains (carried_cells.hpp): an airborne train with at least motion_window(N) plain voids
/// under it, N = min(L + 1, max_level), is carried: its grains (and those that join it) are carried
/// grains, and the N-window cells under it are swept. A carried grain over a sweep is the lowest of a
/// carried train: it falls through the sweep (at the level its length gives, sweep_level), its
/// grains follow, and the train sweeps the next tick's travel under it again or, without room for
/// it, lands (its grains at the train's level, still airborne, the block step moves them on); but
/// when the void between its sweep and an airborne train under it is less than that travel, it has
/// caught that train, and its grains join it instead (a faster body catching a slower one). A sweep
/// with no carried grain right above it, and a carried grain with neither a sweep nor a carried
/// train under it, are what a tool or a file left: the sweep's cells become plain voids, the grain a
/// grain at kFallingLevel.
///
/// `column` gives `std::uint8_t get(int z)`, `void set(int z, std::uint8_t byte)` and `void
/// changed(int z, bool seen)`, called once for each cell whose byte the walk changed, once no later
/// visit can write it; `seen` is false when the cell held a carried grain before the walk and holds
/// one after it (inside a carried train, whose grains pass through void on their way down: the
/// block step reads both as the same static material, and neither is the lowest of its train, so no
/// block's step or quiet test changes, and the bricks need not wake). Only grains and voids change,
/// whose side bytes (momentum.hpp) are 0, so a side plane needs no change. The walk must start at the
/// column's floor (z = 0), so that the void under a train is counted alike on every backend and
/// stepping mode.
struct TrainWalk {
  int top = -1;           ///< where the train's highest grain now is (-1: no train)
  int last = -1;          ///< where that grain was before it moved
  int level = 0;          ///< the train's level
  bool airborne = false;  ///< the train is airborne: grains of any moving level join it
  bool carried = false;   ///< the train is carried: its grains are carried grains
  int voids = 0;          ///< plain void cells right under the next cell visited (or under its sweep)
  int swept = 0;          ///< swept cells right under the next cell visited
  int at = 0;             ///< the cell being visited

  /// Cells below the one visited whose change may still be undone: whether the walk wrote cell z (bit
  /// z % kPending) and then its byte before the walk (slot z % kPending). A cell kPending below the
  /// visited one is reported (a valid train moves a grain at most two tick's travels down; a write
  /// farther down, which only a tool or a file can cause, is reported as seen at once).
  static constexpr int kPending = 64;
  std::uint8_t before[kPending] = {};
  std::uint64_t written = 0;

  /// Ends the walk of a column whose cells end below z_end: a sweep at its top is released.
  template <class Column>
  constexpr void finish(Column& column, int z_end, const StepMaterials& m) {
    at = z_end;
    release_sweep(column, z_end);
    for (int k = z_end - kPending > 0 ? z_end - kPending : 0; k < z_end; ++k) report(column, k, m);
  }

  /// Visits cell z of `column`, in a rule set whose highest motion level is `max_level`; a walk visits
  /// z = 0, 1, ... in order.
  template <class Column>
  constexpr void visit(Column& column, int z, const StepMaterials& m, int max_level) {
    if (z >= kPending && written != 0) report(column, z - kPending, m);
    at = z;
    std::uint8_t cell = column.get(z);
    const std::uint32_t material = cell & kMaterialMask;
    if (swept == 0 && m.is_void(material) && !carried::is_hidden(cell)) {  // the commonest cell: air
      ++voids;
      return;
    }
    if (carried::is_swept(m, cell)) {
      ++swept;
      return;
    }
    const bool carried_cell = carried::is_carried(m, cell);
    // A carried grain over its sweep falls through it, unless it then catches the airborne train under
    // it, whose grains it joins.
    bool caught = false;
    if (carried_cell && swept > 0) {
      caught = top >= 0 && airborne && voids < motion_window(next_level(sweep_level_of(swept, max_level), max_level));
      if (!caught) {
        fall_through_sweep(column, z, max_level);
        return;
      }
    }
    release_sweep(column, z);
    if (m.is_void(material)) {
      ++voids;
      return;
    }
    const int under = voids;
    voids = 0;
    const bool granular = m.is_granular(material);
    const int space = z - last - 1;  // void between it and the train's highest grain, as they were
    const int next = next_level(level, max_level);
    // What joins the train under it: a carried grain, when that train is airborne (carried, or landed
    // in this walk) and it lies within one tick's travel of it or caught it; a grain at rest, when that
    // train is airborne and it lies within the train's travel in the next tick (it falls with it, as
    // the block step's faller over a wake follows it); a moving grain, within one tick's travel at the
    // faster of the two levels, when it moves at the train's level or the train is airborne.
    bool joins = false;
    if (top >= 0 && granular) {
      const int own = cell_motion(cell);
      if (carried_cell)
        joins = airborne && (caught || space <= motion_window(level));
      else if (own == 0)
        joins = airborne && space <= motion_window(next);
      else
        joins = (own == level || airborne) && space <= motion_window(level > own ? level : own);
    }
    if (!joins) {
      if (carried_cell) {
        cell = with_motion(cell, kFallingLevel);  // a carried grain with no train under it
        write(column, z, cell);
      }
      const int own = cell_motion(cell);
      if (!granular || own < kMemberLevel) {
        top = -1;
        return;
      }
      // The first grain of a train.
      top = last = z;
      level = own;
      airborne = level >= kFallingLevel && under >= motion_window(level);
      const int next_travel_level = next_level(level, max_level);
      carried = airborne && under >= motion_window(next_travel_level);
      if (carried) {
        write(column, z, carried::hidden_cell(cell));
        sweep(column, z, next_travel_level);
      }
      return;
    }
    const int to = top + 1;
    const std::uint8_t joined = carried ? carried::hidden_cell(cell) : with_motion(cell, level);
    if (to != z) {
      const std::uint8_t gap = column.get(to);
      write(column, to, joined);
      write(column, z, std::uint8_t(gap & kMaterialMask));
    } else {
      write(column, z, joined);
    }
    voids = z - to;  // the cells over the grain's new place, up to its old one, are void now
    top = to;
    last = z;
  }

 private:
  /// Writes `byte` to cell z (at most the cell visited); its change is reported later (report), from
  /// its byte before the walk, kept at its first write.
  template <class Column>
  constexpr void write(Column& column, int z, std::uint8_t byte) {
    const std::uint8_t old = column.get(z);
    if (old == byte) return;
    column.set(z, byte);
    const std::uint64_t bit = std::uint64_t(1) << (z % kPending);
    if (z <= at - kPending) {
      column.changed(z, true);
    } else if ((written & bit) == 0) {
      before[z % kPending] = old;
      written |= bit;
    }
  }

  /// Reports cell z's change, if the walk changed it.
  template <class Column>
  constexpr void report(Column& column, int z, const StepMaterials& m) {
    if (((written >> (z % kPending)) & 1u) == 0) return;
    written &= ~(std::uint64_t(1) << (z % kPending));
    const std::uint8_t old = before[z % kPending], now = column.get(z);
    if (old != now) column.changed(z, !carried::is_carried(m, old) || !carried::is_carried(m, now));
  }

  /// Sweeps the motion_window(level) cells under cell z (plain voids): a train falling at `level`.
  template <class Column>
  constexpr void sweep(Column& column, int z, int level) {
    for (int k = z - motion_window(level); k < z; ++k) write(column, k, carried::hidden_cell(column.get(k)));
  }

  /// The cells of a sweep under cell z with no carried grain over it become plain voids.
  template <class Column>
  constexpr void release_sweep(Column& column, int z) {
    for (int k = z - swept; k < z; ++k) write(column, k, std::uint8_t(column.get(k) & kMaterialMask));
    voids += swept;
    swept = 0;
  }

  /// The carried grain at z, the lowest of its train, falls through the sweep under it and starts the
  /// walk's train there: carried on if the plain voids under the sweep allow the next tick's travel,
  /// else landed.
  template <class Column>
  constexpr void fall_through_sweep(Column& column, int z, int max_level) {
    const int to = z - swept;
    level = sweep_level_of(swept, max_level);
    const int next = next_level(level, max_level);
    carried = voids >= motion_window(next);
    const std::uint8_t cell = column.get(z), gap = column.get(to);
    write(column, to, carried ? cell : with_motion(cell, level));
    for (int k = to + 1; k < z; ++k) write(column, k, std::uint8_t(column.get(k) & kMaterialMask));
    write(column, z, std::uint8_t(gap & kMaterialMask));
    if (carried) sweep(column, to, next);
    airborne = true;
    top = to;
    last = z;
    voids = z - to;
    swept = 0;
  }
};

/// Closes the trains of one column, cells z_begin .. z_end - 1 (TrainWalk: z_begin is the column's
/// floor, 0, for the void under a train to count alike everywhere), in a rule set whose highest motion
/// level is `max_level`.
template <class Column>
constexpr void close_column(Column& column, int z_begin, int z_end, const StepMaterials& m, int max_level) {
  TrainWalk walk;
  for (int z = z_begin; z < z_end; ++z) walk.visit(column, z, m, max_level);
  walk.finish(column, z_end, m);
}

}  // namespace granular::trains
