#include <chrono>
#include <string>
#include <vector>

#include "granular/world.hpp"
#include "suite_tests.hpp"

namespace granular::accuracy {

namespace {

/// A closed box (the grid's sides, floor and ceiling are its walls) `side` cells square and
/// `height` high: liquid `depth` cells deep on the floor, a block of sand held `drop` cells above
/// the liquid (its base a third of the side, `sand_layers` high), and a pocket of gas on the floor
/// under the liquid (a sixth of the side, 2 layers high), off the sand's axis.
struct Box3 {
  int side, height, depth, drop, sand_layers;
  Int3 size() const { return {side, side, height}; }
  Grid build() const {
    Grid g(size());
    g.fill(Box{{0, 0, 0}, {side, side, depth}}, Material::Liquid);
    const int sand = side / 3, lo = (side - sand) / 2;
    g.fill(Box{{lo, lo, depth + drop}, {lo + sand, lo + sand, depth + drop + sand_layers}}, Material::Granular);
    const int gas = side / 6;
    g.fill(Box{{1, 1, 0}, {1 + gas, 1 + gas, 2}}, Material::Gas);
    return g;
  }
};

/// What the test reads from the grid: cells of sand with liquid somewhere below them in their
/// column, cells of gas with liquid somewhere above them, and each material's mean height.
struct Layering {
  double sand_over_liquid = 0, gas_under_liquid = 0;
  double sand_z = 0, liquid_z = 0, gas_z = 0;
};

Layering layering(const Grid& g) {
  const Int3 s = g.size();
  Layering l;
  double sand = 0, liquid = 0, gas = 0;
  for (int y = 0; y < s.y; ++y)
    for (int x = 0; x < s.x; ++x) {
      // Upward: liquid met so far lies below; downward (second pass): liquid above.
      bool liquid_below = false;
      for (int z = 0; z < s.z; ++z) {
        const Material m = g.at({x, y, z});
        if (m == Material::Liquid) {
          liquid_below = true;
          l.liquid_z += z + 0.5;
          liquid += 1;
        } else if (m == Material::Granular) {
          l.sand_over_liquid += liquid_below;
          l.sand_z += z + 0.5;
          sand += 1;
        } else if (m == Material::Gas) {
          l.gas_z += z + 0.5;
          gas += 1;
        }
      }
      bool liquid_above = false;
      for (int z = s.z - 1; z >= 0; --z) {
        const Material m = g.at({x, y, z});
        if (m == Material::Liquid) liquid_above = true;
        else if (m == Material::Gas) l.gas_under_liquid += liquid_above;
      }
    }
  if (sand > 0) l.sand_z /= sand;
  if (liquid > 0) l.liquid_z /= liquid;
  if (gas > 0) l.gas_z /= gas;
  return l;
}

}  // namespace

TestReport run_buoyancy_test(const SuiteOptions& o) {
  const Box3 box = o.quick ? Box3{24, 40, 16, 8, 6} : Box3{96, 160, 64, 32, 24};
  // Time enough for the slowest rules (one cell per tick) to carry the sand and the gas across the
  // box many times over.
  const std::uint64_t limit = 16 * std::uint64_t(box.height);
  std::string scene = "closed box " + std::to_string(box.side) + "^2 x " + std::to_string(box.height) + ": liquid " +
                      std::to_string(box.depth) + " deep, a block of sand " + std::to_string(box.side / 3) + "^2 x " +
                      std::to_string(box.sand_layers) + " released " + std::to_string(box.drop) + " above it, a gas pocket " +
                      std::to_string(box.side / 6) + "^2 x 2 on the floor under the liquid; run until at rest or " +
                      std::to_string(limit) + " ticks";
  TestReport r = open_report(o, "buoyancy", "Buoyancy: sand sinks, gas rises, every material conserved", scene);
  const Grid initial = box.build();
  World world(test_world_def(o, box.size()), initial);
  const MaterialCounts before = world.count();
  const std::string x_label = "ticks", y_label = "mean height / box height";
  Series sand{"sand", x_label, y_label, {}, {}, false}, liquid{"liquid", x_label, y_label, {}, {}, false},
      gas{"gas", x_label, y_label, {}, {}, false};
  std::int64_t layered_at = -1;  // the first sampled tick with the sand below and the gas above the liquid
  auto sample = [&](std::uint64_t tick, const Grid& g) {
    const Layering l = layering(g);
    for (Series* s : {&sand, &liquid, &gas}) s->x.push_back(double(tick));
    sand.y.push_back(l.sand_z / box.height);
    liquid.y.push_back(l.liquid_z / box.height);
    gas.y.push_back(l.gas_z / box.height);
    if (l.sand_over_liquid == 0 && l.gas_under_liquid == 0 && layered_at < 0) layered_at = std::int64_t(tick);
    if (l.sand_over_liquid != 0 || l.gas_under_liquid != 0) layered_at = -1;
  };
  const auto start = std::chrono::steady_clock::now();
  sample(0, initial);
  bool settled = false;
  std::uint64_t ticks = 0, previous = world.hash();
  while (ticks < limit) {
    world.step(8);
    ticks += 8;
    sample(ticks, world.read_grid());
    const std::uint64_t h = world.hash();
    if (h == previous) {
      settled = true;
      break;
    }
    previous = h;
  }
  const Grid final_grid = world.read_grid();
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.ticks = ticks;
  r.cell_updates = double(initial.cell_count()) * double(ticks);
  const MaterialCounts after = final_grid.count();
  double changed = 0;
  for (int m = 0; m < kMaterialCount; ++m) changed += after[std::size_t(m)] != before[std::size_t(m)];
  r.conserved = changed == 0;
  const Layering l = layering(final_grid);
  const std::string archimedes = "Archimedes: a body denser than the liquid sinks to the bottom, a lighter one rises to the top";
  r.metrics.push_back({"sand_over_liquid", "cells", l.sand_over_liquid, 0, 0.5,
                       archimedes + " (sand cells with liquid below them in their column)"});
  r.metrics.push_back({"gas_under_liquid", "cells", l.gas_under_liquid, 0, 0.5,
                       archimedes + " (gas cells with liquid above them in their column)"});
  r.metrics.push_back({"materials_not_conserved", "materials", changed, 0, 0.5, "absolute: the rules are permutations"});
  r.series.push_back(sand);
  r.series.push_back(liquid);
  r.series.push_back(gas);
  r.notes.push_back("mean heights at the end (cells): sand " + std::to_string(l.sand_z) + ", liquid " + std::to_string(l.liquid_z) +
                    ", gas " + std::to_string(l.gas_z));
  if (layered_at >= 0)
    r.notes.push_back("sand below and gas above the liquid from tick " + std::to_string(layered_at) + " on (sampled every 8)");
  r.notes.push_back(settled ? "at rest after " + std::to_string(ticks - 8) + " ticks"
                            : "not at rest after " + std::to_string(limit) + " ticks: measured then");
  return r;
}

}  // namespace granular::accuracy
