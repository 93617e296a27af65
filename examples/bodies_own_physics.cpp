/// @file bodies_own_physics.cpp
/// A game's own physics moving a crate in the sand, without a physics engine: each tick the world
/// writes the crate into the grid and reports the sand's force on it (World::body_sand); the game
/// adds gravity, integrates, and hands the new pose back. A crate of half the bulk density of sand
/// dropped on a bed comes to rest about half sunk; exits 1 when it does not (it runs as a test).

#include <cstdio>

#include "granular/granular.hpp"

int main() {
  using namespace granular;
  WorldDef def;
  def.size = {48, 48, 48};
  def.backend = BackendKind::Cpu;
  World world(def);
  world.paint(Box{{0, 0, 0}, {48, 48, 20}}, Material::Granular);
  world.step(30);  // the bed settles

  BodyDef crate;  // a box 10 cells (5 cm) across, of 800 kg/m^3, dropped from above the bed
  crate.half_extents = {5, 5, 5};
  crate.density = 800;
  crate.pose.position = {24, 24, 30};
  const BodyId id = world.add_body(crate);

  const double dt = tick_seconds(world.rules(), def.cell_metres);  // seconds per tick
  const double cells_per_metre = 1 / def.cell_metres;
  BodyPose pose = world.body_pose(id);
  double vz = 0;  // m/s
  for (int tick = 0; tick < 200; ++tick) {
    world.step(1);                                      // writes the crate at `pose`, pushes the sand
    const BodySand& sand = world.body_sand(id);         // what the sand did to it
    vz += (sand.force.z / sand.mass - 9.81) * dt;       // the sand's force and gravity
    pose.velocity = {0, 0, vz * dt * cells_per_metre};  // cells per tick
    pose.position.z += pose.velocity.z;
    world.set_body_pose(id, pose);  // where it is written next tick
  }

  const BodySand& sand = world.body_sand(id);
  const double sunk = sand.submerged[to_cell(Material::Granular)] / double(sand.cells);
  std::printf("crate of 800 kg/m^3 on sand of 1600: %.0f%% of it below the sand around it, at rest at %.2f cells\n",
              100 * sunk, pose.position.z);
  return sunk > 0.4 && sunk < 0.6 && vz * vz < 1e-4 ? 0 : 1;
}
