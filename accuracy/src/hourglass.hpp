#pragma once
/// @file hourglass.hpp
/// The hourglass discharge of the silo test: the shipped `hourglass` scene drains from its upper
/// chamber through the neck; the flow rate is measured in windows of the amount emptied.

#include <cstdint>
#include <vector>

#include "granular/accuracy/suite_options.hpp"

namespace granular::accuracy {

/// What hourglass_discharge measured.
struct HourglassDischarge {
  int n = 0;                           ///< the scene's size parameter N
  std::vector<double> emptied;         ///< window centres: fraction of the upper chamber's grains gone
  std::vector<double> rate;            ///< flow in each window (grains per tick)
  double mean_rate = 0;                ///< mean of `rate`
  double spread = 0;                   ///< (max - min) / mean of `rate` over the windows 20%..80% emptied
  bool drained = false;                ///< true when 80% of the upper chamber emptied within the limit
  bool conserved = true;               ///< grains per material conserved
  double seconds = 0;                  ///< run time
  std::uint64_t ticks = 0;             ///< ticks stepped
  double cell_updates = 0;             ///< cells x ticks
};

/// Runs the `hourglass` scene (assets/scenes) at size N = n: counts the grains above the neck
/// (z >= N / 2) every 2 ticks until 80% of them have left (or 400 N ticks), and reports W in six
/// windows of 10% of the initial upper count between 20% and 80% emptied (window ends interpolated
/// between samples).
HourglassDischarge hourglass_discharge(const SuiteOptions& options, int n);

}  // namespace granular::accuracy
