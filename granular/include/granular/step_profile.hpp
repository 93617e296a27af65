#pragma once
/// @file step_profile.hpp
/// Where a World::step call's time went, phase by phase, as a game's profiler shows it.

#include <cstdint>

namespace granular {

/// The host wall time (milliseconds) of each phase of the last World::step() call, summed over its
/// ticks. A backend on a GPU runs the step on the device; its time shows in `step` where the step
/// waits for the device (sparse stepping, no renderer attached), else in the next phase that waits.
struct StepProfile {
  std::uint64_t ticks = 0;   ///< ticks of the call
  double total = 0;          ///< the whole call
  double step = 0;           ///< the backend's steps of the cells
  double bodies = 0;         ///< writing the bodies into the grid and reading what the sand does to them, in all
  double bodies_shapes = 0;  ///< of which finding each body's cells and region, and which bodies rest
  double bodies_read = 0;    ///< of which reading the moving bodies' regions from the backend
  double bodies_stamp = 0;   ///< of which the stamps, on the world's threads
  double bodies_write = 0;   ///< of which writing the regions back to the backend
  /// Finding the forces the sand puts on the bodies, on the world's threads. Part of `bodies` where
  /// the backend steps on the host's threads; where it steps on a device they are found while the
  /// host waits for it, so their time is within `step`, and not in `bodies`.
  double bodies_forces = 0;
};

}  // namespace granular
