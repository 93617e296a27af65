/// @file bench_distributed.cpp
/// What splitting a world into z-slabs costs (DistributedWorld, in-process ranks on one machine):
/// the bowl scene stepped by one World and by 2, 3, ... ranks of a LocalGroup, each slab on the
/// chosen backend (several slabs then share the one GPU or the CPU's threads), in one process.
/// Per rank count: ms per tick, its ratio to one World, the ms per tick rank 0 spent exchanging
/// halos and the bytes it sent, then each rank's stepping and exchange; the hash after the run must equal one World's (exit status 1 if
/// not). On one device this measures the decomposition's overhead (halo exchange through host
/// memory and the halo's redundant layers), not scaling: that needs one device per rank.
///
///   bench_distributed [--backend cpu|cuda] [--n N] [--ranks 2,4] [--ticks T] [--warmup W]
///                     [--threads J] [--rules R]

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include "granular/distributed/distributed_world.hpp"
#include "granular/errors.hpp"
#include "granular/extend/hex.hpp"
#include "granular/distributed/local_group.hpp"
#include "granular/scene.hpp"
#include "granular/world.hpp"
#include "timed_step.hpp"

namespace {

using namespace granular;

/// The command line (see the file comment).
struct Options {
  std::string backend = "cpu";  ///< cpu or cuda
  int n = 128;                  ///< bowl size N
  std::vector<int> ranks{2, 4}; ///< rank counts to compare with one World
  int ticks = 32;               ///< timed ticks
  int warmup = 8;               ///< ticks before the timing
  int threads = 0;              ///< CPU threads per World (0 = all)
  std::string rules = WorldDef{}.rules;  ///< rule-set preset
};

/// Reads the options; throws InvalidArgument for unknown ones or bad values.
Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; i += 2) {
    const std::string key = argv[i];
    if (i + 1 >= argc) throw InvalidArgument("bench_distributed: " + key + " needs a value");
    const std::string value = argv[i + 1];
    if (key == "--backend") o.backend = value;
    else if (key == "--n") o.n = std::atoi(value.c_str());
    else if (key == "--ticks") o.ticks = std::atoi(value.c_str());
    else if (key == "--warmup") o.warmup = std::atoi(value.c_str());
    else if (key == "--threads") o.threads = std::atoi(value.c_str());
    else if (key == "--rules") o.rules = value;
    else if (key == "--ranks") {
      o.ranks.clear();
      std::stringstream list(value);
      for (std::string item; std::getline(list, item, ',');) o.ranks.push_back(std::atoi(item.c_str()));
    } else {
      throw InvalidArgument("bench_distributed: unknown option " + key + " (see the file comment for the options)");
    }
  }
  if (o.backend != "cpu" && o.backend != "cuda")
    throw InvalidArgument("bench_distributed: --backend = " + o.backend + "; use cpu or cuda");
  if (o.ticks < 1 || o.warmup < 0)
    throw InvalidArgument("bench_distributed: --ticks must be >= 1 and --warmup >= 0");
  for (const int r : o.ranks)
    if (r < 2 || r > 64) throw InvalidArgument("bench_distributed: --ranks holds " + std::to_string(r) + "; use 2..64");
  return o;
}

/// One configuration's figures.
struct Row {
  int ranks = 1;
  double ms_per_tick = 0, exchange_ms_per_tick = 0, read_ms = 0, message_ms = 0, write_ms = 0, sent_mib_per_tick = 0;
  std::uint64_t hash = 0;
  std::vector<std::string> per_rank;  ///< each rank's step and exchange, one line each
};

}  // namespace

int main(int argc, char** argv) try {
  const Options o = parse(argc, argv);
  WorldDef def;
  def.backend = o.backend == "cuda" ? BackendKind::Cuda : BackendKind::Cpu;
  def.threads = o.threads;
  def.rules = o.rules;
  const SceneInstance scene = instantiate(load_scene(find_scene("bowl")), o.n);
  std::printf("bench_distributed: %s, rules %s, bowl N=%d (%s cells), %d warm-up then %d timed ticks\n",
              o.backend.c_str(), o.rules.c_str(), o.n, to_string(scene.grid.size()).c_str(), o.warmup, o.ticks);
  std::vector<Row> rows;
  {
    World one(def, scene.grid);
    one.step(o.warmup);
    Row r;
    r.ms_per_tick = bench::timed_step(one, o.ticks) * 1e3 / o.ticks;
    r.hash = one.hash();
    std::printf("  %s\n", one.backend_description().c_str());
    rows.push_back(r);
  }
  for (const int ranks : o.ranks) {
    Row r;
    r.ranks = ranks;
    std::mutex m;
    run_local_ranks(ranks, [&](Communicator& comm) {
      DistributedWorld w(def, comm, scene.grid);
      w.step(o.warmup);
      (void)all_true(comm, true);  // every rank starts the timing together
      const auto start = std::chrono::steady_clock::now();
      HaloExchangeStats sum;
      double stepping = 0;
      for (int t = 0; t < o.ticks; ++t) {
        const auto tick_start = std::chrono::steady_clock::now();
        w.step(1);
        const HaloExchangeStats& e = w.last_exchange();
        stepping += std::chrono::duration<double>(std::chrono::steady_clock::now() - tick_start).count() - e.seconds;
        sum.seconds += e.seconds;
        sum.read_seconds += e.read_seconds;
        sum.message_seconds += e.message_seconds;
        sum.write_seconds += e.write_seconds;
        sum.bytes_sent += e.bytes_sent;
      }
      (void)all_true(comm, true);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const std::uint64_t hash = w.hash();
      {
        const std::lock_guard lock(m);
        char line[200];
        std::snprintf(line, sizeof line,
                      "         rank %d: layers %d..%d, step %.3f ms, exchange %.3f ms (read %.2f, message %.2f, write %.2f), "
                      "sent %.2f MiB per tick\n",
                      comm.rank(), w.slab_range().z0, w.slab_range().z1, stepping * 1e3 / o.ticks, sum.seconds * 1e3 / o.ticks,
                      sum.read_seconds * 1e3 / o.ticks, sum.message_seconds * 1e3 / o.ticks,
                      sum.write_seconds * 1e3 / o.ticks, double(sum.bytes_sent) / double(1 << 20) / o.ticks);
        r.per_rank.resize(std::size_t(ranks));
        r.per_rank[std::size_t(comm.rank())] = line;
      }
      if (comm.rank() == 0) {
        const std::lock_guard lock(m);
        r.ms_per_tick = seconds * 1e3 / o.ticks;
        r.exchange_ms_per_tick = sum.seconds * 1e3 / o.ticks;
        r.read_ms = sum.read_seconds * 1e3 / o.ticks;
        r.message_ms = sum.message_seconds * 1e3 / o.ticks;
        r.write_ms = sum.write_seconds * 1e3 / o.ticks;
        r.sent_mib_per_tick = double(sum.bytes_sent) / double(1 << 20) / o.ticks;
        r.hash = hash;
      }
    });
    rows.push_back(r);
  }
  std::printf("%6s %10s %13s %22s %18s %18s\n", "ranks", "ms/tick", "vs one World",
              "exchange ms (r0): all", "read/message/write", "sent MiB (r0)");
  bool equal = true;
  for (const Row& r : rows) {
    equal = equal && r.hash == rows[0].hash;
    std::printf("%6d %10.3f %13.3f %22.3f %6.2f/%5.2f/%5.2f %18.2f  hash %s%s\n", r.ranks, r.ms_per_tick,
                r.ms_per_tick / rows[0].ms_per_tick, r.exchange_ms_per_tick, r.read_ms, r.message_ms, r.write_ms,
                r.sent_mib_per_tick, hex64(r.hash).c_str(), r.hash == rows[0].hash ? "" : "  DIFFERS from one World");
    for (const std::string& line : r.per_rank) std::fputs(line.c_str(), stdout);
  }
  return equal ? 0 : 1;
} catch (const std::exception& e) {
  std::fprintf(stderr, "bench_distributed: error: %s\n", e.what());
  return 2;
}
