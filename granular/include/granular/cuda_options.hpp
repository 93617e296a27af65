#pragma once
/// @file cuda_options.hpp
/// The settings only the CUDA backend reads (WorldDef::cuda). Plain C++: a game that links only
/// the CPU core sets them or leaves them at their defaults alike.

namespace granular {

/// Settings of the CUDA backend; the CPU backend ignores them. Every field has a usable default.
struct CudaOptions {
  double dense_fraction = 0.125;  ///< sparse stepping of a rule set without a motion model: when more
                                  ///< than this fraction of the bricks was awake at the last tick the
                                  ///< host knows of, step() runs the dense kernels, recording the sparse
                                  ///< state (same cells and activity figures, faster when much is
                                  ///< awake); 0 always, 1 never; 0..1
  double motion_dense_fraction = 1.0;  ///< the same for a rule set with a motion model (default never):
                                       ///< its steps are compute-bound, and on an H200 the 1024^3 bowl
                                       ///< (15 to 22% of the bricks awake) runs at 6.7 ms per tick with
                                       ///< sparse steps against 36.7 with dense-recording ones
                                       ///< (bench/RESULTS.md); 0..1
};

}  // namespace granular
