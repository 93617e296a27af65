#include "accuracy_command.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "accuracy_plot_script.hpp"
#include "child_process.hpp"
#include "choices_text.hpp"
#include "granular/accuracy/report_io.hpp"
#include "granular/accuracy/suite.hpp"
#include "granular/errors.hpp"
#include "granular/rule_presets.hpp"
#include "number_option.hpp"
#include "output_paths.hpp"

namespace granular::cli {

namespace {

struct AccuracyOptions {
  std::vector<std::string> rules = rule_preset_names();
  std::vector<std::string> tests = accuracy::suite_test_names();
  std::string backend = "cpu";
  int threads = 0;
  std::uint64_t seed = 1;
  std::string material = "sand";
  bool quick = false;
  bool dense = false;
  bool json = false;
  std::string csv;
  std::string out;
  std::string cache_dir;
};

BackendKind parse_backend(const std::string& name) {
  if (name == "cpu") return BackendKind::Cpu;
  if (name == "cuda") return BackendKind::Cuda;
  if (name == "auto") return BackendKind::Auto;
  throw InvalidArgument("--backend '" + name + "' is not a backend; use auto, cpu or cuda");
}

/// The command that reproduces this run (every option spelled out).
std::string command_line(const AccuracyOptions& o) {
  auto join = [](const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ",") + x;
    return s;
  };
  std::string c = "granular accuracy";
  if (o.quick) c += " --quick";
  if (o.dense) c += " --dense";
  c += " --rules " + join(o.rules) + " --tests " + join(o.tests) + " --backend " + o.backend +
       " --threads " + std::to_string(o.threads) + " --seed " + std::to_string(o.seed) + " --material " + o.material;
  return c;
}

/// The first of $GRANULAR_PYTHON, python3 and /usr/bin/python3 that can import matplotlib ("" if none).
std::string plotting_python() {
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("GRANULAR_PYTHON"); env && *env) candidates.emplace_back(env);
  candidates.emplace_back("python3");
  candidates.emplace_back("/usr/bin/python3");
  for (const auto& c : candidates)
    if (run_program({c, "-c", "import matplotlib"}, ChildOutput::Discard).status == 0) return c;
  return {};
}

void run(const AccuracyOptions& o) {
  if (o.rules.empty()) throw InvalidArgument("--rules needs at least one rule set");
  // Every argument is checked before the suite prints or runs anything.
  const std::vector<std::string> known = accuracy::suite_test_names();
  for (const auto& t : o.tests)
    if (std::find(known.begin(), known.end(), t) == known.end()) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      throw InvalidArgument("--tests: unknown test '" + t + "'; valid tests: " + list);
    }
  for (const auto& r : o.rules) make_rule_set(r);  // throws naming the valid presets
  if (!o.csv.empty()) check_output_file("--csv", o.csv);
  if (!o.out.empty()) prepare_output_folder("--out", o.out);
  accuracy::SuiteOptions base;
  base.backend = parse_backend(o.backend);
  base.threads = o.threads;
  base.seed = o.seed;
  base.quick = o.quick;
  base.sparse = !o.dense;
  base.material = accuracy::target_material(o.material);
  base.lut_cache_dir = o.cache_dir;
  base.log = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };

  if (!o.json) std::printf("calibration    %s (rules with the motion model: per configuration)\n", base.calibration.describe().c_str());
  std::vector<accuracy::SuiteReport> reports;
  for (const auto& rules : o.rules) {
    accuracy::SuiteOptions options = base;
    options.rules = rules;
    options.calibration = accuracy::calibration_for(*make_rule_set(rules));
    std::fprintf(stderr, "-- rules %s\n", rules.c_str());
    reports.push_back(accuracy::run_suite(options, o.tests));
    if (!o.json) std::printf("\n%s", accuracy::report_text(reports.back()).c_str());
  }
  const std::string json = accuracy::report_json(reports, base.calibration, accuracy::current_run_info(command_line(o)));
  if (o.json) std::cout << json;
  if (!o.csv.empty()) write_output_file(o.csv, accuracy::report_csv(reports));
  if (!o.out.empty()) {
    const auto json_path = std::filesystem::path(o.out) / "accuracy.json";
    write_output_file(json_path, json);
    const std::filesystem::path script = accuracy_plot_script();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(script, ec)) {
      std::fprintf(stderr, "notice: the plot script %s is missing; %s is written, no plots\n", script.c_str(),
                   json_path.c_str());
    } else if (const std::string python = plotting_python(); python.empty()) {
      std::fprintf(stderr, "notice: no python3 with matplotlib found (set $GRANULAR_PYTHON) to run %s; %s is written, no plots\n",
                   script.c_str(), json_path.c_str());
    } else {
      // "--out=DIR" and "--" keep a folder whose name starts with '-' a value, not an option.
      const std::vector<std::string> command = {python, script.string(), "--out=" + o.out, "--", json_path.string()};
      std::fprintf(stderr, "plots: %s\n", shell_words(command).c_str());
      if (const ChildResult plotted = run_program(command); plotted.status != 0)
        std::fprintf(stderr, "notice: the plot script failed (%s); %s is written\n",
                     plotted.started ? ("exit status " + std::to_string(plotted.status)).c_str() : plotted.why.c_str(),
                     json_path.c_str());
    }
  }
  // Conservation and determinism are absolutes, not physics targets: a failure is an error.
  for (const auto& r : reports) {
    if (!r.conserved()) throw Error("grains were not conserved under rules '" + r.config.rules + "' (see the report)");
    for (const auto& t : r.tests)
      if (t.test == "conservation")
        for (const auto& m : t.metrics)
          if (!m.met())
            throw Error("conservation test failed under rules '" + r.config.rules + "': " + m.name + " = " +
                        std::to_string(m.measured) + " (see the report)");
  }
}

}  // namespace

void add_accuracy_command(CLI::App& app) {
  auto o = std::make_shared<AccuracyOptions>();
  CLI::App* cmd = app.add_subcommand("accuracy", "measure the simulation against physical references");
  cmd->add_option("--rules", o->rules, "rule sets to compare, comma-separated; each one of " + rule_preset_choices())
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--tests", o->tests, "tests to run, comma-separated; each one of " + choices_text(accuracy::suite_test_names()))
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--backend", o->backend, "compute backend: cpu, cuda or auto")->capture_default_str();
  add_number_option(*cmd, "-j,--threads", o->threads, threads_range(), "CPU threads (0 = all)");
  add_number_option(*cmd, "--seed", o->seed, {}, "world seed");
  cmd->add_option("--material", o->material, "target material for the repose angle: sand (33 deg) or glass (24 deg)")
      ->capture_default_str();
  cmd->add_flag("--quick", o->quick, "reduced sizes (CI; 15 s to 3 minutes per rule set on 2 cores); default: full size, for a GPU");
  cmd->add_flag("--dense", o->dense, "step every block every tick (default: sparse, the same results)");
  cmd->add_flag("--json", o->json, "print the report as JSON instead of text");
  cmd->add_option("--csv", o->csv, "also write one CSV row per metric to this file")->check(non_empty_path());
  cmd->add_option("--out", o->out, "write accuracy.json and one PNG per test (python3 + matplotlib) into this folder")
      ->check(non_empty_path());
  cmd->add_option("--cache-dir", o->cache_dir, "table cache folder (default: $GRANULAR_CACHE_DIR or ~/.cache/granular)")
      ->check(non_empty_path());
  cmd->callback([o] { run(*o); });
}

}  // namespace granular::cli
