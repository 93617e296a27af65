/// @file bench_tools.cpp
/// What a tool call costs, through World as a game calls it: dig, pour and paint of a radius-8
/// sphere in a 512x512x256 world (sand up to a quarter of its height, air above), on the CPU and,
/// when this build has it and a device is usable, the CUDA backend; then a read_region of the box
/// such a sphere covers (the read alone), and load and snapshot of the whole grid, the largest
/// writer and reader. No step runs between the calls, so the figures are the
/// tools' own. Figures in bench/RESULTS.md.
///
///   bench_tools [--backend cpu|cuda|all] [--calls N] [--size X Y Z] [--radius R] [--rules NAME]
///               [--threads J] [--dense]
///
/// --dense steps densely (WorldDef::sparse = false). The CPU backend's sparse stepping rebuilds its
/// list of awake bricks at every write that wakes one (about 100 µs), which hides the host work a
/// tool shares with the CUDA backend; dense, a CPU tool call is that host work and the cells' copy.
///
/// Last, in the game's loop: step(1) alone against step(1) followed by a pour, interleaved call by
/// call, so that their difference is what the pour adds to a tick, its wake included (the CUDA
/// backend wakes the bricks of all writes since the last step at the start of the next).
///
/// Per row: calls timed, how many changed cells (a read: returned cells), the mean microseconds per call (the whole run of
/// calls and one read of a cell after the last, which waits for any write still on its way, divided
/// by the calls), and the median and 99th percentile of the single calls. It uses only World's
/// public calls, so the same source builds against any version of the library.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "granular/errors.hpp"
#include "granular/world.hpp"

namespace {

using namespace granular;
using Clock = std::chrono::steady_clock;

/// The command line (see the file comment).
struct Options {
  std::string backend = "all";  ///< cpu, cuda or all (cuda only when usable)
  int calls = 2000;             ///< timed calls per tool
  Int3 size{512, 512, 256};     ///< the world
  double radius = 8.0;          ///< the tools' sphere
  std::string rules = WorldDef{}.rules;  ///< rule-set preset
  int threads = 0;              ///< CPU threads (0 = all)
  bool dense = false;           ///< dense stepping (WorldDef::sparse = false)
};

/// Reads the options; throws InvalidArgument for unknown ones or bad values.
Options parse(int argc, char** argv) {
  Options o;
  auto number = [&](int& i) {
    if (i + 1 >= argc) throw InvalidArgument(std::string("bench_tools: ") + argv[i] + " needs a value");
    return std::atof(argv[++i]);
  };
  for (int i = 1; i < argc; ++i) {
    const std::string key = argv[i];
    if (key == "--backend" && i + 1 < argc) o.backend = argv[++i];
    else if (key == "--rules" && i + 1 < argc) o.rules = argv[++i];
    else if (key == "--calls") o.calls = int(number(i));
    else if (key == "--radius") o.radius = number(i);
    else if (key == "--threads") o.threads = int(number(i));
    else if (key == "--dense") o.dense = true;
    else if (key == "--size") {
      o.size.x = int(number(i));
      o.size.y = int(number(i));
      o.size.z = int(number(i));
    } else
      throw InvalidArgument("bench_tools: unknown option or missing value: " + key);
  }
  if (o.backend != "cpu" && o.backend != "cuda" && o.backend != "all")
    throw InvalidArgument("bench_tools: --backend = " + o.backend + "; use cpu, cuda or all");
  if (o.calls < 1) throw InvalidArgument("bench_tools: --calls = " + std::to_string(o.calls) + " must be >= 1");
  if (!(o.radius > 0)) throw InvalidArgument("bench_tools: --radius = " + std::to_string(o.radius) + " must be > 0");
  if (o.size.x < 32 || o.size.y < 32 || o.size.z < 32)
    throw InvalidArgument("bench_tools: --size " + to_string(o.size) + ": every extent must be >= 32");
  return o;
}

/// Prints one row from the single calls' microseconds and the whole run's.
void report(const char* backend, const std::string& what, std::vector<double> us, double total_us, int changed) {
  std::sort(us.begin(), us.end());
  const double median = us[us.size() / 2], p99 = us[std::min(us.size() - 1, us.size() * 99 / 100)];
  std::printf("%-5s %-28s %6zu %8d %10.1f %10.1f %10.1f\n", backend, what.c_str(), us.size(), changed,
              total_us / double(us.size()), median, p99);
  std::fflush(stdout);
}

/// Times `calls` calls of `tool(i)` (which returns whether it changed a cell) and prints their row.
template <class Tool>
void time_calls(const char* backend, const std::string& what, World& world, int calls, Tool&& tool) {
  std::vector<double> us;
  us.reserve(std::size_t(calls));
  int changed = 0;
  const Clock::time_point start = Clock::now();
  for (int i = 0; i < calls; ++i) {
    const Clock::time_point t0 = Clock::now();
    changed += tool(i) ? 1 : 0;
    us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
  }
  (void)world.read_region(Box{{0, 0, 0}, {1, 1, 1}});  // waits for the last write
  const double total = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
  report(backend, what, std::move(us), total, changed);
}

/// Runs every row on one backend.
void run(BackendKind kind, const Options& o) {
  WorldDef def;
  def.size = o.size;
  def.rules = o.rules;
  def.backend = kind;
  def.threads = o.threads;
  def.sparse = !o.dense;
  World world(def);
  const char* name = backend_name(kind);
  std::printf("%s: %s, %s rules, %s world, %s stepping\n", name, world.backend_description().c_str(),
              o.rules.c_str(), to_string(o.size).c_str(), o.dense ? "dense" : "sparse");
  const int surface = o.size.z / 4;
  world.paint(Box{{0, 0, 0}, {o.size.x, o.size.y, surface}}, Material::Granular);

  // Sphere centres spread over the grid, the same for every backend and run.
  const double r = o.radius;
  auto centres = [&](std::uint64_t seed, double z_lo, double z_hi) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> ux(r, o.size.x - r), uy(r, o.size.y - r), uz(z_lo, z_hi);
    std::vector<Vec3> c(std::size_t(o.calls));
    for (Vec3& v : c) v = {ux(rng), uy(rng), uz(rng)};
    return c;
  };
  const std::vector<Vec3> at_surface = centres(1, surface - r / 2, surface), in_air = centres(2, surface + 2 * r, o.size.z - r);
  const std::vector<Vec3> in_air_too = centres(3, surface + 2 * r, o.size.z - r);
  const std::vector<Vec3> in_loop = centres(4, surface + 2 * r, o.size.z - r);

  std::printf("%-5s %-28s %6s %8s %10s %10s %10s\n", "", "call", "calls", "changed", "mean_us", "median_us", "p99_us");
  char label[64];
  std::snprintf(label, sizeof label, "dig r=%g", r);
  time_calls(name, label, world, o.calls,
             [&](int i) { return world.dig(Sphere{at_surface[std::size_t(i)], r}).cells_changed > 0; });
  std::snprintf(label, sizeof label, "pour r=%g amount=200", r);
  time_calls(name, label, world, o.calls, [&](int i) {
    return world.pour(in_air[std::size_t(i)], r, Material::Granular, 200).cells_changed > 0;
  });
  std::snprintf(label, sizeof label, "paint sphere r=%g", r);
  time_calls(name, label, world, o.calls, [&](int i) {
    return world.paint(Sphere{in_air_too[std::size_t(i)], r}, Material::Solid).cells_changed > 0;
  });

  // The read alone (one round trip), over the box a radius-r sphere covers.
  const int w = 2 * int(std::ceil(r)) + 1;
  std::snprintf(label, sizeof label, "read_region %dx%dx%d", w, w, w);
  time_calls(name, label, world, o.calls, [&](int i) {
    const Vec3 c = in_air[std::size_t(i)];
    const Int3 lo{std::clamp(int(c.x) - w / 2, 0, o.size.x - w), std::clamp(int(c.y) - w / 2, 0, o.size.y - w),
                  std::clamp(int(c.z) - w / 2, 0, o.size.z - w)};
    return !world.read_region(Box{lo, {lo.x + w, lo.y + w, lo.z + w}}).empty();
  });

  // The whole grid: load alternates two grids so each call changes cells.
  Grid a = world.read_grid(), b = a;
  b.set({0, 0, o.size.z - 1}, Material::Solid);
  const int whole = 3;
  time_calls(name, "load (whole grid)", world, whole, [&](int i) {
    world.load(i % 2 == 0 ? b : a);
    return true;
  });
  time_calls(name, "snapshot (whole grid)", world, whole, [&](int) { return world.read_grid().cell_count() > 0; });

  // The game's loop: a tick alone, and a tick with a pour, by turns.
  const int ticks = std::max(1, o.calls / 10);
  std::vector<double> alone, with_pour;
  int poured = 0;
  for (int i = 0; i < 2 * ticks; ++i) {
    const Clock::time_point t0 = Clock::now();
    world.step(1);
    if (i % 2 == 1) poured += world.pour(in_loop[std::size_t(i / 2)], r, Material::Granular, 200).cells_changed > 0;
    (void)world.read_region(Box{{0, 0, 0}, {1, 1, 1}});  // waits for the device
    (i % 2 == 0 ? alone : with_pour).push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
  }
  auto sum = [](const std::vector<double>& v) { double t = 0; for (const double x : v) t += x; return t; };
  report(name, "step(1)", alone, sum(alone), 0);
  std::snprintf(label, sizeof label, "step(1) + pour r=%g", r);
  report(name, label, with_pour, sum(with_pour), poured);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    if (o.backend != "cuda") run(BackendKind::Cpu, o);
    if (o.backend != "cpu") {
      WorldDef probe;
      probe.size = {8, 8, 8};
      probe.rules = o.rules;
      probe.backend = BackendKind::Auto;
      const bool usable = World(probe).backend() == BackendKind::Cuda;
      if (usable)
        run(BackendKind::Cuda, o);
      else if (o.backend == "cuda")
        throw BackendError("bench_tools: --backend cuda, but no CUDA backend is usable here");
      else
        std::printf("cuda: not usable here (no device or no CUDA build); skipped\n");
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_tools: %s\n", e.what());
    return 1;
  }
}
