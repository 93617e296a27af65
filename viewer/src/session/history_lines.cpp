#include "session/history_lines.hpp"

#include "granular/extend/hex.hpp"
#include "granular/extend/memory_budget.hpp"

namespace viewer {

namespace {

/// "tick T, hash H" of `world`.
std::string tick_and_hash(const granular::World& world) {
  return "tick " + std::to_string(world.tick()) + ", hash " + granular::hex64(world.hash());
}

/// "1 stroke" / "3 strokes".
std::string strokes(std::size_t n) { return std::to_string(n) + (n == 1 ? " stroke" : " strokes"); }

}  // namespace

std::string history_line(const granular::StrokeHistory& history) {
  std::string line = "undo: " + strokes(history.undo_count());
  if (const std::size_t redo = history.redo_count(); redo > 0) line += " (" + std::to_string(redo) + " to redo)";
  line += ", " + granular::format_bytes(double(history.bytes())) + " of " +
          granular::format_bytes(double(history.max_bytes()));
  if (history.checkpoint_bytes() > 0)
    line += ", checkpoint " + granular::format_bytes(double(history.checkpoint_bytes()));
  return line;
}

std::string undo_line(const std::optional<granular::HistoryMove>& move, const granular::World& world) {
  if (!move) return "undo: nothing to undo";
  return "undo: " + tick_and_hash(world) + " (" + std::to_string(move->strokes_left) +
         " more to undo; paused, Ctrl+Shift+Z redoes)";
}

std::string redo_line(const std::optional<granular::HistoryMove>& move, const granular::World& world) {
  if (!move) return "redo: nothing to redo";
  return "redo: " + tick_and_hash(world) + " (" + std::to_string(move->strokes_left) + " more to redo)";
}

}  // namespace viewer
