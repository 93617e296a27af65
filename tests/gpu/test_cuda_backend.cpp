/// @file test_cuda_backend.cpp
/// The CUDA backend against the CPU reference: the same grid hash after any number of ticks, on
/// any size (odd ones included), seed and rule set (scenes of every material under every preset, water
/// and gas poured and painted between ticks); the same counts, regions and tool results; the
/// GPU-built transition table equal to the CPU's; and the device-memory error path.

#include <doctest/doctest.h>

#include <cstdint>
#include <cstdio>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "../reference/material_scenes.hpp"
#include "../test_support.hpp"
#include "fluid_tool_place.hpp"
#include "granular/errors.hpp"
#include "granular/extend/lut.hpp"
#include "granular/rule_presets.hpp"
#include "granular/rule_set.hpp"
#include "gpu_worlds.hpp"
#include "granular/world.hpp"
#include "granular_cuda/cuda_backend_factory.hpp"

using namespace granular;
using granular::test::random_grid;
using granular::test::random_size;

namespace {

/// A WorldDef for `backend` (the CPU with 2 threads) with the build tree's table cache. Dense
/// stepping: these cases check the dense kernels; sparse stepping is checked in
/// test_cuda_activity.cpp.
WorldDef def_for(BackendKind backend, const char* rules, std::uint64_t seed) {
  WorldDef def;
  def.sparse = false;
  def.rules = rules;
  def.seed = seed;
  def.backend = backend;
  def.threads = 2;
  return def;
}

/// The same initial grid on the CPU and on the GPU.
struct WorldPair {
  World cpu;
  World gpu;
  WorldPair(const Grid& initial, const char* rules, std::uint64_t seed)
      : cpu(def_for(BackendKind::Cpu, rules, seed), initial), gpu(def_for(BackendKind::Cuda, rules, seed), initial) {}
  WorldPair(World cpu_world, World gpu_world) : cpu(std::move(cpu_world)), gpu(std::move(gpu_world)) {}
  void step(int ticks) {
    cpu.step(ticks);
    gpu.step(ticks);
  }
};

/// "" when both worlds hold the same cells, else the first differing cell and both values.
std::string first_difference(const World& cpu, const World& gpu) {
  const Grid a = cpu.read_grid(), b = gpu.read_grid();
  for (int z = 0; z < a.size().z; ++z)
    for (int y = 0; y < a.size().y; ++y)
      for (int x = 0; x < a.size().x; ++x)
        if (a.at({x, y, z}) != b.at({x, y, z}))
          return "first difference at (" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) +
                 "): cpu " + std::to_string(unsigned(to_cell(a.at({x, y, z})))) + ", gpu " +
                 std::to_string(unsigned(to_cell(b.at({x, y, z})))) + " at tick " + std::to_string(cpu.tick());
  return {};
}

/// Requires equal hashes; names the first differing cell when they are not.
void require_same(const WorldPair& w) {
  const std::uint64_t cpu = w.cpu.hash(), gpu = w.gpu.hash();
  if (cpu != gpu) FAIL_CHECK(first_difference(w.cpu, w.gpu));
  REQUIRE(gpu == cpu);
}

}  // namespace

TEST_CASE("cuda: the GPU-built transition table equals the CPU's Lut::build bit for bit") {
  const auto rules = make_rule_set("paper");
  float ms = -1;
  const std::vector<Transition> gpu = build_lut_on_gpu(*rules, &ms);
  MESSAGE("GPU transition table kernel: " << ms << " ms for 16,777,216 keys");
  CHECK(ms >= 0);
  const Lut cpu = Lut::build(*rules, 0);
  REQUIRE(gpu.size() == cpu.entries().size());
  std::uint64_t mismatches = 0;
  std::int64_t first = -1;
  for (std::size_t k = 0; k < gpu.size(); ++k)
    if (gpu[k] != cpu.entries()[k]) {
      if (first < 0) first = std::int64_t(k);
      ++mismatches;
    }
  CAPTURE(first);
  CHECK(mismatches == 0);
  const Lut wrapped = Lut::from_entries(gpu, rule_fingerprint(*rules), 0);
  CHECK(wrapped.content_hash() == cpu.content_hash());

  RuleSet no_device_rule = *rules;
  no_device_rule.device_rule.clear();
  CHECK_THROWS_AS(build_lut_on_gpu(no_device_rule), InvalidArgument);
}

TEST_CASE("cuda: a world on the GPU uses the CUDA backend and describes its device") {
  World gpu(def_for(BackendKind::Cuda, "paper", 1), random_grid({9, 8, 7}, 3));
  CHECK(gpu.backend() == BackendKind::Cuda);
  const std::string description = gpu.backend_description();
  CAPTURE(description);
  CHECK(description.rfind("cuda (", 0) == 0);
  CHECK(description.find(", sm_") != std::string::npos);
}

TEST_CASE("cuda: make_cuda_backend holds an exact copy of the grid") {
  const auto rules = make_rule_set("paper");
  const auto lut = std::make_shared<const Lut>(Lut::build(*rules, 0));
  for (const Int3 size : {Int3{1, 1, 1}, Int3{3, 5, 7}, Int3{8, 8, 8}, Int3{17, 1, 9}, Int3{64, 33, 20}}) {
    CAPTURE(size.x);
    CAPTURE(size.y);
    CAPTURE(size.z);
    const Grid g = random_grid(size, 11, 20, 40);
    const auto backend = make_cuda_backend({.initial = g, .lut = lut, .rules = rules, .seed = 5});
    CHECK(backend->kind() == BackendKind::Cuda);
    CHECK(backend->hash() == g.hash());
    CHECK(backend->count() == g.count());
    Grid back(size);
    backend->read(g.bounds(), back.cells());
    CHECK(back.hash() == g.hash());
  }
  CHECK_THROWS_AS(make_cuda_backend({.initial = Grid({4, 4, 4}), .lut = nullptr, .rules = rules}), InvalidArgument);
}

TEST_CASE("cuda: same hash as the CPU after 1, 7, 8, 100 and 1000 ticks on 20 random scenes") {
  std::mt19937_64 rng(20261123);
  for (int scene = 0; scene < 20; ++scene) {
    const char* rules = scene % 2 == 0 ? "paper" : "isotropic";
    const Int3 size = random_size(rng, 1, 70);
    const int solid = int(rng() % 30), granular = 5 + int(rng() % 70);
    const std::uint64_t seed = rng();
    CAPTURE(scene);
    CAPTURE(rules);
    CAPTURE(size.x);
    CAPTURE(size.y);
    CAPTURE(size.z);
    CAPTURE(solid);
    CAPTURE(granular);
    CAPTURE(seed);
    const Grid initial = random_grid(size, rng(), solid, granular);
    WorldPair w(initial, rules, seed);
    REQUIRE(w.gpu.backend() == BackendKind::Cuda);
    require_same(w);
    int done = 0;
    for (const int checkpoint : {1, 7, 8, 100, 1000}) {
      CAPTURE(checkpoint);
      w.step(checkpoint - done);
      done = checkpoint;
      require_same(w);
    }
    CHECK(w.gpu.count() == initial.count());
  }
}

TEST_CASE("cuda: same hash as the CPU over a 10,000-tick run of a 96^3 scene") {
  const Int3 size{96, 96, 96};
  const Grid initial = random_grid(size, 96, 12, 45);
  WorldPair w(initial, "isotropic", 4242);
  int done = 0;
  for (const int checkpoint : {1, 9, 250, 1000, 2500, 5000, 7500, 10000}) {
    CAPTURE(checkpoint);
    w.step(checkpoint - done);
    done = checkpoint;
    require_same(w);
  }
  CHECK(w.gpu.count() == initial.count());
  CHECK(w.gpu.tick() == 10000);
}

TEST_CASE("cuda: steps of mixed lengths and parities (single and fused-pair ticks) match the CPU") {
  // Odd extents, and heights that give one chunk, several chunks, and a last chunk of one extra
  // layer, for the fused two-tick kernel; each call may start at an odd tick and end with a single.
  const std::vector<Int3> sizes = {{37, 23, 141}, {9, 5, 33}, {1, 1, 35}, {65, 3, 19}, {13, 71, 2},
                                   {3, 3, 1},     {17, 9, 49}, {41, 41, 67}};
  std::mt19937_64 rng(4711);
  for (const char* rules : {"paper", "isotropic"}) {
    for (const Int3 size : sizes) {
      CAPTURE(rules);
      CAPTURE(size.x);
      CAPTURE(size.y);
      CAPTURE(size.z);
      const Grid initial = random_grid(size, rng(), int(rng() % 20), 20 + int(rng() % 60));
      WorldPair w(initial, rules, rng());
      for (const int ticks : {1, 3, 2, 5, 4, 1, 1, 6, 7, 2, 33, 64, 0, 9, 16}) {
        CAPTURE(ticks);
        w.step(ticks);
        require_same(w);
      }
      CHECK(w.gpu.count() == initial.count());
      CHECK(w.gpu.tick() == 154);
    }
  }
}

TEST_CASE("cuda: scenes of every material under every preset, dense, with water and gas poured and painted between ticks, match the CPU") {
  // The dense and fused-pair kernels on random scenes of void, solid, sand, water, gas, gravel and
  // the static states 6, 7 (material_scenes.hpp), odd extents, steps of mixed lengths and parities;
  // tools of water and gas between them; every cell byte (motion state included) equal to the CPU's
  // and every material conserved by the steps.
  std::mt19937_64 rng(0xF1D0);
  for (const std::string& rules : rule_preset_names())
    for (const Int3 size : {Int3{37, 29, 41}, Int3{64, 20, 33}, Int3{5, 9, 70}}) {
      const std::uint64_t seed = rng();
      CAPTURE(rules);
      CAPTURE(size.x);
      CAPTURE(size.y);
      CAPTURE(size.z);
      CAPTURE(seed);
      const Grid initial = granular::test::all_materials_scene(size, rng());
      WorldPair w(initial, rules.c_str(), seed);
      REQUIRE(w.gpu.backend() == BackendKind::Cuda);
      for (const int ticks : {1, 3, 2, 5, 8}) {
        CAPTURE(ticks);
        w.step(ticks);
        require_same(w);
      }
      CHECK(w.gpu.count() == initial.count());
      for (int round = 0; round < 8; ++round) {
        CAPTURE(round);
        const granular::test::FluidToolPlace place = granular::test::random_fluid_tool_place(rng, size);
        const Vec3 c = place.centre;
        const double r = place.radius;
        const std::int64_t amount = place.amount;
        const Box box = place.box;
        auto apply = [&](World& world) -> std::optional<ChangeReport> {
          try {
            switch (round % 4) {
              case 0: return world.pour(c, r, Material::Liquid, amount);
              case 1: return world.paint(Sphere{c, r}, Material::Gas);
              case 2: return world.pour(c, r, Material::Gas, amount);
              default: return world.paint(box, Material::Liquid);
            }
          } catch (const InvalidArgument&) {
            return std::nullopt;
          }
        };
        const auto a = apply(w.cpu), b = apply(w.gpu);
        REQUIRE(a.has_value() == b.has_value());
        if (a) {
          CHECK(a->cells_changed == b->cells_changed);
          CHECK(a->added == b->added);
          CHECK(a->removed == b->removed);
        }
        require_same(w);
        const MaterialCounts counts = w.cpu.count();
        const int ticks = 1 + int(rng() % 20);
        CAPTURE(ticks);
        w.step(ticks);
        require_same(w);
        CHECK(w.gpu.count() == counts);
      }
    }
}

TEST_CASE("cuda: dig, pour and paint between ticks give the same worlds as on the CPU") {
  for (const char* rules : {"paper", "isotropic"}) {
    CAPTURE(rules);
    const Int3 size{61, 48, 57};
    std::mt19937_64 rng(777);
    WorldPair w(random_grid(size, 5, 8, 30), rules, 99);
    std::uniform_real_distribution<double> ux(-4.0, size.x + 4.0), uy(-4.0, size.y + 4.0), uz(-4.0, size.z + 4.0);
    std::uniform_real_distribution<double> radius(1.0, 9.0);
    for (int round = 0; round < 20; ++round) {
      CAPTURE(round);
      const Vec3 c{ux(rng), uy(rng), uz(rng)};
      const double r = radius(rng);
      const std::int64_t amount = std::int64_t(rng() % 400);
      const Int3 lo{int(c.x) - 3, int(c.y) - 3, int(c.z) - 2};
      const Box box{lo, {lo.x + 1 + int(rng() % 12), lo.y + 1 + int(rng() % 12), lo.z + 1 + int(rng() % 6)}};
      const Material paint_material = round % 8 == 2 ? Material::Solid : Material::Granular;
      // The same tool call on either world; nullopt when it refused a region missing the grid.
      auto apply = [&](World& world) -> std::optional<ChangeReport> {
        try {
          switch (round % 4) {
            case 0: return world.dig({c, r});
            case 1: return world.pour(c, r, Material::Granular, amount);
            case 2: return world.paint(box, paint_material);
            default: return world.paint(Sphere{c, r}, Material::Void);
          }
        } catch (const InvalidArgument&) {
          return std::nullopt;
        }
      };
      const auto a = apply(w.cpu), b = apply(w.gpu);
      REQUIRE(a.has_value() == b.has_value());
      if (a) {
        CHECK(a->cells_changed == b->cells_changed);
        CHECK(a->added == b->added);
        CHECK(a->removed == b->removed);
      }
      require_same(w);
      w.step(50);
      require_same(w);
      REQUIRE(w.gpu.count() == w.cpu.count());
    }
    CHECK(w.gpu.tick() == 1000);
  }
}

TEST_CASE("cuda: count, read_region, snapshot and load agree with the CPU") {
  std::mt19937_64 rng(31337);
  for (const Int3 size : {Int3{1, 1, 1}, Int3{1, 70, 1}, Int3{7, 3, 5}, Int3{33, 17, 41}, Int3{64, 64, 64}}) {
    CAPTURE(size.x);
    CAPTURE(size.y);
    CAPTURE(size.z);
    WorldPair w(random_grid(size, rng(), 15, 40), "isotropic", rng());
    w.step(37);
    require_same(w);
    CHECK(w.gpu.count() == w.cpu.count());
    CHECK(w.gpu.read_grid().hash() == w.gpu.hash());
    CHECK(w.gpu.read_grid().count() == w.gpu.count());
    for (int i = 0; i < 25; ++i) {
      std::uniform_int_distribution<int> dx(0, size.x - 1), dy(0, size.y - 1), dz(0, size.z - 1);
      const int x0 = dx(rng), y0 = dy(rng), z0 = dz(rng);
      const Box box = i == 0 ? Box{{0, 0, 0}, size}
                             : Box{{x0, y0, z0},
                                   {x0 + 1 + int(rng() % unsigned(size.x - x0)), y0 + 1 + int(rng() % unsigned(size.y - y0)),
                                    z0 + 1 + int(rng() % unsigned(size.z - z0))}};
      CHECK(w.gpu.read_region(box) == w.cpu.read_region(box));
    }
    const Grid other = random_grid(size, rng(), 5, 50);
    w.cpu.load(other);
    w.gpu.load(other);
    CHECK(w.gpu.hash() == other.hash());
    require_same(w);
    w.step(9);
    require_same(w);
  }
}

TEST_CASE("cuda: a grid too large for the device is refused with OutOfMemory naming its size") {
  CHECK_NOTHROW(check_cuda_fits({64, 64, 64}));
  CHECK_THROWS_AS(check_cuda_fits({8192, 8192, 8192}), OutOfMemory);
  try {
    check_cuda_fits({8192, 8192, 8192});
  } catch (const OutOfMemory& e) {
    const std::string message = e.what();
    MESSAGE(message);
    CHECK(message.find("8192x8192x8192") != std::string::npos);
    CHECK(message.find("free") != std::string::npos);
  }
  CHECK(cuda_bytes_needed({8192, 8192, 8192}) == 8192ull * 8192 * 8192 + 128ull * 1024 * 1024);
  CHECK_THROWS_AS(check_cuda_fits({0, 4, 4}), InvalidArgument);
}

TEST_CASE("cuda: sharing the cells refuses bad handles and leaves the world intact") {
  REQUIRE(cuda_device_uuid().has_value());
  const Grid initial = random_grid({33, 20, 17}, 5);
  World world(def_for(BackendKind::Cuda, "paper", 1), initial);
  CHECK(world.shared_cell_bytes() == (std::uint64_t(initial.cell_count()) + 7) / 8 * 8);
  const std::uint64_t before = world.hash();
  CHECK_THROWS_AS(world.share_cells({-1, world.shared_cell_bytes(), 0, false}), InvalidArgument);
  CHECK_THROWS_AS(world.share_cells({3, world.shared_cell_bytes() - 1, 0, false}), InvalidArgument);
  // A descriptor that is no exported memory: the import fails with the CUDA error, nothing moves.
  FILE* not_memory = std::tmpfile();
  REQUIRE(not_memory != nullptr);
  CHECK_THROWS_AS(world.share_cells({fileno(not_memory), world.shared_cell_bytes(), 0, false}), BackendError);
  std::fclose(not_memory);
  CHECK_THROWS_AS(world.attach_timelines({-1}, {-1}), BackendError);
  CHECK_THROWS_AS(world.hand_off_cells(), BackendError);
  CHECK(world.hash() == before);
  world.step(16);
  World cpu(def_for(BackendKind::Cpu, "paper", 1), initial);
  cpu.step(16);
  CHECK(world.hash() == cpu.hash());
}

TEST_CASE("cuda: tools between sparse steps of the default rules give the CPU's cells, reports and changed bricks") {
  // Several tools in a row between steps: each write is enqueued without waiting, and the next
  // tool's read of an overlapping region must see it.
  const Int3 size{70, 52, 45};  // partial bricks on every axis
  auto def = [](BackendKind backend) {
    WorldDef d;  // the default rules (a motion model) and sparse stepping
    d.seed = 7;
    d.backend = backend;
    d.threads = 2;
    return d;
  };
  const Grid initial = random_grid(size, 3, 5, 25);
  World cpu(def(BackendKind::Cpu), initial), gpu(def(BackendKind::Cuda), initial);
  REQUIRE(gpu.backend() == BackendKind::Cuda);
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<double> ux(-3.0, size.x + 3.0), uy(-3.0, size.y + 3.0), uz(-3.0, size.z + 3.0);
  std::uniform_real_distribution<double> radius(1.5, 9.0);
  for (int round = 0; round < 40; ++round) {
    CAPTURE(round);
    const std::uint64_t cpu_version = cpu.change_version(), gpu_version = gpu.change_version();
    const int ticks = int(rng() % 4);
    cpu.step(ticks);
    gpu.step(ticks);
    for (int t = 0, tools = 1 + int(rng() % 3); t < tools; ++t) {
      CAPTURE(t);
      const Vec3 c{ux(rng), uy(rng), uz(rng)};
      const double r = radius(rng);
      const std::int64_t amount = std::int64_t(rng() % 600);
      const Box box{{int(c.x) - 4, int(c.y) - 4, int(c.z) - 3}, {int(c.x) + 5, int(c.y) + 3, int(c.z) + 6}};
      const int kind = int(rng() % 4);
      auto apply = [&](World& world) -> std::optional<ChangeReport> {
        try {
          switch (kind) {
            case 0: return world.dig({c, r});
            case 1: return world.pour(c, r, Material::Granular, amount);
            case 2: return world.paint(box, round % 5 == 0 ? Material::Solid : Material::Granular);
            default: return world.paint(Sphere{c, r}, Material::Void);
          }
        } catch (const InvalidArgument&) {
          return std::nullopt;
        }
      };
      const auto a = apply(cpu), b = apply(gpu);
      REQUIRE(a.has_value() == b.has_value());
      if (!a) continue;
      CHECK(a->cells_changed == b->cells_changed);
      CHECK(a->added == b->added);
      CHECK(a->removed == b->removed);
      CHECK(a->region == b->region);
      CHECK(a->clipped == b->clipped);
    }
    REQUIRE(gpu.hash() == cpu.hash());  // the motion state of every grain included
    CHECK(gpu.bricks_changed_since(gpu_version) == cpu.bricks_changed_since(cpu_version));
    CHECK(gpu.change_version() == cpu.change_version());
  }
  cpu.step(24);
  gpu.step(24);
  CHECK(gpu.hash() == cpu.hash());
  CHECK(gpu.activity().active_bricks == cpu.activity().active_bricks);
}

TEST_CASE("cuda: reads and writes of boxes larger than one staging chunk agree with the CPU") {
  // 300x300x100: chunks of whole slices; 2100x2050x3: a slice is more than a chunk, so chunks of
  // rows; the whole grid and whole slices, one copy.
  for (const Int3 size : {Int3{300, 300, 100}, Int3{2100, 2050, 3}})
    for (const bool sparse : {false, true}) {
      CAPTURE(size.x);
      CAPTURE(size.y);
      CAPTURE(sparse);
      const Grid initial = random_grid(size, 17, 10, 30);
      WorldDef cpu_def = def_for(BackendKind::Cpu, "paper", 3), gpu_def = def_for(BackendKind::Cuda, "paper", 3);
      cpu_def.sparse = gpu_def.sparse = sparse;
      WorldPair w(World(cpu_def, initial), World(gpu_def, initial));
      require_same(w);
      const Grid other = random_grid(size, 18, 5, 40);
      w.cpu.load(other);
      w.gpu.load(other);
      CHECK(w.gpu.hash() == other.hash());
      require_same(w);
      CHECK(w.gpu.read_grid().hash() == other.hash());
      const Box big{{1, 2, 0}, {size.x - 1, size.y - 3, size.z}};
      CHECK(w.gpu.read_region(big) == w.cpu.read_region(big));
      const ChangeReport a = w.cpu.paint(big, Material::Granular), b = w.gpu.paint(big, Material::Granular);
      CHECK(a.cells_changed == b.cells_changed);
      CHECK(a.added == b.added);
      CHECK(a.removed == b.removed);
      require_same(w);
      // Whole slices of more than a chunk: one copy each way.
      const Box slab{{0, 0, size.z / 3}, {size.x, size.y, size.z}};
      CHECK(w.gpu.read_region(slab) == w.cpu.read_region(slab));
      CHECK(w.cpu.paint(slab, Material::Solid).cells_changed == w.gpu.paint(slab, Material::Solid).cells_changed);
      require_same(w);
      w.step(3);
      require_same(w);
      CHECK(w.gpu.bricks_changed_since(0) == w.cpu.bricks_changed_since(0));
    }
}
