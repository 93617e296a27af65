#pragma once
/// @file poured_cone.hpp
/// The poured-cone test for one granular material: the pour and measurement of pour_cone at the
/// suite's sizes, the angle of repose against the material's reference and the footprint against a
/// round one. The sand cone (`cone`) and the gravel cone (`gravel_cone`) are this test with their
/// own material and target.

#include <string>

#include "granular/accuracy/report.hpp"
#include "granular/accuracy/suite_options.hpp"
#include "granular/material.hpp"

namespace granular::accuracy {

/// What a poured-cone test pours and the angle it is compared with.
struct ConeTarget {
  std::string test;             ///< the test's identifier, e.g. "cone"
  std::string title;            ///< its title line
  Material material;            ///< the granular material poured and measured
  std::string name;             ///< the reference material's name, e.g. "dry sand"
  double repose_deg = 0;        ///< its angle of repose in degrees (tolerance 2 deg)
  std::string source;           ///< where that angle comes from
};

/// Pours `target.material` from a spout onto a floor (quick: 96^2 x 64 cells, spout of radius 2,
/// 4000 ticks of at most 60 grains; full: 256^2 x 128, radius 4, 16000 ticks of at most 400), lets
/// it settle and reports measure_cone's angle of repose against `target.repose_deg` (+- 2 deg),
/// r_max / r_min at half height against 1 (+- 0.05) and the 1-, 2- and 4-fold Fourier amplitudes of
/// r(phi) against 0 (+- 0.05 / 2.05, the amplitude that makes r_max / r_min = 1.05), with the
/// per-azimuth angle and radius as its series. Conserved: every material's count changes by the
/// grains poured alone.
TestReport run_poured_cone(const SuiteOptions& options, const ConeTarget& target);

}  // namespace granular::accuracy
