#include <doctest/doctest.h>

#include <cmath>
#include <memory>

#include "granular/errors.hpp"
#include "granular/rule_presets.hpp"
#include "granular/world.hpp"

// Liquid, gas and a second grain under the default rules (the motion model) on the CPU: what a
// user sees them do, measured from the grid.

using namespace granular;

namespace {

WorldDef fluid_world(Int3 size, std::shared_ptr<const RuleSet> rules = nullptr) {
  WorldDef def;
  def.size = size;
  def.backend = BackendKind::Cpu;
  def.threads = 2;
  def.rule_set = std::move(rules);
  return def;
}

/// The mean height (cell centre z) of the cells of material `m`, and how many there are.
struct Layer {
  double mean_z = 0;
  int min_z = 1 << 30, max_z = -1;
  std::uint64_t cells = 0;
};

Layer layer_of(const World& world, std::uint8_t m) {
  const Int3 n = world.size();
  const auto cells = world.read_region(Box{{0, 0, 0}, n});
  Layer l;
  double sum = 0;
  for (int z = 0; z < n.z; ++z)
    for (int y = 0; y < n.y; ++y)
      for (int x = 0; x < n.x; ++x)
        if (cells[std::size_t(x + n.x * (y + std::size_t(n.y) * z))] == m) {
          sum += z + 0.5;
          ++l.cells;
          if (z < l.min_z) l.min_z = z;
          if (z > l.max_z) l.max_z = z;
        }
  l.mean_z = l.cells ? sum / double(l.cells) : 0;
  return l;
}

std::uint8_t cell(Material m) { return to_cell(m); }

}  // namespace

TEST_CASE("fluids: a pool dropped on a flat floor spreads to one layer and then costs nothing") {
  World world(fluid_world({48, 48, 24}));
  world.paint(Box{{0, 0, 0}, {48, 48, 1}}, Material::Solid);
  world.paint(Box{{20, 20, 8}, {28, 28, 16}}, Material::Liquid);  // 512 cells: fits one layer of 2304
  const MaterialCounts before = world.count();
  int ticks = 0;
  for (; ticks < 3000; ++ticks) {
    world.step(1);
    if (world.activity().active_bricks == 0) break;
  }
  const Layer water = layer_of(world, cell(Material::Liquid));
  MESSAGE("pool: settled after " << ticks << " ticks, water at z " << water.min_z << ".." << water.max_z);
  CHECK(world.count() == before);
  CHECK(water.min_z == 1);
  CHECK(water.max_z == 1);
  CHECK(world.activity().active_bricks == 0);
}

TEST_CASE("fluids: sand poured on water sinks to the bottom, and gas under water rises above it") {
  World world(fluid_world({24, 24, 40}));
  world.paint(Box{{0, 0, 0}, {24, 24, 1}}, Material::Solid);
  world.paint(Box{{0, 0, 1}, {24, 24, 16}}, Material::Liquid);
  world.paint(Box{{8, 8, 20}, {16, 16, 26}}, Material::Granular);
  world.paint(Box{{8, 8, 2}, {12, 12, 4}}, Material::Gas);
  const MaterialCounts before = world.count();
  world.step(400);
  const Layer sand = layer_of(world, cell(Material::Granular)), water = layer_of(world, cell(Material::Liquid)),
              gas = layer_of(world, cell(Material::Gas));
  MESSAGE("sand mean z " << sand.mean_z << " (" << sand.min_z << ".." << sand.max_z << "), water " << water.mean_z << " ("
                         << water.min_z << ".." << water.max_z << "), gas " << gas.mean_z << " (" << gas.min_z << ".."
                         << gas.max_z << ")");
  CHECK(world.count() == before);
  CHECK(sand.mean_z < water.mean_z);
  CHECK(gas.min_z > water.max_z);
}

TEST_CASE("fluids: gas stays trapped under an inverted cup") {
  World world(fluid_world({32, 32, 32}));
  world.paint(Box{{0, 0, 0}, {32, 32, 1}}, Material::Solid);
  world.paint(Box{{0, 0, 1}, {32, 32, 28}}, Material::Liquid);
  // An inverted cup: a lid at z 20 over x, y 8..16 with walls down to z 14.
  world.paint(Box{{8, 8, 20}, {16, 16, 21}}, Material::Solid);
  world.paint(Box{{8, 8, 14}, {9, 16, 20}}, Material::Solid);
  world.paint(Box{{15, 8, 14}, {16, 16, 20}}, Material::Solid);
  world.paint(Box{{8, 8, 14}, {16, 9, 20}}, Material::Solid);
  world.paint(Box{{8, 15, 14}, {16, 16, 20}}, Material::Solid);
  world.paint(Box{{10, 10, 8}, {14, 14, 10}}, Material::Gas);  // 32 cells below the cup
  world.paint(Box{{24, 24, 8}, {26, 26, 10}}, Material::Gas);  // 8 cells beside it: they rise to the surface
  const MaterialCounts before = world.count();
  world.step(600);
  const auto cells = world.read_region(Box{{0, 0, 0}, {32, 32, 32}});
  int in_cup = 0, above_water = 0;
  for (int z = 0; z < 32; ++z)
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x) {
        if (cells[std::size_t(x + 32 * (y + 32 * z))] != cell(Material::Gas)) continue;
        if (x > 8 && x < 15 && y > 8 && y < 15 && z >= 14 && z < 20) ++in_cup;
        if (z >= 28) ++above_water;
      }
  MESSAGE("gas in the cup " << in_cup << " of 32, above the water " << above_water << " of 8");
  CHECK(world.count() == before);
  CHECK(in_cup == 32);
  CHECK(above_water == 8);
}

TEST_CASE("fluids: gas rising to a closed ceiling spreads under it to one layer") {
  World world(fluid_world({24, 24, 24}));
  world.paint(Box{{0, 0, 0}, {24, 24, 1}}, Material::Solid);
  world.paint(Box{{0, 0, 20}, {24, 24, 21}}, Material::Solid);
  world.paint(Box{{0, 0, 1}, {24, 24, 20}}, Material::Liquid);
  world.paint(Box{{10, 10, 3}, {14, 14, 7}}, Material::Gas);  // 64 cells
  const MaterialCounts before = world.count();
  int ticks = 0;
  for (; ticks < 3000; ++ticks) {
    world.step(1);
    if (world.activity().active_bricks == 0) break;
  }
  const Layer gas = layer_of(world, cell(Material::Gas));
  MESSAGE("gas under the ceiling: settled after " << ticks << " ticks at z " << gas.min_z << ".." << gas.max_z);
  CHECK(world.count() == before);
  CHECK(gas.min_z == 19);
  CHECK(gas.max_z == 19);
  CHECK(world.activity().active_bricks == 0);
}

TEST_CASE("fluids: a game's own material: oil, a liquid lighter than water, added as a row of a copied rule set") {
  RuleSet rules = preset("inertial-24");
  rules.name = "inertial-24-with-oil";
  MaterialDef& oil = rules.materials[6];
  oil = rules.materials[to_cell(Material::Liquid)];  // a liquid, moving as water does...
  oil.name = "oil";
  oil.density = 1;  // ...but lighter than water (2), heavier than void (0)
  oil.spread = 128;
  oil.colour = 0x3A2A10;
  World world(fluid_world({24, 24, 32}, std::make_shared<const RuleSet>(rules)));
  world.paint(Box{{0, 0, 0}, {24, 24, 1}}, Material::Solid);
  world.paint(Box{{0, 0, 1}, {24, 24, 6}}, Material::State6);   // oil at the bottom...
  world.paint(Box{{0, 0, 6}, {24, 24, 11}}, Material::Liquid);  // ...under water
  const MaterialCounts before = world.count();
  world.step(500);
  const Layer oil_layer = layer_of(world, 6), water = layer_of(world, cell(Material::Liquid));
  MESSAGE("oil z " << oil_layer.min_z << ".." << oil_layer.max_z << " (mean " << oil_layer.mean_z << "), water z "
                   << water.min_z << ".." << water.max_z << " (mean " << water.mean_z << ")");
  CHECK(world.count() == before);
  CHECK(oil_layer.mean_z > water.mean_z);
  CHECK(oil_layer.min_z >= water.max_z - 1);
}

TEST_CASE("fluids: shaking a bed of gravel on sand again and again sorts the heavier gravel below") {
  World world(fluid_world({16, 16, 24}));
  world.paint(Box{{0, 0, 0}, {16, 16, 1}}, Material::Solid);
  world.paint(Box{{0, 0, 1}, {16, 16, 5}}, Material::Granular);
  world.paint(Box{{0, 0, 5}, {16, 16, 9}}, Material::Gravel);
  const MaterialCounts before = world.count();
  world.step(50);
  const double gravel_before = layer_of(world, cell(Material::Gravel)).mean_z;
  CHECK(gravel_before > layer_of(world, cell(Material::Granular)).mean_z);  // at rest, gravel stays on top
  std::int64_t shaken = 0;
  for (int t = 0; t < 300; ++t) {
    shaken += world.shake(Sphere{{8, 8, 5}, 12}, 4).cells_shaken;
    world.step(1);
  }
  world.step(100);
  const Layer gravel = layer_of(world, cell(Material::Gravel)), sand = layer_of(world, cell(Material::Granular));
  MESSAGE("gravel mean z " << gravel_before << " -> " << gravel.mean_z << ", sand " << sand.mean_z << "; " << shaken
                           << " cells shaken");
  CHECK(world.count() == before);
  CHECK(gravel.mean_z < sand.mean_z);
  CHECK_THROWS_AS(world.shake(Sphere{{8, 8, 5}, 4}, 0), InvalidArgument);
  CHECK_THROWS_AS(world.shake(Sphere{{8, 8, 5}, 4}, 13), InvalidArgument);
}
