#pragma once
/// @file history_lines.hpp
/// What the sandbox says about its undo history: the HUD's line and the stdout lines of Ctrl+Z and
/// Ctrl+Shift+Z (or Ctrl+Y).

#include <optional>
#include <string>

#include "granular/stroke_history.hpp"
#include "granular/world.hpp"

namespace viewer {

/// The HUD's line: "undo: 3 strokes (1 to redo), 12.4 MiB of 256 MiB, checkpoint 16 MiB".
std::string history_line(const granular::StrokeHistory& history);

/// The stdout line of an undo that did `move` (nothing when nullopt) on `world`: "undo: tick T,
/// hash H (S more strokes to undo; paused, Ctrl+Shift+Z redoes)", or "undo: nothing to undo".
std::string undo_line(const std::optional<granular::HistoryMove>& move, const granular::World& world);

/// The stdout line of a redo: "redo: tick T, hash H (S more strokes to redo)", or "redo: nothing to
/// redo" (also when the world changed since the undo, which forgets what could be redone).
std::string redo_line(const std::optional<granular::HistoryMove>& move, const granular::World& world);

}  // namespace viewer
