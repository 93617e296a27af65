#pragma once
/// @file progress_bar.hpp
/// A progress bar on stderr: redrawn in place on a terminal, a line per 10% otherwise (CI logs).

#include <chrono>
#include <cstdint>
#include <string>

namespace granular::cli {

/// Reports progress of a long run.
class ProgressBar {
 public:
  /// A bar for `total` units labelled `label`; `enabled` = false draws nothing.
  ProgressBar(std::string label, std::uint64_t total, bool enabled);
  /// Records that `done` units are finished.
  void update(std::uint64_t done);
  /// Draws the final state and ends the line.
  void finish();

 private:
  void draw(std::uint64_t done);

  std::string label_;
  std::uint64_t total_;
  bool enabled_;
  bool terminal_;
  int last_decile_ = -1;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace granular::cli
