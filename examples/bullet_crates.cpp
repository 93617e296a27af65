/// @file bullet_crates.cpp
/// Crates and balls of several densities dropped into sand and into water, moved by Bullet and
/// pushed back by the sand (granular::bullet's BulletCoupling). Light ones float, heavy ones sink to
/// the floor, and every grain and drop of water is still there at the end; exits 1 when any of that
/// is not so (it runs as a test).

#include <btBulletDynamicsCommon.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "granular/bullet_coupling.hpp"
#include "granular/world.hpp"

int main() {
  using namespace granular;
  // A 40 x 20 x 20 cm box of 5 mm cells: a sand bed on the left, a pool on the right, a wall between.
  WorldDef def;
  def.size = {80, 40, 40};
  def.backend = BackendKind::Cpu;
  World world(def);
  world.paint(Box{{0, 0, 0}, {39, 40, 16}}, Material::Granular);
  world.paint(Box{{39, 0, 0}, {41, 40, 28}}, Material::Solid);
  world.paint(Box{{41, 0, 0}, {80, 40, 16}}, Material::Liquid);
  world.step(30);  // the bed settles
  const MaterialCounts before = world.count();

  // Bullet, in metres, z up.
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld dynamics(&dispatcher, &broadphase, &solver, &configuration);
  dynamics.setGravity(btVector3(0, 0, -9.81f));
  BulletCoupling coupling(world, dynamics);

  // Each body: a shape, a density and where it is dropped (cells), and whether it should float.
  struct Drop {
    const char* name;
    bool ball;
    double density;  // kg/m^3
    double x, y;     // cells
    bool floats;
  };
  const std::vector<Drop> drops{
      {"light crate in sand", false, 700, 10, 12, true},    {"heavy crate in sand", false, 3600, 28, 12, false},
      {"cork ball in sand", true, 300, 18, 30, true},       {"light crate in water", false, 450, 52, 12, true},
      {"heavy crate in water", false, 2500, 70, 12, false}, {"steel ball in water", true, 7800, 60, 30, false}};
  const double cell = def.cell_metres, half = 4 * cell;  // crates and balls 8 cells (4 cm) across
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btDefaultMotionState>> states;
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  for (const Drop& d : drops) {
    shapes.push_back(d.ball ? std::unique_ptr<btCollisionShape>(new btSphereShape(btScalar(half)))
                            : std::unique_ptr<btCollisionShape>(
                                  new btBoxShape(btVector3(btScalar(half), btScalar(half), btScalar(half)))));
    const double volume = d.ball ? 4.0 / 3.0 * 3.14159265358979 * half * half * half : 8 * half * half * half;
    const btScalar mass = btScalar(d.density * volume);
    btVector3 inertia;
    shapes.back()->calculateLocalInertia(mass, inertia);
    btTransform at;
    at.setIdentity();
    at.setOrigin(btVector3(btScalar(d.x * cell), btScalar(d.y * cell), btScalar(30 * cell)));
    states.push_back(std::make_unique<btDefaultMotionState>(at));
    bodies.push_back(std::make_unique<btRigidBody>(mass, states.back().get(), shapes.back().get(), inertia));
    dynamics.addRigidBody(bodies.back().get());
    coupling.add(*bodies.back());
  }

  for (int tick = 0; tick < 150; ++tick) coupling.step();  // 4.8 s

  bool ok = true;
  for (std::size_t i = 0; i < drops.size(); ++i) {
    const double z = bodies[i]->getWorldTransform().getOrigin().z() / cell;  // centre, cells
    const BodySand& sand = world.body_sand(coupling.body_of(*bodies[i]));
    double submerged = 0;
    for (int m = 1; m < kMaterialCount; ++m) submerged += sand.submerged[std::size_t(m)];
    const double share = sand.cells > 0 ? submerged / double(sand.cells) : 0;
    const bool floats = z - 4 > 2 && share < 0.95;  // off the floor, part of it out
    const bool sank = z - 4 < 1.5;                  // its bottom on the floor
    const bool right = drops[i].floats ? floats : sank;
    std::printf("%-22s %6.0f kg/m^3: centre %5.1f cells above the floor, %3.0f%% submerged: %s\n", drops[i].name,
                drops[i].density, z, 100 * share, right ? (drops[i].floats ? "floats" : "sank") : "WRONG");
    ok = ok && right;
  }
  const MaterialCounts after = world.count();
  for (const Material m : {Material::Granular, Material::Liquid})
    if (after[to_cell(m)] != before[to_cell(m)]) {
      std::printf("%s: %llu cells before, %llu after\n", std::string(material_name(m)).c_str(),
                  static_cast<unsigned long long>(before[to_cell(m)]),
                  static_cast<unsigned long long>(after[to_cell(m)]));
      ok = false;
    }
  for (const auto& body : bodies) dynamics.removeRigidBody(body.get());
  std::printf("%s\n", ok ? "every body where its density puts it; sand and water conserved" : "FAILED");
  return ok ? 0 : 1;
}
