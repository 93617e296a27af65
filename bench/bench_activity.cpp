/// @file bench_activity.cpp
/// Sparse against dense stepping on the bowl scene, through World, on either backend, in one
/// process (docs/design/sparse-stepping.md; figures in bench/RESULTS.md):
///
/// 1. *Series*: a dense and a sparse world step the bowl side by side from release to rest; per
///    window of ticks, the wall time per tick of each and the sparse world's mean active cells and
///    bricks go to `activity_<backend>_<N>.csv` (plot: bench/plot_activity.py). The hashes are
///    compared after every window (a mismatch is an error, exit status 1). After --series-seconds
///    of wall time the sparse world goes on alone (no CSV rows) until it is at rest or reaches
///    --max-ticks, and the dense world loads its state.
/// 2. *Settled*: from the final state, ms per tick dense and sparse, and their ratio.
/// 3. *Pour*: sand poured every tick into a closed 64^3 cup at the top corner of the settled world,
///    against the same pour into a 64^3 world alone (both sparse); ms per tick of the steps.
///
///   bench_activity [--backend cpu|cuda] [--n N] [--max-ticks T] [--window W] [--threads J]
///                  [--series-seconds S] [--pour-ticks P] [--dense-fraction F] [--rules R] [--out DIR]
/// --dense-fraction sets the sparse worlds' WorldDef::cuda.dense_fraction and motion_dense_fraction (CUDA: above this awake
/// fraction a step uses dense-recording ticks; 1 = sparse ticks only, as before that existed).
/// Prints a short table last.

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "granular/errors.hpp"
#include "granular/extend/hex.hpp"
#include "granular/scene.hpp"
#include "granular/world.hpp"
#include "timed_step.hpp"

namespace {

using namespace granular;
using bench::timed_step;

/// The command line (see the file comment).
struct Options {
  std::string backend = "cpu";  ///< cpu or cuda
  int n = 256;                  ///< bowl size N
  int max_ticks = 8192;         ///< the sparse world stops here even if not at rest
  int window = 64;              ///< ticks per step call and CSV row (a multiple of 8)
  int threads = 0;              ///< CPU threads (0 = all)
  int pour_ticks = 512;         ///< ticks of the pour measurement (0 = none)
  int cup = 64;                 ///< edge of the pour's cup and of the world alone
  double series_seconds = 1e9;  ///< stepping time after which the side-by-side series stops
  double dense_fraction = CudaOptions{}.dense_fraction;  ///< the sparse worlds' WorldDef::cuda.dense_fraction
  std::string out = ".";        ///< folder of the CSV
  std::string rules = WorldDef{}.rules;  ///< rule-set preset
};

/// Reads the options; throws InvalidArgument for unknown ones or bad values.
Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--backend") o.backend = value;
    else if (key == "--n") o.n = std::atoi(value.c_str());
    else if (key == "--max-ticks") o.max_ticks = std::atoi(value.c_str());
    else if (key == "--window") o.window = std::atoi(value.c_str());
    else if (key == "--threads") o.threads = std::atoi(value.c_str());
    else if (key == "--pour-ticks") o.pour_ticks = std::atoi(value.c_str());
    else if (key == "--series-seconds") o.series_seconds = std::atof(value.c_str());
    else if (key == "--dense-fraction") o.dense_fraction = std::atof(value.c_str());
    else if (key == "--rules") o.rules = value;
    else if (key == "--out") o.out = value;
    else throw InvalidArgument("bench_activity: unknown option " + key + " (see the file comment for the options)");
  }
  if (o.backend != "cpu" && o.backend != "cuda") throw InvalidArgument("bench_activity: --backend is cpu or cuda");
  if (o.window < 8 || o.window % 8 != 0) throw InvalidArgument("bench_activity: --window must be a multiple of 8");
  return o;
}

/// The bench's world definition: backend and threads from the options, sparse or dense.
WorldDef def_for(const Options& o, bool sparse) {
  WorldDef def;
  def.backend = o.backend == "cuda" ? BackendKind::Cuda : BackendKind::Cpu;
  def.threads = o.threads;
  def.sparse = sparse;
  def.cuda.dense_fraction = def.cuda.motion_dense_fraction = o.dense_fraction;
  def.rules = o.rules;
  return def;
}

/// A closed cup: solid floor and walls around the box [0, cup)^2 x [top - cup, top) (the grid's
/// own edges close the other sides), so that what is poured in stays in a cup^3 region, as in a
/// world of cup^3 cells whose outside reads as solid.
void paint_cup(World& world, int cup) {
  const Int3 n = world.size();
  const int z0 = n.z - cup;
  world.paint(Box{{0, 0, z0 - 2}, {cup + 2, cup + 2, z0}}, Material::Solid);
  world.paint(Box{{cup, 0, z0 - 2}, {cup + 2, cup + 2, n.z}}, Material::Solid);
  world.paint(Box{{0, cup, z0 - 2}, {cup + 2, cup + 2, n.z}}, Material::Solid);
  world.paint(Box{{0, 0, z0}, {cup, cup, n.z}}, Material::Void);
}

/// Mean ms per tick of `ticks` single-tick steps, each after pouring into the cup at `origin`.
double pour_ms_per_tick(World& world, Int3 origin, int cup, int ticks) {
  double seconds = 0;
  for (int t = 0; t < ticks; ++t) {
    world.pour({origin.x + cup / 2.0, origin.y + cup / 2.0, origin.z + cup - 6.0}, 4, Material::Granular, 12);
    seconds += timed_step(world, 1);
  }
  return seconds * 1000.0 / ticks;
}

/// Runs the three measurements and prints the table; returns the exit status.
int run(const Options& o) {
  const SceneInstance scene = instantiate(load_scene(find_scene("bowl")), o.n);
  World dense(def_for(o, false), scene.grid);
  World sparse(def_for(o, true), scene.grid);
  const double cells = double(scene.grid.cell_count());
  const std::string csv_path = o.out + "/activity_" + o.backend + "_" + std::to_string(o.n) + ".csv";
  std::ofstream csv(csv_path);
  csv << "backend,n,tick_end,phase,dense_ms_per_tick,sparse_ms_per_tick,mean_active_cells,mean_active_bricks,"
         "total_bricks\n";
  std::printf("bench_activity: %s, bowl N=%d (%.3g cells), windows of %d ticks, up to %d ticks, dense_fraction %g\n",
              dense.backend_description().c_str(), o.n, cells, o.window, o.max_ticks, o.dense_fraction);
  int quiet_windows = 0;
  double series_wall = 0;
  while (int(sparse.tick()) < o.max_ticks && quiet_windows < 2 && series_wall < o.series_seconds) {
    const double d = timed_step(dense, o.window), s = timed_step(sparse, o.window);
    series_wall += d + s;
    const ActivityStats a = sparse.activity();
    if (dense.hash() != sparse.hash()) {
      std::fprintf(stderr, "MISMATCH at tick %llu: dense %s, sparse %s\n", static_cast<unsigned long long>(sparse.tick()),
                   hex64(dense.hash()).c_str(), hex64(sparse.hash()).c_str());
      return 1;
    }
    const double mean_cells = double(a.cell_ticks) / double(a.ticks);
    const char* phase = mean_cells == 0 ? "settled" : mean_cells > 0.5 * cells ? "falling" : "piling";
    csv << o.backend << ',' << o.n << ',' << sparse.tick() << ',' << phase << ',' << d * 1000.0 / o.window << ','
        << s * 1000.0 / o.window << ',' << mean_cells << ',' << double(a.brick_ticks) / double(a.ticks) << ','
        << a.total_bricks << '\n';
    quiet_windows = a.brick_ticks == 0 ? quiet_windows + 1 : 0;
  }
  const std::uint64_t series_ticks = sparse.tick();
  if (quiet_windows < 2 && int(sparse.tick()) < o.max_ticks) {
    // The sparse world alone to rest; its rows have no dense time (nan), so the plot still shows
    // how a sparse tick's cost falls with the active cells.
    while (int(sparse.tick()) < o.max_ticks && quiet_windows < 2) {
      const double s = timed_step(sparse, o.window);
      const ActivityStats a = sparse.activity();
      csv << o.backend << ',' << o.n << ',' << sparse.tick() << ",piling,nan," << s * 1000.0 / o.window << ','
          << double(a.cell_ticks) / double(a.ticks) << ',' << double(a.brick_ticks) / double(a.ticks) << ','
          << a.total_bricks << '\n';
      quiet_windows = a.brick_ticks == 0 ? quiet_windows + 1 : 0;
    }
    dense.load(sparse.read_grid());
  }
  csv.close();
  const ActivityStats end = sparse.activity();
  const std::uint64_t rest_ticks = sparse.tick();

  // Settled: the final state, several step calls of one window each.
  double dense_s = 0, sparse_s = 0;
  for (int r = 0; r < 4; ++r) {
    dense_s += timed_step(dense, o.window);
    sparse_s += timed_step(sparse, o.window);
  }
  const bool same = dense.hash() == sparse.hash();
  const double dense_ms = dense_s * 1000.0 / (4 * o.window), sparse_ms = sparse_s * 1000.0 / (4 * o.window);
  // The settled state closes the series, so the plot shows all three phases.
  {
    const ActivityStats a = sparse.activity();
    std::ofstream tail(csv_path, std::ios::app);
    tail << o.backend << ',' << o.n << ',' << sparse.tick() << ",settled," << dense_ms << ',' << sparse_ms << ','
         << double(a.cell_ticks) / double(a.ticks) << ',' << double(a.brick_ticks) / double(a.ticks) << ','
         << a.total_bricks << '\n';
  }

  // Pour into a cup of the settled world against the same cup alone.
  double big_ms = 0, alone_ms = 0, alone_dense_ms = 0;
  std::uint64_t big_bricks = 0;
  if (o.pour_ticks > 0 && o.n >= o.cup + 4) {
    paint_cup(sparse, o.cup);
    sparse.step(24);  // the cup's paint settles out of the wake bookkeeping
    WorldDef alone_def = def_for(o, true);
    alone_def.size = {o.cup, o.cup, o.cup};
    World alone(alone_def);
    alone.step(8);
    big_ms = pour_ms_per_tick(sparse, {0, 0, o.n - o.cup}, o.cup, o.pour_ticks);
    big_bricks = sparse.activity().active_bricks;
    alone_ms = pour_ms_per_tick(alone, {0, 0, 0}, o.cup, o.pour_ticks);
    WorldDef alone_dense_def = def_for(o, false);
    alone_dense_def.size = alone_def.size;
    World alone_dense(alone_dense_def);
    alone_dense_ms = pour_ms_per_tick(alone_dense, {0, 0, 0}, o.cup, o.pour_ticks);
  }

  std::printf("series CSV: %s (%llu ticks side by side; %llu ticks in all; at the end %llu of %llu bricks active)\n",
              csv_path.c_str(), static_cast<unsigned long long>(series_ticks),
              static_cast<unsigned long long>(rest_ticks), static_cast<unsigned long long>(end.active_bricks),
              static_cast<unsigned long long>(end.total_bricks));
  std::printf("%-44s %14s\n", "measure", "value");
  std::printf("%-44s %14.4f\n", "settled: dense ms/tick", dense_ms);
  std::printf("%-44s %14.4f\n", "settled: sparse ms/tick", sparse_ms);
  std::printf("%-44s %13.1fx\n", "settled: dense / sparse", sparse_ms > 0 ? dense_ms / sparse_ms : 0.0);
  if (o.pour_ticks > 0 && o.n >= o.cup + 4) {
    std::printf("%-44s %14.4f\n", ("pour: " + std::to_string(o.cup) + "^3 cup in the settled world, ms/tick").c_str(), big_ms);
    std::printf("%-44s %14.4f\n", ("pour: " + std::to_string(o.cup) + "^3 world alone, ms/tick").c_str(), alone_ms);
    std::printf("%-44s %14.4f\n", ("pour: " + std::to_string(o.cup) + "^3 world alone, dense, ms/tick").c_str(),
                alone_dense_ms);
    std::printf("%-44s %13.2fx\n", "pour: in world / alone", alone_ms > 0 ? big_ms / alone_ms : 0.0);
    std::printf("%-44s %13.2fx\n", "pour: in world / alone dense", alone_dense_ms > 0 ? big_ms / alone_dense_ms : 0.0);
    std::printf("%-44s %14llu\n", "pour: active bricks at the end (in world)", static_cast<unsigned long long>(big_bricks));
  }
  std::printf("%-44s %14s\n", "dense == sparse (hash, every window)", same ? "yes" : "NO");
  return same ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse(argc, argv));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_activity: %s\n", e.what());
    return 2;
  }
}
