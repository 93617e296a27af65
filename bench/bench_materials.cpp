/// @file bench_materials.cpp
/// Every material of the presets' table moving at once, and at rest, through World on either
/// backend (figures in bench/RESULTS.md):
///
/// 1. *Mixed*: an N^3 world released at tick 0: a water column at one end breaks over the
///    floor (a dam break), a block of sand falls into a water pool with gas pockets at its bottom,
///    and a block of gravel falls onto a sand bed. ms per tick over --ticks ticks from release, and
///    the real-time factor (granular::tick_seconds of the rules, time_scale.hpp, over the time per tick).
/// 2. *Settled*: in an N^3 world, a pool (water in full layers in a walled basin) beside a sand pile
///    and a gravel pile left by collapsing columns, stepped until no brick is awake (at most
///    --max-ticks) beside a dense world whose hash must equal it every 64 ticks (up to
///    --dense-until); then ms per tick of the dense and the sparse world at rest, and their ratio.
///
///   bench_materials [--backend cpu|cuda] [--n N] [--ticks T] [--max-ticks M] [--dense-until D] [--threads J]
///                   [--rules R]
/// 3. *Scenes*: with --scene-ticks T > 0, each shipped scene of water, gas and gravel (dam_break,
///    u_tube, sand_into_water, bubbles, gravel_and_sand; docs/SCENES.md) at --scene-n (0: its default
///    N), emitters included, for T ticks: ms per tick and the real-time factor.
/// Exit status 1 when the dense and sparse worlds' hashes differ or a material count changes.

#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "granular/errors.hpp"
#include "granular/scene.hpp"
#include "granular/time_scale.hpp"
#include "granular/world.hpp"
#include "timed_step.hpp"

namespace {

using namespace granular;
using bench::timed_step;

/// The command line (see the file comment).
struct Options {
  std::string backend = "cpu";  ///< cpu or cuda
  int n = 128;                  ///< world size N
  int ticks = 256;              ///< ticks of the mixed measurement
  int max_ticks = 20000;        ///< the settled world stops here even if not at rest
  int dense_until = 1 << 30;    ///< the dense world steps beside the sparse one up to this tick
  int scene_ticks = 0;          ///< ticks of each shipped fluid scene (0: none)
  int scene_n = 0;              ///< the scenes' N (0: each scene's default)
  int threads = 0;              ///< CPU threads (0 = all)
  std::string rules = WorldDef{}.rules;  ///< rule-set preset
};

/// Reads the options; throws InvalidArgument for unknown ones or bad values.
Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; i += 2) {
    const std::string key = argv[i];
    if (i + 1 >= argc) throw InvalidArgument("bench_materials: " + key + " needs a value");
    const std::string value = argv[i + 1];
    if (key == "--backend") o.backend = value;
    else if (key == "--n") o.n = std::atoi(value.c_str());
    else if (key == "--ticks") o.ticks = std::atoi(value.c_str());
    else if (key == "--max-ticks") o.max_ticks = std::atoi(value.c_str());
    else if (key == "--threads") o.threads = std::atoi(value.c_str());
    else if (key == "--dense-until") o.dense_until = std::atoi(value.c_str());
    else if (key == "--scene-ticks") o.scene_ticks = std::atoi(value.c_str());
    else if (key == "--scene-n") o.scene_n = std::atoi(value.c_str());
    else if (key == "--rules") o.rules = value;
    else throw InvalidArgument("bench_materials: unknown option " + key);
  }
  if (o.backend != "cpu" && o.backend != "cuda") throw InvalidArgument("bench_materials: --backend " + o.backend + " (cpu or cuda)");
  if (o.n < 32 || o.n % 16 != 0) throw InvalidArgument("bench_materials: --n " + std::to_string(o.n) + " (a multiple of 16, >= 32)");
  if (o.ticks < 1 || o.max_ticks < 1) throw InvalidArgument("bench_materials: --ticks and --max-ticks must be >= 1");
  if (o.scene_ticks < 0 || o.scene_n < 0) throw InvalidArgument("bench_materials: --scene-ticks and --scene-n must be >= 0");
  return o;
}

WorldDef def_for(const Options& o, Int3 size, bool sparse) {
  WorldDef def;
  def.size = size;
  def.backend = o.backend == "cuda" ? BackendKind::Cuda : BackendKind::Cpu;
  def.threads = o.threads;
  def.sparse = sparse;
  def.rules = o.rules;
  return def;
}

/// The mixed scene of N (see the file comment), on a floor, in an N^3 world.
void paint_mixed(World& w, int n) {
  const int h = n, f = n / 32;  // height, floor thickness
  w.paint(Box{{0, 0, 0}, {n, n, f}}, Material::Solid);
  // Dam break: water 3/16 N long and 3/8 N high along the x = 0 wall, over half the y extent.
  w.paint(Box{{0, 0, f}, {3 * n / 16, n / 2, f + 3 * h / 8}}, Material::Liquid);
  // A walled pool in the far half, water to h/4 with gas pockets at its bottom; sand above it.
  const int px0 = n / 2, py0 = n / 2, px1 = n - f, py1 = n - f, wall = f + h / 3;
  w.paint(Box{{px0 - f, py0 - f, f}, {n, n, wall}}, Material::Solid);
  w.paint(Box{{px0, py0, f}, {px1, py1, f + h / 4}}, Material::Liquid);
  for (int k = 0; k < 4; ++k) {
    const int x = px0 + (k + 1) * (px1 - px0) / 5;
    w.paint(Box{{x - 2, py0 + 4, f + 1}, {x + 2, py1 - 4, f + 3}}, Material::Gas);
  }
  w.paint(Box{{px0 + n / 8, py0 + n / 8, h - n / 8}, {px1 - n / 8, py1 - n / 8, h - n / 32}}, Material::Granular);
  // A sand bed in the near right quarter and a gravel block falling onto it.
  w.paint(Box{{n / 2, 0, f}, {n, n / 2 - f, f + n / 16}}, Material::Granular);
  w.paint(Box{{5 * n / 8, n / 8, h - n / 6}, {7 * n / 8, 3 * n / 8, h - n / 16}}, Material::Gravel);
}

/// The settled scene of N, in the lower half of the world: a basin of water in full layers, and
/// collapsing sand and gravel columns.
void paint_settled(World& w, int n) {
  const int h = n / 2, f = n / 32;
  w.paint(Box{{0, 0, 0}, {n, n, f}}, Material::Solid);
  w.paint(Box{{0, 0, f}, {n / 2, n, f + h / 3}}, Material::Solid);
  w.paint(Box{{f, f, f + 1}, {n / 2 - f, n - f, f + h / 3}}, Material::Void);
  w.paint(Box{{f, f, f + 1}, {n / 2 - f, n - f, f + h / 4}}, Material::Liquid);
  w.paint(Box{{5 * n / 8, n / 8, f}, {6 * n / 8, 2 * n / 8, f + h / 2}}, Material::Granular);
  w.paint(Box{{5 * n / 8, 5 * n / 8, f}, {6 * n / 8, 6 * n / 8, f + h / 2}}, Material::Gravel);
}

/// Part 3: each shipped fluid scene for o.scene_ticks ticks; returns false when a count is off.
bool run_scenes(const Options& o) {
  for (const char* name : {"dam_break", "u_tube", "sand_into_water", "bubbles", "gravel_and_sand"}) {
    const SceneInstance scene = instantiate(load_scene(find_scene(name)), o.scene_n);
    World world(def_for(o, scene.grid.size(), true), scene.grid);
    const MaterialCounts before = world.count();
    MaterialCounts poured{};
    double seconds = 0;
    for (int t = 0; t < o.scene_ticks; ++t) {
      const MaterialCounts p = run_emitters(world, scene.emitters);
      for (int m = 0; m < kMaterialCount; ++m) poured[m] += p[m];
      seconds += timed_step(world, 1);
    }
    const MaterialCounts expected = counts_after_pouring(before, poured);
    const double ms = seconds * 1000.0 / o.scene_ticks, tick_ms = tick_seconds(world.rules()) * 1000.0;
    std::printf("scene %-16s %dx%dx%d: %.4f ms/tick over %d ticks (%.2fx real time)%s\n", name, world.size().x,
                world.size().y, world.size().z, ms, o.scene_ticks, tick_ms / ms,
                world.count() == expected ? "" : "; material counts CHANGED");
    if (world.count() != expected) return false;
  }
  return true;
}

int run(const Options& o) {
  if (o.scene_ticks > 0 && !run_scenes(o)) return 1;
  const Int3 size{o.n, o.n, o.n};
  World mixed(def_for(o, size, true));
  paint_mixed(mixed, o.n);
  const MaterialCounts before = mixed.count();
  mixed.step(8);  // the first cycle: tables warm, every brick awake
  const double s = timed_step(mixed, o.ticks);
  const double ms = s * 1000.0 / o.ticks;
  const ActivityStats a = mixed.activity();
  std::printf("bench_materials: %s, rules %s, %dx%dx%d\n", mixed.backend_description().c_str(), o.rules.c_str(), size.x,
              size.y, size.z);
  const double tick_ms = tick_seconds(mixed.rules()) * 1000.0;
  std::printf("mixed: %.4f ms/tick over %d ticks from release (%.2fx real time: a tick is %.2f ms); %llu of %llu bricks awake at the end\n",
              ms, o.ticks, tick_ms / ms, tick_ms, static_cast<unsigned long long>(a.active_bricks),
              static_cast<unsigned long long>(a.total_bricks));
  if (mixed.count() != before) {
    std::fprintf(stderr, "bench_materials: the mixed world's material counts changed\n");
    return 1;
  }

  // Side by side with a dense world, hashes compared every window, up to --dense-until.
  World sparse(def_for(o, size, true)), dense(def_for(o, size, false));
  paint_settled(sparse, o.n);
  paint_settled(dense, o.n);
  int rest = 0;
  while (int(sparse.tick()) < o.max_ticks) {
    sparse.step(64);
    if (int(dense.tick()) < o.dense_until) {
      dense.step(64);
      if (dense.hash() != sparse.hash()) {
        std::fprintf(stderr, "bench_materials: dense and sparse differ at tick %llu\n",
                     static_cast<unsigned long long>(sparse.tick()));
        return 1;
      }
    }
    if (sparse.activity().brick_ticks == 0) {
      rest = int(sparse.tick());
      break;
    }
  }
  const std::uint64_t compared = dense.tick();
  // At rest no block can change under any draw, so two fresh worlds from the resting state (every
  // cell at rest, the same bytes) step exactly as the side-by-side pair would have; a world not at
  // rest is timed and compared as the pair stands.
  const bool take_over = rest > 0 && dense.tick() != sparse.tick();
  const bool comparable = take_over || dense.tick() == sparse.tick();
  std::optional<World> fresh_dense, fresh_sparse;
  if (take_over) {
    const Grid resting = sparse.read_grid();
    fresh_dense.emplace(def_for(o, size, false), resting);
    fresh_sparse.emplace(def_for(o, size, true), resting);
  }
  World& d = take_over ? *fresh_dense : dense;
  World& sp = take_over ? *fresh_sparse : sparse;
  sp.step(64);  // the fresh sparse world's first cycle finds every brick asleep
  d.step(64);
  double dense_s = 0, sparse_s = 0;
  for (int r = 0; r < 4; ++r) {
    dense_s += timed_step(d, 64);
    sparse_s += timed_step(sp, 64);
  }
  const double dense_ms = dense_s * 1000.0 / 256, sparse_ms = sparse_s * 1000.0 / 256;
  std::printf("settled: %s; dense and sparse equal over the first %llu ticks; dense %.4f ms/tick, sparse %.6f "
              "ms/tick: %.0fx; %llu bricks awake\n",
              rest > 0 ? ("at rest after " + std::to_string(rest) + " ticks (no brick awake)").c_str()
                       : "NOT at rest by --max-ticks",
              static_cast<unsigned long long>(compared), dense_ms, sparse_ms, dense_ms / sparse_ms,
              static_cast<unsigned long long>(sp.activity().active_bricks));
  if (comparable && d.hash() != sp.hash()) {
    std::fprintf(stderr, "bench_materials: dense and sparse differ after the settled measurement\n");
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse(argc, argv));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
