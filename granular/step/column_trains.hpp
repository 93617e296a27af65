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

#include <cstdint>

#include "granular/motion.hpp"
#include "step/step_materials.hpp"

namespace granular::trains {

/// The lowest motion level of a train's grains: they are moving.
inline constexpr int kMemberLevel = 1;

/// The cells [lo, hi] of a column that a close_column call changed (lo > hi: none).
struct ChangedSpan {
  int lo = 1, hi = 0;
  /// True when the call changed a cell.
  constexpr bool any() const { return lo <= hi; }
};

/// One column's walk, bottom up: the train it is in and what it changed. A train starts at a granular
/// grain at motion level L >= kMemberLevel; it is airborne when L >= kFallingLevel and at least
/// motion_window(L) void cells lie right under that grain (down to the grid's floor at most). The
/// next grain above joins it when it is granular and moving, only void lies between them, that gap is
/// at most motion_window of the faster of the two levels (the distance it falls in a tick), and its
/// level is L or the train is airborne; anything else ends the train, and a grain that does not join
/// starts the next. A joining grain takes level L (its phase bit kept) and moves down to the cell
/// above the train's top; that cell's void moves up to where the grain was, its wake bit cleared (it
/// no longer lies under the grain that left it). `column` gives `std::uint8_t get(int z)` and `void
/// set(int z, std::uint8_t byte)`. Only grains and voids move, whose side bytes (momentum.hpp) are 0,
/// so a side plane needs no change. The walk must start at the column's floor (z = 0), so that the
/// void under a train is counted alike on every backend and stepping mode.
struct TrainWalk {
  int top = -1;           ///< where the train's highest grain now is (-1: no train)
  int last = -1;          ///< where that grain was before it moved
  int level = 0;          ///< the train's level
  bool airborne = false;  ///< the train is airborne: grains of any moving level join it
  int voids = 0;          ///< void cells right under the next cell visited, as the walk left them
  ChangedSpan changed;    ///< the cells the walk changed so far

  /// Visits cell z of `column`; a walk visits z = 0, 1, ... in order.
  template <class Column>
  constexpr void visit(Column& column, int z, const StepMaterials& m) {
    const std::uint8_t cell = column.get(z);
    const std::uint32_t material = cell & kMaterialMask;
    if (m.is_void(material)) {
      ++voids;
      return;
    }
    const int under = voids;
    voids = 0;
    const int cell_level = cell_motion(cell);
    if (!m.is_granular(material) || cell_level < kMemberLevel) {
      top = -1;
      return;
    }
    const int reach = motion_window(level > cell_level ? level : cell_level);
    if (top < 0 || (cell_level != level && !airborne) || z - last - 1 > reach) {
      top = last = z;
      level = cell_level;
      airborne = level >= kFallingLevel && under >= motion_window(level);
      return;
    }
    const int to = top + 1;
    const std::uint8_t joined =
        std::uint8_t((cell & ~(kMotionLevelMask << kMotionShift)) | (std::uint32_t(level) << kMotionShift));
    if (to != z || joined != cell) {
      const std::uint8_t gap = column.get(to);
      column.set(to, joined);
      if (to != z) column.set(z, std::uint8_t(gap & kMaterialMask));
      if (!changed.any()) changed.lo = to;
      changed.hi = z;
    }
    voids = z - to;  // the cells over the grain's new place, up to its old one, are void now
    top = to;
    last = z;
  }
};

/// Closes the trains of one column, cells z_begin .. z_end - 1 (TrainWalk: z_begin is the column's
/// floor, 0, for the void under a train to count alike everywhere), and returns what changed.
template <class Column>
constexpr ChangedSpan close_column(Column& column, int z_begin, int z_end, const StepMaterials& m) {
  TrainWalk walk;
  for (int z = z_begin; z < z_end; ++z) walk.visit(column, z, m);
  return walk.changed;
}

}  // namespace granular::trains
