#pragma once
/// @file suite.hpp
/// Running the accuracy suite: the tests by name, in dependency order.

#include <string>
#include <vector>

#include "granular/accuracy/report.hpp"
#include "granular/accuracy/suite_options.hpp"

namespace granular::accuracy {

/// Every test name, in the order the suite runs them: cone, cone_sizes, gravel_cone, hysteresis,
/// dug_slope, pour, silo, collapse, fall, falling_block, communicating_vessels, dam_break, levelling,
/// torricelli, buoyancy, conservation (fall uses collapse's stop times; conservation checks every earlier test).
std::vector<std::string> suite_test_names();

/// Runs the named tests (a subset of suite_test_names(), any order; run in the suite's order)
/// for one configuration. Throws InvalidArgument naming the valid tests for an unknown name or an
/// empty list.
SuiteReport run_suite(const SuiteOptions& options, const std::vector<std::string>& tests);

}  // namespace granular::accuracy
