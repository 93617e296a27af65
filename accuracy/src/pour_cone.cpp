#include "granular/accuracy/pour_cone.hpp"

#include <algorithm>
#include <chrono>
#include <string>

#include "granular/errors.hpp"
#include "granular/rule_set.hpp"
#include "granular/world.hpp"
#include "settle.hpp"

namespace granular::accuracy {

PourResult pour_cone(const WorldDef& base, int floor_size, int height, std::int64_t grains_per_tick,
                     std::uint64_t ticks, std::uint64_t settle_ticks, double spout_radius, Material material,
                     std::uint64_t max_grains) {
  if (floor_size < 8) throw InvalidArgument("pour_cone: floor_size = " + std::to_string(floor_size) + " must be >= 8");
  if (height < 8) throw InvalidArgument("pour_cone: height = " + std::to_string(height) + " must be >= 8");
  if (grains_per_tick < 0)
    throw InvalidArgument("pour_cone: grains_per_tick = " + std::to_string(grains_per_tick) + " must be >= 0");
  if (!(spout_radius >= 1 && spout_radius <= height / 4.0))
    throw InvalidArgument("pour_cone: spout_radius = " + std::to_string(spout_radius) + " must lie in [1, height / 4 = " +
                          std::to_string(height / 4.0) + "]");
  WorldDef def = base;
  def.size = {floor_size, floor_size, height};
  World world(def);
  if (world.rules().materials[to_cell(material)].behaviour != Behaviour::Granular)
    throw InvalidArgument("pour_cone: material '" + std::string(material_name(material)) + "' is not granular in rule set '" +
                          world.rules().name + "'");
  world.paint(Box{{0, 0, 0}, {floor_size, floor_size, 1}}, Material::Solid);

  PourResult result;
  result.before = world.count();
  const Vec3 spout{floor_size / 2.0, floor_size / 2.0, height - 2.0 - spout_radius};
  const auto start = std::chrono::steady_clock::now();
  for (std::uint64_t t = 0; t < ticks && result.poured < max_grains; ++t) {
    const std::int64_t amount = std::int64_t(std::min<std::uint64_t>(std::uint64_t(grains_per_tick), max_grains - result.poured));
    const ChangeReport report = world.pour(spout, spout_radius, material, amount);
    result.poured += report.added[to_cell(material)];
    world.step(1);
    ++result.pour_ticks;
  }
  result.settled = settle(world, settle_ticks).settled;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.ticks = world.tick();
  result.grid = world.read_grid();
  result.after = result.grid.count();
  result.conserved = true;
  for (int m = 0; m < kMaterialCount; ++m)
    result.conserved = result.conserved && result.after[std::size_t(m)] == result.before[std::size_t(m)] +
                                                                             (m == to_cell(material) ? result.poured : 0) -
                                                                             (m == to_cell(Material::Void) ? result.poured : 0);
  result.metrics = measure_cone(result.grid, spout, 1, material);
  return result;
}

}  // namespace granular::accuracy
