#pragma once
/// @file lut_command.hpp
/// `granular lut`: build, validate and cache a rule set's transition table.

#include <CLI/CLI.hpp>

namespace granular::cli {

/// Adds the `lut` subcommand to `app`.
void add_lut_command(CLI::App& app);

}  // namespace granular::cli
