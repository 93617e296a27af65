#include "granular/accuracy/suite.hpp"

#include <algorithm>
#include <string>
#include <utility>

#include "granular/errors.hpp"
#include "granular/world.hpp"
#include "suite_tests.hpp"

namespace granular::accuracy {

TestReport open_report(const SuiteOptions& options, std::string test, std::string title, std::string scene) {
  log_line(options, test + ": " + scene);
  TestReport r;
  r.test = std::move(test);
  r.title = std::move(title);
  r.scene = std::move(scene);
  return r;
}

std::vector<std::string> suite_test_names() {
  return {"cone",     "cone_sizes", "gravel_cone",           "hysteresis", "dug_slope", "pour",
          "silo",     "collapse",   "fall",                  "falling_block", "communicating_vessels",
          "dam_break", "levelling", "torricelli",            "buoyancy",   "conservation"};
}

SuiteReport run_suite(const SuiteOptions& o, const std::vector<std::string>& tests) {
  const std::vector<std::string> all = suite_test_names();
  std::string valid;
  for (const auto& n : all) valid += (valid.empty() ? "" : ", ") + n;
  if (tests.empty()) throw InvalidArgument("accuracy: no test selected; valid tests: " + valid);
  for (const auto& t : tests)
    if (std::find(all.begin(), all.end(), t) == all.end())
      throw InvalidArgument("accuracy: unknown test '" + t + "'; valid tests: " + valid);
  auto wanted = [&](const char* name) { return std::find(tests.begin(), tests.end(), name) != tests.end(); };

  SuiteReport report;
  report.config.rules = o.rules;
  report.config.size = o.quick ? "quick" : "full";
  report.config.threads = o.threads;
  report.config.stepping = o.sparse ? "sparse" : "dense";
  report.config.seed = o.seed;
  report.config.calibration = o.calibration;
  {
    // The backend actually used (auto resolves here, once, with a tiny world).
    WorldDef probe = test_world_def(o, {2, 2, 2});
    const World world(probe);
    report.config.backend = backend_name(world.backend());
    report.config.backend_description = world.backend_description();
  }
  const TestReport* collapse = nullptr;
  if (wanted("cone")) report.tests.push_back(run_cone_test(o));
  if (wanted("cone_sizes")) report.tests.push_back(run_cone_sizes_test(o));
  if (wanted("gravel_cone")) report.tests.push_back(run_gravel_cone_test(o));
  if (wanted("hysteresis")) report.tests.push_back(run_hysteresis_test(o));
  if (wanted("dug_slope")) report.tests.push_back(run_dug_slope_test(o));
  if (wanted("pour")) report.tests.push_back(run_pour_test(o));
  if (wanted("silo")) report.tests.push_back(run_silo_test(o));
  std::size_t collapse_index = 0;
  if (wanted("collapse")) {
    report.tests.push_back(run_collapse_test(o));
    collapse_index = report.tests.size();
  }
  if (wanted("fall")) {
    if (collapse_index) collapse = &report.tests[collapse_index - 1];
    TestReport fall = run_fall_test(o, collapse);
    report.tests.push_back(std::move(fall));
  }
  if (wanted("falling_block")) report.tests.push_back(run_falling_block_test(o));
  if (wanted("communicating_vessels")) report.tests.push_back(run_communicating_vessels_test(o));
  if (wanted("dam_break")) report.tests.push_back(run_dam_break_test(o));
  if (wanted("levelling")) report.tests.push_back(run_levelling_test(o));
  if (wanted("torricelli")) report.tests.push_back(run_torricelli_test(o));
  if (wanted("buoyancy")) report.tests.push_back(run_buoyancy_test(o));
  if (wanted("conservation")) {
    const std::vector<TestReport> earlier = report.tests;
    report.tests.push_back(run_conservation_test(o, earlier));
  }
  return report;
}

}  // namespace granular::accuracy
