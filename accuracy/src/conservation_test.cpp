#include <algorithm>
#include <chrono>
#include <random>
#include <string>
#include <vector>

#include "granular/extend/hex.hpp"
#include "granular/rule_presets.hpp"
#include "granular/world.hpp"
#include "suite_tests.hpp"

namespace granular::accuracy {

namespace {

/// A random grid: void, solid, granular (10% solid, 35% granular), or uniform over all 8 states.
Grid random_scene(Int3 size, std::uint64_t seed, bool all_states) {
  Grid g(size);
  std::mt19937_64 rng(seed);
  for (auto& c : g.cells()) {
    const std::uint64_t v = rng() % 100;
    c = all_states ? std::uint8_t(rng() % kMaterialCount)
        : v < 10   ? to_cell(Material::Solid)
        : v < 45   ? to_cell(Material::Granular)
                   : to_cell(Material::Void);
  }
  return g;
}

}  // namespace

TestReport run_conservation_test(const SuiteOptions& o, const std::vector<TestReport>& earlier) {
  struct Scene {
    Int3 size;
    bool all_states;
    std::uint64_t ticks;
    std::vector<int> cpu_threads;  ///< CPU thread counts the configured backend is compared with
  };
  // Full size: 10^6 ticks of the first scene against the CPU on 1 thread, 10^5 of the second on 1
  // and 3 threads; quick: 2 x 10^4 ticks of each on 1, 2 and 3 threads (hashes compared after
  // ticks / substeps ticks, see below).
  const std::vector<Scene> scenes =
      o.quick ? std::vector<Scene>{{{24, 24, 24}, false, 20000, {1, 2, 3}}, {{23, 17, 29}, true, 20000, {1, 2, 3}}}
              : std::vector<Scene>{{{32, 32, 32}, false, 1000000, {1}}, {{31, 29, 33}, true, 100000, {1, 3}}};
  std::string scene = "random scenes";
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    const Scene& sc = scenes[i];
    scene += std::string(i ? ";" : "") + " " + std::to_string(sc.size.x) + "x" + std::to_string(sc.size.y) + "x" +
             std::to_string(sc.size.z) + (sc.all_states ? " (all 8 states, " : " (void/solid/granular, ") +
             std::to_string(sc.ticks) + " ticks) on the configured backend and the CPU with";
    for (std::size_t k = 0; k < sc.cpu_threads.size(); ++k)
      scene += (k == 0 ? " " : ", ") + std::to_string(sc.cpu_threads[k]);
    scene += std::string(sc.cpu_threads.size() == 1 ? " thread" : " threads") + " (and the last with the other stepping)";
  }
  const int rule_substeps = std::max(1, make_rule_set(o.rules)->motion.substeps);
  if (rule_substeps > 1)
    scene += "; with " + std::to_string(rule_substeps) +
             " sub-steps per tick the other runs stop, and all hashes are compared, after ticks / " +
             std::to_string(rule_substeps) + " ticks (the same number of Margolus steps)";
  TestReport r = open_report(o, "conservation",
                             "Conservation and stability: exact counts, one hash per seed on every thread count and backend", scene);
  double count_errors = 0, hash_mismatches = 0;
  Series runs{"hash agreement per run (1 = same as the first)", "run", "agrees", {}, {}, false};
  const auto start = std::chrono::steady_clock::now();
  int run_index = 0;
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    const Grid initial = random_scene(scenes[s].size, o.seed * 1000 + s, scenes[s].all_states);
    const MaterialCounts expected = initial.count();
    std::uint64_t reference_hash = 0;
    bool first = true;
    std::vector<SuiteOptions> variants;
    variants.push_back(o);
    for (int threads : scenes[s].cpu_threads) {
      SuiteOptions cpu = o;
      cpu.backend = BackendKind::Cpu;
      cpu.threads = threads;
      variants.push_back(cpu);
    }
    SuiteOptions other_stepping = variants.back();  // sparse and dense stepping give the same grid
    other_stepping.sparse = !o.sparse;
    variants.push_back(other_stepping);
    // The hashes are compared after the same number of Margolus steps for every rule set: with
    // the motion model (substeps per tick) the comparison runs ticks / substeps ticks, and only the
    // configured backend goes on to all the ticks, its counts checked at the end.
    const int substeps = rule_substeps;
    const std::uint64_t compared = std::max<std::uint64_t>(1, scenes[s].ticks / std::uint64_t(substeps));
    for (std::size_t k = 0; k < variants.size(); ++k) {
      const SuiteOptions& v = variants[k];
      World world(test_world_def(v, scenes[s].size), initial);
      world.step(int(compared));
      const std::uint64_t h = world.hash();
      const std::uint64_t ticks = k == 0 ? scenes[s].ticks : compared;
      if (ticks > compared) world.step(int(ticks - compared));
      r.ticks += ticks;
      r.cell_updates += double(initial.cell_count()) * double(ticks) * substeps;
      const bool counts_ok = world.count() == expected;
      count_errors += counts_ok ? 0 : 1;
      if (first) reference_hash = h;
      const bool same = h == reference_hash;
      hash_mismatches += same ? 0 : 1;
      first = false;
      runs.x.push_back(++run_index);
      runs.y.push_back(same ? 1 : 0);
      const std::string what = world.backend_description() + (v.sparse ? ", sparse" : ", dense");
      log_line(o, "  " + what + ": hash " + hex64(h) + (counts_ok ? "" : ", COUNTS CHANGED"));
      if (!same || !counts_ok)
        r.notes.push_back("scene " + std::to_string(s) + " on " + what + ": hash " + hex64(h) +
                          " vs " + hex64(reference_hash) + (counts_ok ? "" : ", counts changed"));
    }
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.conserved = count_errors == 0;
  double tests_not_conserved = 0;
  for (const TestReport& t : earlier)
    if (!t.conserved) {
      tests_not_conserved += 1;
      r.notes.push_back("test '" + t.test + "' did not conserve its grains");
    }
  const std::string exact = "absolute: the rules are permutations";
  r.metrics.push_back({"count_changes_random_scenes", "runs", count_errors, 0, 0.5, exact});
  r.metrics.push_back({"hash_mismatches", "runs", hash_mismatches, 0, 0.5, "absolute: same seed, same hash on every backend and thread count"});
  r.metrics.push_back({"tests_not_conserving", "tests", tests_not_conserved, 0, 0.5, exact});
  r.series.push_back(runs);
  return r;
}

}  // namespace granular::accuracy
