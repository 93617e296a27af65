/// @file test_world_tools.cpp
/// How the tools (dig, pour, paint) and load reach the backend, seen through the public Backend
/// interface around the real CPU backend: one read of the region and at most one write, which
/// wakes exactly the bricks holding a changed cell, and no read of the step's changed-brick flags;
/// the bytes written keep the motion state of every cell whose material stays; bricks_changed_since
/// stays exact for every version read between steps and tools; and each tool's cells, report and
/// woken bricks equal those of a plain per-cell statement of what it does, pour's choice of cells
/// included.

#include <doctest/doctest.h>

#include <algorithm>
#include <functional>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include "granular/extend/backend.hpp"
#include "granular/extend/backend_factory.hpp"
#include "granular/errors.hpp"
#include "granular/motion.hpp"
#include "granular/rule_set.hpp"
#include "granular/world.hpp"
#include "test_support.hpp"
#include "world/tool_region.hpp"

using namespace granular;
using granular::test::test_def;

namespace {

/// What World asked of its backend since the last reset.
struct BackendCalls {
  int reads = 0;                        ///< read() calls
  int writes = 0;                       ///< write() calls
  int changed_brick_takes = 0;          ///< take_changed_bricks() calls
  std::vector<std::uint32_t> woken;     ///< the bricks the last write woke
  const Backend* backend = nullptr;     ///< the CPU backend inside, to read raw cell bytes
  void reset() { *this = BackendCalls{.backend = backend}; }
};

/// The CPU backend, counting the calls that move cells between World and the backend.
class CountingBackend final : public Backend {
 public:
  CountingBackend(std::unique_ptr<Backend> inner, std::shared_ptr<BackendCalls> calls)
      : inner_(std::move(inner)), calls_(std::move(calls)) {
    calls_->backend = inner_.get();
  }
  BackendKind kind() const override { return inner_->kind(); }
  std::string description() const override { return inner_->description(); }
  void step(std::uint64_t first_tick, int ticks) override { inner_->step(first_tick, ticks); }
  void read(const Box& box, std::span<std::uint8_t> out) const override {
    ++calls_->reads;
    inner_->read(box, out);
  }
  void write(const Box& box, std::span<const std::uint8_t> in, std::span<const std::uint32_t> wake_bricks) override {
    ++calls_->writes;
    calls_->woken.assign(wake_bricks.begin(), wake_bricks.end());
    inner_->write(box, in, wake_bricks);
  }
  MaterialCounts count() const override { return inner_->count(); }
  std::uint64_t hash() const override { return inner_->hash(); }
  void take_changed_bricks(std::span<std::uint8_t> flags) override {
    ++calls_->changed_brick_takes;
    inner_->take_changed_bricks(flags);
  }
  ActivityStats last_activity() const override { return inner_->last_activity(); }

 private:
  std::unique_ptr<Backend> inner_;
  std::shared_ptr<BackendCalls> calls_;
};

/// A sparse CPU world of `size` with the motion model, its backend counting into `calls`.
World counted_world(Int3 size, const std::shared_ptr<BackendCalls>& calls) {
  WorldDef def = test_def(size, "inertial");
  def.backend_factory = [calls](const BackendCreateInfo& info) -> std::unique_ptr<Backend> {
    return std::make_unique<CountingBackend>(make_cpu_backend(info), calls);
  };
  return World(def);
}

/// The raw bytes of every cell (materials and motion state), read past World.
std::vector<std::uint8_t> raw_cells(const BackendCalls& calls, Int3 size) {
  std::vector<std::uint8_t> cells(std::size_t(size.x) * std::size_t(size.y) * std::size_t(size.z));
  calls.backend->read(Box{{0, 0, 0}, size}, cells);
  return cells;
}

/// The bricks (ascending) holding a cell whose byte differs between `a` and `b`.
std::vector<std::uint32_t> differing_bricks(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b,
                                            Int3 size) {
  const Int3 n = brick_counts(size);
  std::vector<std::uint32_t> bricks;
  for (int z = 0; z < size.z; ++z)
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x) {
        const std::size_t i = std::size_t(x) + std::size_t(size.x) * (std::size_t(y) + std::size_t(size.y) * std::size_t(z));
        if (a[i] != b[i])
          bricks.push_back(std::uint32_t((z / kBrickSize * n.y + y / kBrickSize) * n.x + x / kBrickSize));
      }
  std::sort(bricks.begin(), bricks.end());
  bricks.erase(std::unique(bricks.begin(), bricks.end()), bricks.end());
  return bricks;
}

}  // namespace

TEST_CASE("world tools: each tool reads its region once and writes it at most once, waking the bricks it changed") {
  const Int3 size{40, 36, 34};  // partial bricks on every axis
  auto calls = std::make_shared<BackendCalls>();
  World world = counted_world(size, calls);
  world.paint(Box{{4, 4, 2}, {36, 32, 12}}, Material::Granular);
  world.step(5);  // grains in motion, step changes not yet taken
  const std::uint64_t before_tools = world.change_version();

  // Each call: the same tools and load, with steps between some of them.
  const Grid loaded = [&] {
    Grid g = world.read_grid();
    g.set({20, 20, 30}, Material::Granular);
    g.set({1, 1, 1}, Material::Solid);
    return g;
  }();
  int call = 0;
  for (const auto& tool : std::vector<std::function<ChangeReport()>>{
           [&] { return world.dig(Sphere{{18.5, 17.5, 8.5}, 8.0}); },
           [&] { return world.pour({18.0, 17.0, 22.0}, 8.0, Material::Granular, 300); },
           [&] { return world.paint(Sphere{{30.0, 8.0, 6.0}, 8.0}, Material::Solid); },
           [&] { return world.paint(Box{{0, 30, 28}, {40, 36, 34}}, Material::Granular); },
           [&] {
             world.load(loaded);
             return ChangeReport{.cells_changed = 1};
           },
       }) {
    CAPTURE(call);
    const std::vector<std::uint8_t> at_version = raw_cells(*calls, size);
    const std::uint64_t version = world.change_version();
    const bool after_step = call % 2 == 1;
    if (after_step) world.step(3);  // its changes are still to be taken when the tool runs
    const std::vector<std::uint8_t> before = raw_cells(*calls, size);
    calls->reset();
    const ChangeReport report = tool();
    CHECK(calls->reads == 1);
    CHECK(calls->writes == 1);
    CHECK(calls->changed_brick_takes == 0);  // a tool reads no step flags, even right after a step
    CHECK(report.cells_changed > 0);
    const std::vector<std::uint8_t> after = raw_cells(*calls, size);
    CHECK(calls->woken == differing_bricks(before, after, size));
    const std::vector<std::uint32_t> listed = world.bricks_changed_since(version);
    if (after_step) {
      // Step flags are exact up to a cell that changed and changed back: every brick that differs
      // is listed, and every brick the tool woke.
      for (const std::uint32_t b : differing_bricks(at_version, after, size))
        CHECK(std::binary_search(listed.begin(), listed.end(), b));
      for (const std::uint32_t b : calls->woken) CHECK(std::binary_search(listed.begin(), listed.end(), b));
    } else {
      CHECK(listed == calls->woken);
    }
    ++call;
  }

  // A tool that changes no cell reads and does not write.
  world.paint(Box{{0, 0, 0}, {2, 2, 2}}, Material::Solid);
  calls->reset();
  CHECK(world.paint(Box{{0, 0, 0}, {2, 2, 2}}, Material::Solid).cells_changed == 0);
  CHECK(calls->reads == 1);
  CHECK(calls->writes == 0);
  CHECK(world.bricks_changed_since(before_tools).size() > 0);
}

TEST_CASE("world tools: a cell whose material a tool leaves keeps its motion state") {
  const Int3 size{48, 48, 48};
  auto calls = std::make_shared<BackendCalls>();
  World world = counted_world(size, calls);
  world.paint(Box{{8, 8, 24}, {40, 40, 40}}, Material::Granular);
  world.step(6);  // a falling slab: grains with velocity
  const std::vector<std::uint8_t> start = raw_cells(*calls, size);
  std::int64_t moving = 0;
  for (const std::uint8_t c : start) moving += (c & ~kMaterialMask) != 0;
  REQUIRE(moving > 1000);

  int call = 0;
  for (const auto& tool : std::vector<std::function<ChangeReport()>>{
           [&] { return world.dig(Sphere{{24.0, 24.0, 30.0}, 8.0}); },
           [&] { return world.pour({20.0, 20.0, 26.0}, 8.0, Material::Granular, 100); },
           [&] { return world.paint(Sphere{{30.0, 30.0, 34.0}, 8.0}, Material::Solid); },
           [&] { return world.paint(Box{{10, 10, 20}, {30, 30, 28}}, Material::Granular); },
       }) {
    CAPTURE(call++);
    const std::vector<std::uint8_t> before = raw_cells(*calls, size);
    const ChangeReport report = tool();
    const std::vector<std::uint8_t> after = raw_cells(*calls, size);
    std::int64_t kept_moving = 0, changed = 0;
    for (int z = 0; z < size.z; ++z)
      for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x) {
          const std::size_t i = std::size_t(x) + std::size_t(size.x) * (std::size_t(y) + std::size_t(size.y) * std::size_t(z));
          if ((before[i] & kMaterialMask) != (after[i] & kMaterialMask)) {
            ++changed;
            REQUIRE(after[i] == (after[i] & kMaterialMask));  // a new material starts at rest
            continue;
          }
          REQUIRE(after[i] == before[i]);
          const Box& r = report.region;
          const bool inside = x >= r.min.x && x < r.max.x && y >= r.min.y && y < r.max.y && z >= r.min.z && z < r.max.z;
          kept_moving += inside && (before[i] & ~kMaterialMask) != 0;
        }
    CHECK(changed == report.cells_changed);
    CHECK(changed > 0);
    CHECK(kept_moving > 20);  // grains inside the region that the tool left alone, still moving
  }
}

TEST_CASE("world tools: bricks_changed_since stays exact for versions read between steps and tools") {
  const Int3 size{40, 36, 34};
  auto calls = std::make_shared<BackendCalls>();
  World world = counted_world(size, calls);
  world.paint(Box{{4, 4, 20}, {36, 32, 30}}, Material::Granular);
  const std::uint64_t v0 = world.change_version();
  const std::vector<std::uint8_t> start = raw_cells(*calls, size);
  world.step(4);
  const std::vector<std::uint8_t> stepped = raw_cells(*calls, size);
  const std::vector<std::uint32_t> step_bricks = differing_bricks(start, stepped, size);
  REQUIRE(!step_bricks.empty());
  // A tool right after the step: its bricks are marked before the step's are taken.
  CHECK(world.dig(Sphere{{6.0, 6.0, 6.0}, 5.0}).cells_changed == 0);  // the grains have not got there
  world.paint(Sphere{{30.0, 30.0, 5.0}, 4.0}, Material::Solid);
  const std::vector<std::uint32_t> tool_bricks = calls->woken;
  REQUIRE(!tool_bricks.empty());
  const std::vector<std::uint32_t> since_v0 = world.bricks_changed_since(v0);
  for (const std::uint32_t b : step_bricks) CHECK(std::binary_search(since_v0.begin(), since_v0.end(), b));
  for (const std::uint32_t b : tool_bricks) CHECK(std::binary_search(since_v0.begin(), since_v0.end(), b));

  // A version read after a step and before a tool lists the tool's bricks alone.
  world.step(4);
  const std::uint64_t v1 = world.change_version();
  CHECK(world.bricks_changed_since(v1).empty());
  world.paint(Sphere{{8.0, 30.0, 5.0}, 4.0}, Material::Solid);
  CHECK(world.bricks_changed_since(v1) == calls->woken);
  const std::uint64_t v2 = world.change_version();
  CHECK(v2 > v1);
  CHECK(world.bricks_changed_since(v2).empty());
}

namespace {

/// A tool as a plain loop over every cell of its region: the cells after it (whole bytes) and its
/// report, from the cells before it.
struct ReferenceTool {
  Int3 size;
  std::vector<std::uint8_t> cells;  ///< the whole grid's bytes, x fastest
  ChangeReport report{};

  /// The grid index of cell (x, y, z).
  std::size_t index(int x, int y, int z) const {
    return std::size_t(x) + std::size_t(size.x) * (std::size_t(y) + std::size_t(size.y) * std::size_t(z));
  }
  /// Whether the centre of cell (x, y, z) lies in `s`, the test as the tools state it.
  static bool inside(const Sphere& s, int x, int y, int z) {
    const double dx = x + 0.5 - s.center.x, dy = y + 0.5 - s.center.y, dz = z + 0.5 - s.center.z;
    return dx * dx + dy * dy + dz * dz <= s.radius * s.radius;
  }
  /// Gives the cell at `i` material `m` at rest when its material is another, counting it.
  void set(std::size_t i, std::uint8_t m) {
    const std::uint8_t was = cells[i] & kMaterialMask;
    if (was == m) return;
    cells[i] = m;
    ++report.cells_changed;
    ++report.removed[was];
    ++report.added[m];
  }
  /// Calls fn(x, y, z, index) for every cell of `region` whose centre lies in `s`.
  template <class Fn>
  void for_each_in(const Box& region, const Sphere& s, Fn&& fn) const {
    for (int z = region.min.z; z < region.max.z; ++z)
      for (int y = region.min.y; y < region.max.y; ++y)
        for (int x = region.min.x; x < region.max.x; ++x)
          if (inside(s, x, y, z)) fn(x, y, z, index(x, y, z));
  }
  /// The region of a sphere tool, put in the report with its clipping.
  Box region_of(const Sphere& s) {
    const Box region = sphere_region(s, size, "reference", report.clipped);
    report.region = region;
    return region;
  }

  /// Every cell in the sphere of a material that is not static becomes void.
  void dig(const Sphere& s, const MaterialTable& table) {
    for_each_in(region_of(s), s, [&](int, int, int, std::size_t i) {
      if (table[cells[i] & kMaterialMask].behaviour != Behaviour::Static) set(i, to_cell(Material::Void));
    });
  }
  /// Every cell in the sphere becomes `m`.
  void paint(const Sphere& s, Material m) {
    for_each_in(region_of(s), s, [&](int, int, int, std::size_t i) { set(i, to_cell(m)); });
  }
  /// Every cell of the box inside the grid becomes `m`.
  void paint(const Box& box, Material m) {
    report.region = intersect(box, Box{{0, 0, 0}, size});
    report.clipped = !(report.region == box);
    for (int z = report.region.min.z; z < report.region.max.z; ++z)
      for (int y = report.region.min.y; y < report.region.max.y; ++y)
        for (int x = report.region.min.x; x < report.region.max.x; ++x) set(index(x, y, z), to_cell(m));
  }
  /// The `amount` void cells in the sphere of the smallest mix64(salt ^ packed position), salt =
  /// mix64(seed ^ mix64(tick * golden ratio + tool calls before this one)).
  void pour(const Sphere& s, Material m, std::int64_t amount, std::uint64_t seed, std::uint64_t tick,
            std::uint64_t tool_calls) {
    const std::uint64_t salt = mix64(seed ^ mix64(tick * 0x9E3779B97F4A7C15ull + tool_calls));
    std::vector<std::pair<std::uint64_t, std::size_t>> voids;
    for_each_in(region_of(s), s, [&](int x, int y, int z, std::size_t i) {
      if ((cells[i] & kMaterialMask) == to_cell(Material::Void))
        voids.emplace_back(mix64(salt ^ (std::uint64_t(x) | std::uint64_t(y) << 21 | std::uint64_t(z) << 42)), i);
    });
    std::sort(voids.begin(), voids.end());
    for (std::size_t k = 0; k < voids.size() && std::int64_t(k) < amount; ++k) set(voids[k].second, to_cell(m));
  }
  /// Every granular or liquid cell in the sphere gets motion level `level`.
  void shake(const Sphere& s, int level, const MaterialTable& table) {
    for_each_in(region_of(s), s, [&](int, int, int, std::size_t i) {
      const Behaviour b = table[cells[i] & kMaterialMask].behaviour;
      if (b != Behaviour::Granular && b != Behaviour::Liquid) return;
      const auto shaken = std::uint8_t((cells[i] & ~(kMotionLevelMask << kMotionShift)) | (level << kMotionShift));
      if (shaken == cells[i]) return;
      cells[i] = shaken;
      ++report.cells_shaken;
    });
  }
};

}  // namespace

TEST_CASE("world tools: every tool equals a plain per-cell reference, pour's choice of cells included") {
  const Int3 size{40, 36, 34};  // partial bricks on every axis
  auto calls = std::make_shared<BackendCalls>();
  World world = counted_world(size, calls);
  const MaterialTable& table = world.rules().materials;
  std::uint64_t tool_calls = 0;  // the world's count, which pour's choice depends on
  std::mt19937_64 rng(20261202);
  std::uniform_real_distribution<double> coord(-6.0, 46.0), radius(0.3, 13.0), unit(0.0, 1.0);
  std::uniform_int_distribution<int> material(0, kMaterialCount - 1), pick(0, 5);
  // A mixed scene of every material, grains of it in motion.
  for (int k = 0; k < 40; ++k) {
    const Int3 lo{int(unit(rng) * 36), int(unit(rng) * 32), int(unit(rng) * 30)};
    const Int3 extent{1 + int(unit(rng) * 12), 1 + int(unit(rng) * 12), 1 + int(unit(rng) * 12)};
    world.paint(Box{lo, {lo.x + extent.x, lo.y + extent.y, lo.z + extent.z}}, Material(material(rng)));
    ++tool_calls;
  }
  int pours_clipped = 0, pours_short = 0, pours_chosen = 0;
  for (int call = 0; call < 400; ++call) {
    CAPTURE(call);
    if (call % 25 == 0) world.step(1 + int(unit(rng) * 5));  // grains moving, the tick advancing
    const std::vector<std::uint8_t> before = raw_cells(*calls, size);
    ReferenceTool expected{size, before};
    const Sphere s{{coord(rng), coord(rng), coord(rng)}, radius(rng)};
    bool clipped = false;
    try {
      (void)sphere_region(s, size, "test", clipped);
    } catch (const InvalidArgument&) {
      continue;  // misses the grid
    }
    calls->reset();
    ChangeReport got;
    const int tool = pick(rng);
    if (tool == 0) {
      got = world.dig(s);
      expected.dig(s, table);
    } else if (tool == 1 || tool == 2) {
      const Material m = Material(1 + material(rng) % (kMaterialCount - 1));
      // Amounts from none to more than the sphere holds.
      const auto amount = std::int64_t(unit(rng) * unit(rng) * 4.0 * s.radius * s.radius * s.radius);
      got = world.pour(s.center, s.radius, m, amount);
      expected.pour(s, m, amount, world.def().seed, world.tick(), tool_calls);
      pours_clipped += clipped ? 1 : 0;
      pours_short += got.cells_changed < amount ? 1 : 0;
      pours_chosen += got.cells_changed == amount && amount > 0 ? 1 : 0;
    } else if (tool == 3) {
      const Material m = Material(material(rng));
      got = world.paint(s, m);
      expected.paint(s, m);
    } else if (tool == 4) {
      const int level = 1 + int(unit(rng) * world.rules().motion.max_level());
      got = world.shake(s, level);
      expected.shake(s, level, table);
    } else {
      const Int3 lo{int(coord(rng)), int(coord(rng)), int(coord(rng))};
      const Int3 extent{1 + int(unit(rng) * 10), 1 + int(unit(rng) * 10), 1 + int(unit(rng) * 10)};
      const Box box{lo, {lo.x + extent.x, lo.y + extent.y, lo.z + extent.z}};
      if (intersect(box, Box{{0, 0, 0}, size}).empty()) continue;
      const Material m = Material(material(rng));
      got = world.paint(box, m);
      expected.paint(box, m);
    }
    ++tool_calls;
    const std::vector<std::uint8_t> after = raw_cells(*calls, size);
    REQUIRE(after == expected.cells);
    CHECK(got.cells_changed == expected.report.cells_changed);
    CHECK(got.added == expected.report.added);
    CHECK(got.removed == expected.report.removed);
    CHECK(got.cells_shaken == expected.report.cells_shaken);
    CHECK(got.region == expected.report.region);
    CHECK(got.clipped == expected.report.clipped);
    const bool changed = before != after;
    CHECK(calls->writes == (changed ? 1 : 0));
    if (changed) CHECK(calls->woken == differing_bricks(before, after, size));
  }
  // The draws reached every case of the choice: clipped spheres, amounts the void cells fall short
  // of, and amounts chosen out of more.
  CHECK(pours_clipped > 5);
  CHECK(pours_short > 5);
  CHECK(pours_chosen > 5);
}
