#pragma once
/// @file world_files.hpp
/// The sandbox's snapshot file: the one Ctrl+S writes and Ctrl+O reads when --save names none, and
/// the lines that report a save or a load on stdout.

#include <string>

#include "granular/world.hpp"

namespace viewer {

/// The snapshot file of Ctrl+S and Ctrl+O when --save names none, in the current folder.
inline constexpr const char* kDefaultSnapshotFile = "granular-sandbox.gsnap";

/// "N cells, tick T, hash H": what identifies a world's state in the save and load lines.
std::string world_state_text(const granular::World& world);

/// Writes a snapshot of `world` to `path` (granular::save_snapshot: atomically; granular::Error on
/// failure) and returns the line reporting it: "saved: PATH (N cells, tick T, hash H)".
std::string save_world(const granular::World& world, const std::string& path);

/// The line reporting that `world` was loaded from `path`: "loaded: PATH (N cells, tick T, hash H)".
std::string loaded_line(const granular::World& world, const std::string& path);

}  // namespace viewer
