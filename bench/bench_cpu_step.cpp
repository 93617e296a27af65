/// @file bench_cpu_step.cpp
/// CPU step throughput on the paper's bowl scene: the backend (dense stepping) against the plain
/// per-block loop, in the same process, over the same ticks; and the settled bowl stepped dense
/// against sparse. Reports cell-updates per second (grid cells times ticks, stepped or skipped).
///
///   build/bench/bench_cpu_step [--benchmark_filter=...]   (environment: GRANULAR_BENCH_N, default 256)

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <map>
#include <memory>

#include "granular/extend/lut.hpp"
#include "granular/rule_presets.hpp"
#include "granular/scene.hpp"
#include "granular/world.hpp"
#include "plain_step.hpp"
#include "cpu/thread_pool.hpp"

namespace {

using namespace granular;

/// Ticks measured per benchmark iteration: one full 8-offset cycle, times 4.
constexpr int kTicksPerIteration = 32;

int bench_n() {
  const char* n = std::getenv("GRANULAR_BENCH_N");
  return n ? std::atoi(n) : 256;
}

/// The bowl scene advanced to the start of a phase, computed once per phase and reused.
const Grid& bowl_at(int start_tick) {
  static std::map<int, Grid> cache;
  auto it = cache.find(start_tick);
  if (it != cache.end()) return it->second;
  const SceneInstance inst = instantiate(load_scene(find_scene("bowl")), bench_n());
  WorldDef def;
  def.rules = "paper";  // the plain loop runs the paper's table
  def.backend = BackendKind::Cpu;
  World w(def, inst.grid);
  w.step(start_tick);
  return cache.emplace(start_tick, w.read_grid()).first->second;
}

void report(benchmark::State& state, const Grid& g) {
  state.counters["cell_updates_per_s"] = benchmark::Counter(
      double(g.cell_count()) * kTicksPerIteration * double(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["N"] = double(g.size().x);
}

void BM_Backend(benchmark::State& state) {
  const int start = int(state.range(0)), threads = int(state.range(1));
  const Grid& g = bowl_at(start);
  WorldDef def;
  def.rules = "paper";  // the plain loop runs the paper's table
  def.backend = BackendKind::Cpu;
  def.threads = threads;
  def.sparse = false;
  const World keep_tables_alive(def, g);  // worlds of one process share the 64 MiB tables
  for (auto _ : state) {
    state.PauseTiming();
    World w(def, g);  // phase starts are multiples of 8, so tick 0 has the original offset
    state.ResumeTiming();
    w.step(kTicksPerIteration);
    benchmark::DoNotOptimize(w.tick());
  }
  report(state, g);
}

void BM_PlainLoop(benchmark::State& state) {
  const int start = int(state.range(0)), threads = int(state.range(1));
  const Grid& g = bowl_at(start);
  const auto rules = make_rule_set("paper");
  const auto lut = obtain_lut(*rules).lut;
  const reference::PlainRules plain = reference::plain_rules(*rules, *lut, 0);
  for (auto _ : state) {
    state.PauseTiming();
    Grid work = g;
    state.ResumeTiming();
    for (int t = 0; t < kTicksPerIteration; ++t)
      reference::plain_step(work.cells(), work.size(), plain, std::uint64_t(start + t), threads);
    benchmark::DoNotOptimize(work.cells().data());
  }
  report(state, g);
}

/// The bowl at rest (tick 10240; at N = 256 the last grain stops near tick 9400), stepped dense
/// (range 0) or sparse (range 1) on all hardware threads. The sparse world first runs 3 cycles, so
/// that it has found out what sleeps.
void BM_Settled(benchmark::State& state) {
  const bool sparse = state.range(0) != 0;
  const Grid& g = bowl_at(10240);
  WorldDef def;
  def.backend = BackendKind::Cpu;
  def.sparse = sparse;
  World w(def, g);
  w.step(24);
  for (auto _ : state) {
    w.step(kTicksPerIteration);
    benchmark::DoNotOptimize(w.tick());
  }
  state.counters["active_bricks"] = double(w.activity().active_bricks);
  report(state, g);
}

// Phases of the bowl run: 0 = released, 128 = falling onto the bowl, 1024 = piling, 4096 = settled.
void phases(benchmark::internal::Benchmark* b) {
  for (int start : {0, 128, 1024, 4096})
    for (int threads : {1, granular::hardware_threads()}) b->Args({start, threads});
  b->ArgNames({"tick", "threads"})->Unit(benchmark::kMillisecond)->UseRealTime();
}

}  // namespace

BENCHMARK(BM_Backend)->Apply(phases);
BENCHMARK(BM_PlainLoop)->Apply(phases);
BENCHMARK(BM_Settled)->ArgName("sparse")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
