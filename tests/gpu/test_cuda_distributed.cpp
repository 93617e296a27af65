/// @file test_cuda_distributed.cpp
/// A DistributedWorld of in-process ranks, each slab on the CUDA backend of the one GPU, equals a
/// CPU World of the whole grid: every preset with every material, tools across slab boundaries,
/// sparse stepping on.

#include <doctest/doctest.h>

#include <mutex>
#include <string>

#include "granular/distributed/distributed_world.hpp"
#include "granular/distributed/local_group.hpp"
#include "granular/rule_presets.hpp"
#include "granular/world.hpp"
#include "test_support.hpp"

using namespace granular;
using granular::test::mixed_material_grid;

namespace {

/// A definition on `backend`, 2 threads, seed 13.
WorldDef def_of(Int3 size, const std::string& rules, BackendKind backend) {
  WorldDef def;
  def.size = size;
  def.rules = rules;
  def.backend = backend;
  def.threads = 2;
  def.seed = 13;
  // A distributed world refuses trains (test_distributed_world.cpp): a preset with them runs its
  // other levers.
  return granular::test::without_trains(def);
}

/// Tools at the slab boundaries of a 2- or 3-rank split, then ticks, `rounds` times; the hashes.
template <class W>
std::vector<std::uint64_t> session(W& w, Int3 size, int rounds) {
  std::vector<std::uint64_t> hashes;
  for (int r = 0; r < rounds; ++r) {
    const double z = size.z * (r % 2 == 0 ? 0.5 : 0.34);
    w.dig(Sphere{{size.x * 0.5, size.y * 0.5, z}, 5.5});
    w.pour(Vec3{size.x * 0.4, size.y * 0.6, z + 0.75}, 6.0, Material(2 + r % 4), 90);
    w.paint(Box{{2, 2, int(z) - 2}, {size.x - 3, 6, int(z) + 3}}, Material(1 + r % 5));
    w.step(5);
    hashes.push_back(w.hash());
  }
  return hashes;
}

}  // namespace

TEST_CASE("cuda distributed: 2 and 3 in-process ranks on the GPU equal a CPU World, every preset, all materials") {
  const Int3 size{45, 37, 151};
  const Grid initial = mixed_material_grid(size, 5);
  for (const std::string& rules : rule_preset_names()) {
    // A distributed world refuses pressure and shallow water (test_distributed_world.cpp).
    if (preset(rules).motion.pressure || preset(rules).motion.shallow) continue;
    World cpu(def_of(size, rules, BackendKind::Cpu), initial);
    const std::vector<std::uint64_t> expected = session(cpu, size, 4);
    for (const int ranks : {2, 3}) {
      CAPTURE(rules);
      CAPTURE(ranks);
      std::vector<std::uint64_t> got;
      std::mutex m;
      run_local_ranks(ranks, [&](Communicator& comm) {
        DistributedWorld w(def_of(size, rules, BackendKind::Cuda), comm, initial);
        REQUIRE(w.slab().backend() == BackendKind::Cuda);
        std::vector<std::uint64_t> h = session(w, size, 4);
        if (comm.rank() == 0) {
          const std::lock_guard lock(m);
          got = std::move(h);
        }
      });
      CHECK(got == expected);
    }
  }
}
