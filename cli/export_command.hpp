#pragma once
/// @file export_command.hpp
/// `granular export`: write the grid after N ticks to a .raw or .vox file.

#include <CLI/CLI.hpp>

namespace granular::cli {

/// Adds the `export` subcommand to `app`.
void add_export_command(CLI::App& app);

}  // namespace granular::cli
