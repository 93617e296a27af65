#pragma once
/// @file child_process.hpp
/// Running another program (the accuracy plot script's python) from an argument vector: the
/// program and each argument reach the child as they are, never through a shell, so a path holding
/// quotes, spaces or `;` is only ever a path.

#include <string>
#include <vector>

namespace granular::cli {

/// Whether a child's standard output and error reach this process's or are discarded.
enum class ChildOutput { Inherit, Discard };

/// How a child ended.
struct ChildResult {
  bool started = false;  ///< false when the program could not be started (not found, not executable)
  int status = -1;       ///< its exit status; 128 + the signal number when a signal ended it
  std::string why;       ///< when not started: the system's reason
};

/// Runs `argv[0]` (looked up on PATH when it holds no '/') with the arguments `argv` through
/// posix_spawnp and waits for it. `argv` must not be empty.
ChildResult run_program(const std::vector<std::string>& argv, ChildOutput output = ChildOutput::Inherit);

/// `argv` as one line a POSIX shell would read back as the same words (each word in single quotes
/// where it holds anything but letters, digits and -_./=:,+), for messages only: nothing runs it.
std::string shell_words(const std::vector<std::string>& argv);

}  // namespace granular::cli
