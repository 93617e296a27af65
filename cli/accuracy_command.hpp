#pragma once
/// @file accuracy_command.hpp
/// `granular accuracy`: the accuracy suite against physical references (accuracy/).

#include <CLI/CLI.hpp>

namespace granular::cli {

/// Adds the `accuracy` subcommand to `app`.
void add_accuracy_command(CLI::App& app);

}  // namespace granular::cli
