#pragma once
/// @file report_io.hpp
/// The suite's outputs: a text table for humans, JSON (everything, for the plot script) and CSV
/// (one row per metric).

#include <string>
#include <vector>

#include "granular/accuracy/calibration.hpp"
#include "granular/accuracy/report.hpp"

namespace granular::accuracy {

/// Human-readable report of one configuration: per test the scene, each metric's measured value,
/// reference, error and source, the notes, run time and conservation.
std::string report_text(const SuiteReport& report);

/// Where and how a suite run was made, recorded in its JSON.
struct RunInfo {
  std::string command;  ///< the command line that reproduces the run
  std::string date;     ///< UTC date and time, ISO 8601
  std::string machine;  ///< CPU model and hardware threads
};

/// The RunInfo of this process: `command` as given, the current UTC time, this machine's CPU.
RunInfo current_run_info(std::string command);

/// JSON of every configuration's report (config, tests, metrics, series, notes), the calibration
/// and the run info. A string that is not valid UTF-8 (a CPU or GPU name) has each invalid byte
/// sequence written as U+FFFD.
std::string report_json(const std::vector<SuiteReport>& reports, const Calibration& calibration, const RunInfo& info);

/// CSV with a header and one row per metric: rules, backend, size, stepping, test, metric, unit, measured,
/// reference, tolerance, error, normalized_error, met, seconds, ticks, conserved, source.
std::string report_csv(const std::vector<SuiteReport>& reports);

}  // namespace granular::accuracy
