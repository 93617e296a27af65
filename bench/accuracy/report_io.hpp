#pragma once
/// @file report_io.hpp
/// The suite's outputs: a text table for humans, JSON (everything, for the plot script) and CSV
/// (one row per metric).

#include <string>
#include <vector>

#include "accuracy/calibration.hpp"
#include "accuracy/report.hpp"

namespace granular::accuracy {

/// Human-readable report of one configuration: per test the scene, each metric's measured value,
/// reference, error and source, the notes, run time and conservation.
std::string report_text(const SuiteReport& report);

/// JSON of every configuration's report (config, tests, metrics, series, notes) and the calibration.
std::string report_json(const std::vector<SuiteReport>& reports, const Calibration& calibration);

/// CSV with a header and one row per metric: rules, backend, size, test, metric, unit, measured,
/// reference, tolerance, error, normalized_error, met, seconds, ticks, conserved, source.
std::string report_csv(const std::vector<SuiteReport>& reports);

}  // namespace granular::accuracy
