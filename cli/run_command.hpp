#pragma once
/// @file run_command.hpp
/// `granular run`: run a scene headless and print a summary.

#include <CLI/CLI.hpp>

namespace granular::cli {

/// Adds the `run` subcommand to `app`.
void add_run_command(CLI::App& app);

}  // namespace granular::cli
