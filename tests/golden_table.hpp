#pragma once
/// @file golden_table.hpp
/// Fixed points of the simulation (Box2D's EXPECTED_HASH): for every preset and several shipped
/// scenes, the World::hash() of the grid (every cell byte, grains' motion bits included) after a
/// fixed number of ticks from the scene's initial grid, with a fixed seed. Every backend and
/// stepping mode (CPU and CUDA, sparse and dense, any thread count) must reach exactly these values.
///
/// A pinned value changes only with an intended change of behaviour: a rule, a preset's parameters,
/// the random draws, the offset cycle, the hash itself, or a shipped scene used here. Then the new
/// value is pasted here (the failure message prints the entry) and the commit says why it changed.
/// A refactoring, a new fast path or a new backend never changes one.
///
/// Besides the shipped scenes (sand and solid only), one scene of every material, built here
/// (all_materials_pool, tests/reference/material_scenes.hpp), is pinned under inertial-24, under its
/// columns, entrain, flow, pressure, momentum and shallow-water levers (inertial-24-columns,
/// inertial-24-entrain, inertial-24-flow, inertial-24-pressure, inertial-24-momentum, whose hash covers
/// the liquids' velocities, and inertial-24-shallow, whose hash covers the face plane) and under
/// isotropic: its values were taken where the plain per-block loop reaches
/// the same hash (test_golden.cpp checks that on every run).

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

#include "granular/grid.hpp"
#include "granular/scene.hpp"
#include "granular/world_def.hpp"
#include "reference/material_scenes.hpp"

namespace granular::test {

/// One fixed point: `preset` run `ticks` ticks on scene `scene` at size parameter `n` gives `hash`.
struct GoldenCase {
  std::string_view preset;  ///< rule-set preset name
  std::string_view scene;   ///< shipped scene name (assets/scenes), or kAllMaterialsScene
  int n = 0;                ///< the scene's size parameter N
  int ticks = 0;            ///< ticks stepped from the initial grid
  std::uint64_t hash = 0;   ///< World::hash() after them
};

/// The seed of every golden run (WorldDef::seed).
inline constexpr std::uint64_t kGoldenSeed = 20240611;

/// The scene name of the golden scene of every material (not a shipped one: all_materials_pool).
inline constexpr std::string_view kAllMaterialsScene = "all-materials";

/// The pinned hashes.
inline constexpr GoldenCase kGoldenCases[] = {
    {"paper", "bowl", 32, 64, 0x045de1826a9c4857ull},
    {"paper", "hourglass", 48, 64, 0x2cf2a8991bd7b342ull},
    {"paper", "silo", 32, 64, 0xf9a14cfef23b9cd6ull},
    {"paper", "column", 32, 64, 0x9b35d014d2350503ull},
    {"isotropic", "bowl", 32, 64, 0xac9009cd7298f0cbull},
    {"isotropic", "hourglass", 48, 64, 0x337653942c48fa50ull},
    {"isotropic", "silo", 32, 64, 0x3104cf6862ebb73bull},
    {"isotropic", "column", 32, 64, 0xefddf2afa2d222e8ull},
    {"d4", "bowl", 32, 64, 0xcaf274c1b28f1fc0ull},
    {"d4", "hourglass", 48, 64, 0x51a47f90e3bc833full},
    {"d4", "silo", 32, 64, 0xc70aaf149d621d75ull},
    {"d4", "column", 32, 64, 0xdc32a2bc73893593ull},
    {"inertial", "bowl", 32, 64, 0x162ebb90451842d2ull},
    {"inertial", "hourglass", 48, 64, 0x8291fe42209f8d43ull},
    {"inertial", "silo", 32, 64, 0x74371f6ff6fb978aull},
    {"inertial", "column", 32, 64, 0x9204b48c4fc868c1ull},
    {"inertial-24", "bowl", 32, 64, 0x706364cf37fe7cfaull},
    {"inertial-24", "hourglass", 48, 64, 0xb08b704bab29288full},
    {"inertial-24", "silo", 32, 64, 0xf6a204e1d1dff6a1ull},
    {"inertial-24", "column", 32, 64, 0x859b206d9050e052ull},
    {"inertial-24-columns", "bowl", 32, 64, 0xeb7714f5a74f4ee8ull},
    {"inertial-24-columns", "hourglass", 48, 64, 0x84c1b03f5bf9aca9ull},
    {"inertial-24-columns", "silo", 32, 64, 0xd71364a391f44311ull},
    {"inertial-24-columns", "column", 32, 64, 0xeb6be82a1d475f9full},
    {"inertial-24-entrain", "bowl", 32, 64, 0x88795ed963b3f1d5ull},
    {"inertial-24-entrain", "hourglass", 48, 64, 0x713fd9334023d4baull},
    {"inertial-24-entrain", "silo", 32, 64, 0x8c4d65cf4d7ecba2ull},
    {"inertial-24-entrain", "column", 32, 64, 0x142bea3ce32404a5ull},
    {"inertial-24-flow", "bowl", 32, 64, 0x8e5f2b19f2e47c41ull},
    {"inertial-24-flow", "hourglass", 48, 64, 0x7895c16b0374fce1ull},
    {"inertial-24-flow", "silo", 32, 64, 0x3442a3dea4230868ull},
    {"inertial-24-flow", "column", 32, 64, 0xa17205bf1b960973ull},
    {"isotropic", kAllMaterialsScene, 32, 64, 0x1c7ef40c215698ddull},
    {"inertial-24", kAllMaterialsScene, 32, 64, 0x2e00f47e4960e98eull},
    {"inertial-24-columns", kAllMaterialsScene, 32, 64, 0x10608ddf7ee460cfull},
    {"inertial-24-entrain", kAllMaterialsScene, 32, 64, 0x60a982d6c7d21217ull},
    {"inertial-24-flow", kAllMaterialsScene, 32, 64, 0x7b93add6cb51175eull},
    {"inertial-24-pressure", "bowl", 32, 64, 0x8e5f2b19f2e47c41ull},
    {"inertial-24-pressure", "u_tube", 32, 64, 0x2b429c74b259f3dfull},
    {"inertial-24-pressure", "dam_break", 32, 64, 0x2d1ba34e299a553eull},
    {"inertial-24-pressure", "reservoir", 32, 64, 0x05b3d389767bb1c7ull},
    {"inertial-24-pressure", kAllMaterialsScene, 32, 64, 0xb5a5cc38e4e3ef63ull},
    {"inertial-24-momentum", "bowl", 32, 64, 0xee8d99e5eeb9f204ull},
    {"inertial-24-momentum", "u_tube", 32, 64, 0xdca0bf913c4640caull},
    {"inertial-24-momentum", "dam_break", 32, 64, 0x4d216388a7e144e3ull},
    {"inertial-24-momentum", "reservoir", 32, 64, 0xb05bc95b8406c9e8ull},
    {"inertial-24-momentum", kAllMaterialsScene, 32, 64, 0xf52f8bc046a7c748ull},
    {"inertial-24-shallow", "bowl", 32, 64, 0x8e5f2b19f2e47c41ull},
    {"inertial-24-shallow", "u_tube", 32, 64, 0xefac5f24f42e5e63ull},
    {"inertial-24-shallow", "dam_break", 32, 64, 0xade4738cf4f237c9ull},
    {"inertial-24-shallow", "reservoir", 32, 64, 0x94866a84aaf481f7ull},
    {"inertial-24-shallow", kAllMaterialsScene, 32, 64, 0xb00aa78a0e885ab0ull},
};

/// The initial grid of a golden case: its shipped scene built at its N (the scene of every material
/// built here).
inline Grid golden_initial(const GoldenCase& c) {
  if (c.scene == kAllMaterialsScene) return all_materials_pool(c.n);
  return instantiate(load_scene(find_scene(c.scene)), c.n).grid;
}

/// The WorldDef of a golden run on `backend`, sparse or dense, with 2 CPU threads and the table
/// cache from the environment.
inline WorldDef golden_def(const GoldenCase& c, BackendKind backend, bool sparse) {
  WorldDef def;
  def.rules = std::string(c.preset);
  def.seed = kGoldenSeed;
  def.backend = backend;
  def.threads = 2;
  def.sparse = sparse;
  return def;
}

/// The table entry of a case with hash `hash`, as it is written above.
inline std::string golden_entry(const GoldenCase& c, std::uint64_t hash) {
  char h[24];
  std::snprintf(h, sizeof h, "0x%016llxull", static_cast<unsigned long long>(hash));
  return "{\"" + std::string(c.preset) + "\", \"" + std::string(c.scene) + "\", " + std::to_string(c.n) + ", " +
         std::to_string(c.ticks) + ", " + h + "}";
}

}  // namespace granular::test
