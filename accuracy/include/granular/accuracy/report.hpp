#pragma once
/// @file report.hpp
/// What one accuracy test reports: measured values against physical references (with sources),
/// the data series behind its plot, its run time and whether grains were conserved.

#include <cstdint>
#include <string>
#include <vector>

#include "granular/accuracy/calibration.hpp"

namespace granular::accuracy {

/// One measured quantity against its reference.
struct Metric {
  std::string name;         ///< short identifier, e.g. "angle_of_repose"
  std::string unit;         ///< unit of measured/reference ("deg", "", "cells/tick"...)
  double measured = 0;      ///< the value measured from the grid
  double reference = 0;     ///< the physical reference (or the ideal, e.g. 1 for a round footprint)
  double tolerance = 0;     ///< the suite's target: |measured - reference| <= tolerance (> 0)
  std::string source;       ///< where the reference comes from (paper, book, or "ideal")
  /// measured - reference.
  double error() const { return measured - reference; }
  /// |error| / tolerance: 1 is the edge of the target, below 1 the target is met.
  double normalized_error() const;
  /// True when |error| <= tolerance.
  bool met() const { return normalized_error() <= 1.0; }
};

/// A named curve of a test's plot (x against y), e.g. W against D, or the reference curve.
struct Series {
  std::string name;          ///< legend label
  std::string x_label;       ///< x axis label with unit
  std::string y_label;       ///< y axis label with unit
  std::vector<double> x;     ///< abscissae
  std::vector<double> y;     ///< ordinates (same length as x)
  bool reference = false;    ///< true for a reference curve (drawn as a line, not markers)
};

/// The outcome of one test of the suite for one configuration.
struct TestReport {
  std::string test;              ///< test identifier: one of suite_test_names() (cone, ..., conservation)
  std::string title;             ///< one line for humans
  std::string scene;             ///< how the scene was built (sizes in cells)
  std::vector<Metric> metrics;   ///< measured values against references
  std::vector<Series> series;    ///< what the plot draws
  std::vector<std::string> notes;  ///< caveats worth printing (e.g. "the pile did not settle")
  double seconds = 0;            ///< wall-clock run time of the simulation steps and measurements
  std::uint64_t ticks = 0;       ///< ticks stepped in all
  double cell_updates = 0;       ///< sum over runs of cells x ticks
  bool conserved = true;         ///< grains per material conserved exactly (with every removal accounted)
  /// Mean normalized error over the metrics (0 when there are none).
  double mean_normalized_error() const;
};

/// The configuration a suite run used.
struct SuiteConfig {
  std::string rules = "paper";  ///< rule-set preset
  std::string backend = "cpu";  ///< backend actually used ("cpu", "cuda")
  std::string backend_description;  ///< the backend with details, e.g. "cpu (2 threads)" or the GPU's name
  std::string size = "full";    ///< "quick" or "full"
  std::string stepping = "sparse";  ///< "sparse" (awake bricks only) or "dense" (every block): same results
  int threads = 0;              ///< CPU threads (0 = all)
  std::uint64_t seed = 1;       ///< world seed
  Calibration calibration;      ///< the physical units of the rule set (calibration_for)
};

/// All tests of one configuration.
struct SuiteReport {
  SuiteConfig config;               ///< what ran
  std::vector<TestReport> tests;    ///< in the order they ran
  /// Sum of the tests' run times.
  double seconds() const;
  /// Mean over tests of their mean normalized error.
  double mean_normalized_error() const;
  /// True when every test conserved grains.
  bool conserved() const;
};

}  // namespace granular::accuracy
