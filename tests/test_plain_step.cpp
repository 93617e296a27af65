/// @file test_plain_step.cpp
/// The fast CPU step against the plain per-block loop (tests/reference/plain_step.hpp) for every
/// preset: World on the CPU backend, sparse and dense, 1 and 2 threads, compared with the plain
/// loop after every tick of random scenes holding all 8 states (sand, gravel, water and gas among
/// them), on odd and even grid sizes; the plain loop on several threads (as the benchmark runs it)
/// against itself on one; the plain fluid pass against fluid::fluid_pass on random blocks; and,
/// block by block, where the fast step departs from fluid_block.hpp's comment. Under the pressure
/// lever (inertial-24-pressure), also vessels whose water stands at different heights: a U-tube and
/// a raised tank with an orifice in its wall and a hole in its floor.

#include <doctest/doctest.h>

#include <algorithm>

#include <array>
#include <cstdint>
#include <iterator>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "granular/grid.hpp"
#include "granular/rule_presets.hpp"
#include "granular/world.hpp"
#include "material_scenes.hpp"
#include "plain_divergence.hpp"
#include "plain_step.hpp"
#include "step/fluid_block.hpp"
#include "step/motion_block.hpp"
#include "step/step_materials.hpp"
#include "test_support.hpp"

using namespace granular;
using granular::test::departure_from_plain_loop;
using granular::test::test_def;

namespace {

/// Ticks each scene runs: three 8-tick offset cycles.
constexpr int kTicks = 24;

/// The PlainRules of `world`.
reference::PlainRules plain_rules_of(const World& world) {
  return reference::plain_rules(world.rules(), world.lut(), world.def().seed);
}

/// Block cells from materials in block order (bottom layer 0..3, then top layer 4..7).
BlockCells block_of(std::array<Material, 8> m) {
  BlockCells b{};
  for (int i = 0; i < 8; ++i) b[std::size_t(i)] = to_cell(m[std::size_t(i)]);
  return b;
}

/// A block's cells as the 8 bytes of a word (cell i in byte i).
std::uint64_t bytes_of(const BlockCells& b) {
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= std::uint64_t(b[std::size_t(i)]) << (8 * i);
  return v;
}

BlockCells cells_of(std::uint64_t bytes) {
  BlockCells b{};
  for (int i = 0; i < 8; ++i) b[std::size_t(i)] = std::uint8_t(bytes >> (8 * i));
  return b;
}

/// A block for messages: "bottom (water, gas, solid, solid) top (void, water:L1, solid, solid)".
std::string describe_block(const BlockCells& b) {
  std::string s;
  for (int i = 0; i < 8; ++i) {
    if (i == 0) s += "bottom (";
    if (i == 4) s += ") top (";
    if (i != 0 && i != 4) s += ", ";
    s += std::string(material_name(Material(cell_material(b[std::size_t(i)]))));
    if (cell_motion(b[std::size_t(i)]) != 0) s += ":L" + std::to_string(cell_motion(b[std::size_t(i)]));
  }
  return s + ")";
}

/// The PlainRules of a preset's material table alone (no table: for plain_fluid_pass).
reference::PlainRules plain_materials(const RuleSet& rules) {
  reference::PlainRules r;
  for (int s = 0; s < kMaterialCount; ++s) {
    const MaterialDef& d = rules.materials[std::size_t(s)];
    r.materials[std::size_t(s)] = {d.behaviour, d.density, d.spread, d.grain.topple_gain, d.grain.roll_cost,
                                   d.grain.roll_chance, d.grain.entrain};
  }
  r.substeps = rules.motion.substeps;
  return r;
}

/// A preset's table with a lighter liquid (oil, state 6) and a heavier gas (state 7) added, and water
/// spreading with chance 200/256: what the presets do not exercise of the fluid pass.
RuleSet with_oil_and_second_gas(RuleSet r) {
  MaterialDef& oil = r.materials[6];
  oil.behaviour = Behaviour::Liquid;
  oil.density = 1;
  oil.spread = 128;
  oil.grain = r.materials[to_cell(Material::Liquid)].grain;
  MaterialDef& heavy = r.materials[7];
  heavy.behaviour = Behaviour::Gas;
  heavy.density = -3;
  heavy.spread = 64;
  r.materials[to_cell(Material::Liquid)].spread = 200;
  return r;
}

}  // namespace

TEST_CASE("plain step: World's hash is the hash of its cell bytes, as the plain loop's grids are hashed") {
  const Grid initial = granular::test::all_materials_scene({17, 12, 9}, 3);
  const World world(test_def(initial.size(), "paper", 1, 3), initial);
  CHECK(world.hash() == hash_cells(initial.size(), initial.cells()));
  CHECK(world.hash() == initial.hash());
}

TEST_CASE("plain step: World on the CPU, sparse and dense, 1 and 2 threads, equals the plain loop after every tick of every preset") {
  const Int3 sizes[] = {{17, 12, 9}, {33, 20, 16}, {40, 40, 24}};
  const std::uint64_t seeds[] = {1, 0x5EED0002, 77};
  for (const std::string& preset : rule_preset_names()) {
    // Worlds of one process share the 64 MiB tables while one of them lives.
    const World keep_tables_alive(test_def({8, 8, 8}, preset.c_str(), 1), Grid({8, 8, 8}));
    for (std::size_t k = 0; k < std::size(sizes); ++k) {
      const Int3 size = sizes[k];
      const std::uint64_t seed = seeds[k];
      const Grid initial = granular::test::all_materials_scene(size, seed ^ 0xC0FFEE);
      const MaterialCounts counts = initial.count();
      for (int m = 0; m < kMaterialCount; ++m) REQUIRE_MESSAGE(counts[std::size_t(m)] > 0, "state " << m << " missing");
      const World first(test_def(size, preset.c_str(), 1, seed), initial);
      const granular::test::PlainTrajectory plain = granular::test::plain_trajectory(first, initial, kTicks);
      REQUIRE(plain.after_tick.back() != std::vector<std::uint8_t>(initial.cells().begin(), initial.cells().end()));
      // The plain loop conserves every material (each move is an exchange).
      Grid last(size);
      std::copy(plain.after_tick.back().begin(), plain.after_tick.back().end(), last.cells().begin());
      for (auto& c : last.cells()) c = cell_material(c);
      CHECK_MESSAGE(last.count() == counts, "preset " << preset << ", " << to_string(size) << ": the plain loop changed the counts");
      // The plain loop's own thread split (the benchmark's) changes nothing.
      std::vector<std::uint8_t> threaded(initial.cells().begin(), initial.cells().end());
      std::vector<std::uint8_t> threaded_side(plain.side_after_tick.empty() ? 0 : threaded.size(), 0);
      std::vector<std::int32_t> threaded_faces(plain.faces_after_tick.empty() ? 0 : plain.faces_after_tick[0].size(), 0);
      reference::plain_run(threaded, size, plain_rules_of(first), 0, kTicks, 3, threaded_side, threaded_faces);
      const std::string split = granular::test::first_differing_cell(size, plain.after_tick.back(), threaded,
                                                                     "plain loop on 1 thread", "on 3 threads");
      CHECK_MESSAGE(split.empty(), "preset " << preset << ", " << to_string(size) << ": " << split);
      if (!plain.side_after_tick.empty()) CHECK(threaded_side == plain.side_after_tick.back());
      if (!plain.faces_after_tick.empty()) {
        CHECK(threaded_faces == plain.faces_after_tick.back());
        // The pass had liquid to move: some face of the plane moved during the run.
        CHECK(std::any_of(plain.faces_after_tick.begin(), plain.faces_after_tick.end(), [](const auto& faces) {
          return std::any_of(faces.begin(), faces.end(), [](std::int32_t f) { return f != 0; });
        }));
      }
      for (const bool sparse : {true, false})
        for (const int threads : {1, 2}) {
          WorldDef def = test_def(size, preset.c_str(), threads, seed);
          def.sparse = sparse;
          World world(def, initial);
          const std::string departure = departure_from_plain_loop(world, plain);
          CHECK_MESSAGE(departure.empty(), "preset " << preset << ", " << to_string(size) << ", seed " << seed << ", "
                                                     << std::string(sparse ? "sparse" : "dense") << ", " << threads
                                                     << " thread(s): " << departure);
        }
    }
  }
}

TEST_CASE("plain step: a game's own materials (oil, a lighter liquid, and a heavier gas in states 6 and 7) equal the plain loop") {
  // States 6 and 7 of the random scenes become oil and a second gas, and water spreads with chance
  // 200/256: two liquids and two gases of different densities, drawn spreads, on a one-step and a
  // motion rule set.
  for (const char* base : {"isotropic", "inertial"}) {
    CAPTURE(base);
    const auto rules = std::make_shared<const RuleSet>(with_oil_and_second_gas(preset(base)));
    const Int3 size{24, 21, 18};
    const Grid initial = granular::test::all_materials_scene(size, 0x011);
    WorldDef def = test_def(size, base, 2, 5);
    def.rule_set = rules;
    const World first(def, initial);
    const granular::test::PlainTrajectory plain = granular::test::plain_trajectory(first, initial, kTicks);
    for (const bool sparse : {true, false}) {
      def.sparse = sparse;
      World world(def, initial);
      const std::string departure = departure_from_plain_loop(world, plain);
      CHECK_MESSAGE(departure.empty(), (sparse ? "sparse: " : "dense: ") << departure);
    }
  }
}

TEST_CASE("plain step: the plain fluid pass equals fluid::fluid_pass on random blocks, with and without motion levels") {
  // With the fast step's departures followed: everything else of the pass (its four steps, the
  // symmetry frame, the draws, the movers, the level reset) is compared here, a block at a time.
  for (const bool custom : {false, true})
    for (const bool levels : {true, false}) {
      const RuleSet base = preset(levels ? "inertial" : "paper");
      const RuleSet rules = custom ? with_oil_and_second_gas(base) : base;
      const StepMaterials mats = step_materials(rules.materials);
      const reference::PlainRules plain = plain_materials(rules);
      const int materials = custom ? 8 : 6;
      std::mt19937_64 rng(levels ? 11 : 12);
      int failures = 0;
      for (int n = 0; n < 200000 && failures < 3; ++n) {
        BlockCells cells{};
        std::array<bool, 8> mover{};
        std::uint32_t movers = 0;
        for (int i = 0; i < 8; ++i) {
          const std::uint32_t m = std::uint32_t(rng() % std::uint64_t(materials));
          const bool faller = mats.is_faller(m);
          const std::uint32_t level = levels && faller && rng() % 3 == 0 ? std::uint32_t(rng() % 4) : 0;
          cells[std::size_t(i)] = std::uint8_t(m | (level << kMotionShift) | (levels && faller && (rng() & 1) ? kMotionPhaseBit : 0));
          mover[std::size_t(i)] = !levels || (rng() & 1) != 0;
          if (mover[std::size_t(i)]) movers |= 1u << i;
        }
        const int symmetry = int(rng() & 7u);
        const std::uint64_t draws = levels ? rng() : 0;
        const std::uint64_t fast = levels ? fluid::fluid_pass<true>(bytes_of(cells), movers, symmetry, draws, mats)
                                          : fluid::fluid_pass<false>(bytes_of(cells), movers, symmetry, draws, mats);
        const BlockCells expected = reference::plain_fluid_pass(plain, cells, mover, symmetry, draws, levels);
        if (bytes_of(expected) == fast) continue;
        ++failures;
        FAIL_CHECK((custom ? "oil and a second gas, " : "the presets' materials, ")
                   << (levels ? "with levels" : "without levels") << ": block " << describe_block(cells) << ", movers 0x"
                   << std::hex << movers << ", symmetry " << symmetry << ", draws 0x" << draws << std::dec
                   << ": the plain pass gives " << describe_block(expected) << ", fluid_pass "
                   << describe_block(cells_of(fast)));
      }
    }
}

// Blocks where the fluid pass's order decides the result (fluid_block.hpp's comment: a cell moves at
// most once per pass; step 3 for every column, then step 4): the comment's result, which the plain
// loop and the fast pass must both give.

namespace {

/// A block whose result turns on the pass's order: its cells, who takes part (symmetry 0, every draw
/// 0, motion levels on, the presets' materials of "inertial"), and what the comment makes of it.
struct OrderBlock {
  const char* what;          ///< what the block shows, for messages
  BlockCells in;             ///< the block
  std::array<bool, 8> mover; ///< who takes part
  BlockCells comment;        ///< the block after the pass, by the comment
};

/// The order blocks: a cell that could move twice, and step 3 before step 4.
std::vector<OrderBlock> order_blocks() {
  using M = Material;
  std::vector<OrderBlock> d;
  // Column 0: a gas taking part under void (first block) or water (second) rises in step 1.
  // Column 1: water on water, taking part; columns 2 and 3 solid. Neither cell of column 0 moves
  // again, so the water stays: in the first block it may not topple (1b) into the void the gas
  // left, in the second the moving water (level 1) may not spread (step 2) into the gas that rose.
  const std::array<bool, 8> mover{true, false, false, false, false, true, false, false};
  d.push_back({"the void the gas left does not move again (1b)",
               block_of({M::Gas, M::Liquid, M::Solid, M::Solid, M::Void, M::Liquid, M::Solid, M::Solid}), mover,
               block_of({M::Void, M::Liquid, M::Solid, M::Solid, M::Gas, M::Liquid, M::Solid, M::Solid})});
  OrderBlock spread{"the gas that rose does not move again (step 2)",
                    block_of({M::Gas, M::Liquid, M::Solid, M::Solid, M::Liquid, M::Liquid, M::Solid, M::Solid}), mover,
                    block_of({M::Liquid, M::Liquid, M::Solid, M::Solid, M::Gas, M::Liquid, M::Solid, M::Solid})};
  spread.in[5] = spread.comment[5] = std::uint8_t(to_cell(M::Liquid) | (1u << kMotionShift));
  d.push_back(spread);
  // Gases taking part at bottom cells 1 (under the solid cell 5) and 2 (under the gas at 6). Step 3:
  // gas 2, under a gas, spreads into the denser fluid beside it: not cell 3 (solid), so the water at
  // 0 (its y neighbour). Step 4: gas 1 cannot rise; the top of its x neighbour's column (4, void)
  // is a denser fluid, but the cell under it (0) now holds gas, so it stays.
  d.push_back({"step 3 for every column before step 4",
               block_of({M::Liquid, M::Gas, M::Gas, M::Solid, M::Void, M::Solid, M::Gas, M::Solid}),
               {false, true, true, false, false, false, false, false},
               block_of({M::Gas, M::Gas, M::Liquid, M::Solid, M::Void, M::Solid, M::Gas, M::Solid})});
  return d;
}

/// The movers of a block as fluid_pass's bit mask.
std::uint32_t mover_bits(const std::array<bool, 8>& mover) {
  std::uint32_t bits = 0;
  for (int i = 0; i < 8; ++i)
    if (mover[std::size_t(i)]) bits |= 1u << i;
  return bits;
}

}  // namespace

TEST_CASE("plain step: on blocks where the pass's order decides, the plain loop and the fast pass give the comment's result") {
  const RuleSet rules = preset("inertial");
  const StepMaterials mats = step_materials(rules.materials);
  for (const OrderBlock& d : order_blocks()) {
    CAPTURE(d.what);
    const BlockCells plain = reference::plain_fluid_pass(plain_materials(rules), d.in, d.mover, 0, 0, true);
    CHECK_MESSAGE(plain == d.comment, "plain loop: " << describe_block(plain));
    const std::uint64_t fast = fluid::fluid_pass<true>(bytes_of(d.in), mover_bits(d.mover), 0, 0, mats);
    CHECK_MESSAGE(fast == bytes_of(d.comment), "fast pass: " << describe_block(cells_of(fast)));
  }
}

TEST_CASE("plain step: the fast step follows the comment: moving gravel sinks through sand in a block without a fluid") {
  // Under the motion model: gravel at level 2 in the top cell 4, inside its window, on sand; every
  // other cell solid, so it cannot fall or roll and stays (a mover). Step 1: the gravel is denser
  // and moving, so it sinks (level 0) and the sand comes up, whether or not the block holds a fluid
  // (here water in place of the solid cell 3). (Until 7eeac38 motion::step_block ran the fluid pass
  // only in a block holding a liquid or a gas.)
  using M = Material;
  const RuleSet rules = preset("inertial");
  const StepMaterials mats = step_materials(rules.materials);
  const motion::SubStep sub = motion::sub_step(rules.motion, mats, 1, 0, 1, false);
  auto load = [](std::uint32_t index) {
    return motion::motion_entry_at(index, [](std::uint32_t k) { return motion::motion_rule(motion::full_code_key(k)); });
  };
  for (const bool with_water : {false, true}) {
    CAPTURE(with_water);
    BlockCells in = block_of({M::Granular, M::Solid, M::Solid, with_water ? M::Liquid : M::Solid, M::Gravel, M::Solid,
                              M::Solid, M::Solid});
    in[4] = std::uint8_t(in[4] | (2u << kMotionShift));
    const BlockCells after = cells_of(motion::step_block(bytes_of(in), sub, 0, 0, 0, load));
    CHECK_MESSAGE((after[0] == to_cell(M::Gravel) && after[4] == to_cell(M::Granular)),
                  "sub-step 1 of tick 0, seed 1, block at the origin " << describe_block(in)
                                                                       << ": the comment sinks the gravel to level 0, the fast step gives "
                                                                       << describe_block(after));
  }
}

// The pressure lever: scenes whose water has surfaces at different heights, so that its stage moves
// water in every tick (the random scenes' water is mostly in small puddles).

namespace {

/// Ticks each pressure scene runs.
constexpr int kPressureTicks = 48;

/// A U-tube of 21 x 5 x 19 cells (odd extents: coarse cells cut at the far faces): a wall over x = 9,
/// 10 from z = 3 up, water under it and in the left leg (x 0..8) up to z = 14, in the right leg
/// (x 11..20) up to z = 4, a gas bubble at the left leg's floor and three grains of sand above the
/// right leg. Surfaces at 15 and 5 cells.
Grid u_tube() {
  Grid g({21, 5, 19});
  for (int z = 0; z < 19; ++z)
    for (int y = 0; y < 5; ++y)
      for (int x = 0; x < 21; ++x) {
        Material m = Material::Void;
        if ((x == 9 || x == 10) && z >= 3) m = Material::Solid;
        else if (x < 9 ? z <= 14 : z <= (x <= 10 ? 2 : 4)) m = Material::Liquid;
        g.set({x, y, z}, m);
      }
  g.set({3, 2, 1}, Material::Gas);
  for (int x = 14; x <= 16; ++x) g.set({x, 2, 12}, Material::Granular);
  return g;
}

/// A raised tank in 23 x 6 x 21 cells: a shelf at z = 8 over the whole grid with a hole at x = 4,
/// y = 2..3; on it water over x 0..11 up to z = 17 behind a wall at x = 12 (z 9..20) with an orifice
/// at y = 2..3, z = 9..10; void outside the wall and under the shelf, with gravel on the floor.
Grid raised_tank() {
  Grid g({23, 6, 21});
  for (int z = 0; z < 21; ++z)
    for (int y = 0; y < 6; ++y)
      for (int x = 0; x < 23; ++x) {
        Material m = Material::Void;
        const bool hole = x == 4 && (y == 2 || y == 3), orifice = (y == 2 || y == 3) && (z == 9 || z == 10);
        if (z == 8 && !hole) m = Material::Solid;
        else if (x == 12 && z >= 9 && !orifice) m = Material::Solid;
        else if (x < 12 && z >= 9 && z <= 17) m = Material::Liquid;
        else if (z == 0 && x % 3 == 0) m = Material::Gravel;
        g.set({x, y, z}, m);
      }
  return g;
}

/// Water cells of `cells` (a grid of `size`) with x in [x_min, x_max].
int water_between(const std::vector<std::uint8_t>& cells, Int3 size, int x_min, int x_max) {
  int n = 0;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const int x = int(i % std::size_t(size.x));
    if (x >= x_min && x <= x_max && cell_material(cells[i]) == std::uint8_t(Material::Liquid)) ++n;
  }
  return n;
}

}  // namespace

TEST_CASE("plain step: the plain head field gives the U-tube's low surface the head of its high one, less the way to it") {
  const Grid g = u_tube();
  const Int3 size = g.size();
  const World world(test_def(size, "inertial-24-pressure", 1), g);
  const reference::PlainRules rules = plain_rules_of(world);
  const std::vector<std::uint8_t> cells(g.cells().begin(), g.cells().end());
  const std::vector<std::int32_t> heads = reference::plain_heads(cells, size, rules);
  const Int3 c{11, 3, 10};
  REQUIRE(heads.size() == std::size_t(c.x * c.y * c.z));
  auto head_of_cell = [&](int x, int y, int z) { return heads[std::size_t(x / 2 + c.x * (y / 2 + c.y * (z / 2)))]; };
  const std::int32_t unit = reference::kPlainHeadUnit, wet = reference::kPlainWetStep, dry = reference::kPlainDryStep;
  // The left surface's coarse cells seed 15 cells; the right leg's surface (z = 4) lies under it, so
  // its head is 15 cells less a wet step per coarse step on the shortest way: 6 down the left leg, 4
  // under the wall, 1 up the right leg.
  CHECK(head_of_cell(2, 2, 14) == 15 * unit);
  CHECK(head_of_cell(16, 2, 4) == 15 * unit - 11 * wet);
  // Carried out of the body, odd: the void two coarse cells over the right surface takes its head less
  // two dry steps (the left leg's head, carried over the wall, arrives lower), and the coarse cell of
  // the wall's top beside and above the left surface takes the left head less two dry steps.
  CHECK(head_of_cell(16, 2, 8) == 15 * unit - 11 * wet - 2 * dry + 1);
  CHECK(head_of_cell(10, 0, 16) == 15 * unit - 2 * dry + 1);
  // Every coarse cell with a cell of the body keeps an even head; every other one is dry or odd, and
  // here every one is reached.
  std::vector<bool> wet_cell(heads.size());
  for (int z = 0; z < size.z; ++z)
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x) {
        const Material below = z == 0 ? Material::Solid : g.at({x, y, z - 1});
        if (g.at({x, y, z}) == Material::Liquid && below != Material::Void && below != Material::Gas)
          wet_cell[std::size_t(x / 2 + c.x * (y / 2 + c.y * (z / 2)))] = true;
      }
  for (std::size_t k = 0; k < heads.size(); ++k) {
    CAPTURE(k);
    CHECK(reference::plain_outside_body(heads[k]) == !wet_cell[k]);
    CHECK(heads[k] != reference::kPlainDry);
  }
  // The same water at motion level 1 everywhere is in free flight: no head anywhere.
  std::vector<std::uint8_t> moving = cells;
  for (auto& cell : moving)
    if (cell_material(cell) == std::uint8_t(Material::Liquid)) cell = std::uint8_t(cell | (1u << kMotionShift));
  for (const std::int32_t h : reference::plain_heads(moving, size, rules)) CHECK(h == reference::kPlainDry);
}

TEST_CASE("plain step: the plain head field carries a body's head up and sideways into dry coarse cells, never down") {
  // The raised tank: its water on the shelf (z 9..17) is the body; nothing under the shelf (coarse
  // layers 0..3, z 0..7) is reached, while the void over the surface (z 18, 19) is.
  const Grid g = raised_tank();
  const Int3 size = g.size();
  const World world(test_def(size, "inertial-24-pressure", 1), g);
  const std::vector<std::uint8_t> cells(g.cells().begin(), g.cells().end());
  const std::vector<std::int32_t> heads = reference::plain_heads(cells, size, plain_rules_of(world));
  const Int3 c{12, 3, 11};
  REQUIRE(heads.size() == std::size_t(c.x * c.y * c.z));
  auto head_of = [&](int i, int j, int k) { return heads[std::size_t(i + c.x * (j + c.y * k))]; };
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < c.y; ++j)
      for (int i = 0; i < c.x; ++i) {
        INFO("coarse cell " << i << ", " << j << ", " << k);
        CHECK(head_of(i, j, k) == reference::kPlainDry);
      }
  // The surface seeds 18 cells in coarse layer 8 (z 16, 17); the coarse cell over it lies one dry step up.
  CHECK(head_of(2, 1, 8) == 18 * reference::kPlainHeadUnit);
  CHECK(head_of(2, 1, 9) == 18 * reference::kPlainHeadUnit - reference::kPlainDryStep + 1);
}

TEST_CASE("plain step: under pressure, World on the CPU, sparse and dense, 1 and 2 threads, equals the plain loop on a U-tube and a raised tank") {
  struct Scene {
    const char* name;
    Grid grid;
    int low_x_min, low_x_max;  ///< where the water the pressure moves arrives: its count grows
  };
  const Scene scenes[] = {{"u_tube", u_tube(), 11, 20}, {"raised_tank", raised_tank(), 13, 22}};
  for (const Scene& scene : scenes) {
    CAPTURE(scene.name);
    const Int3 size = scene.grid.size();
    const World first(test_def(size, "inertial-24-pressure", 1, 9), scene.grid);
    const granular::test::PlainTrajectory plain = granular::test::plain_trajectory(first, scene.grid, kPressureTicks);
    const std::vector<std::uint8_t> start(scene.grid.cells().begin(), scene.grid.cells().end());
    const std::vector<std::uint8_t>& end = plain.after_tick.back();
    // The lever moves water: without it the plain loop ends elsewhere, and with it water reaches the
    // low side (the U-tube's right leg, the shelf outside the tank's wall).
    reference::PlainRules without = plain_rules_of(first);
    without.pressure = false;
    std::vector<std::uint8_t> unpressed = start;
    reference::plain_run(unpressed, size, without, 0, kPressureTicks);
    CHECK_MESSAGE(unpressed != end, "the pressure stage changed nothing in " << kPressureTicks << " ticks");
    const int before = water_between(start, size, scene.low_x_min, scene.low_x_max);
    const int after = water_between(end, size, scene.low_x_min, scene.low_x_max);
    CHECK_MESSAGE(after > before + 8, "water on the low side: " << before << " at tick 0, " << after << " at the end");
    // Every material conserved, and the thread split changes nothing.
    Grid last(size);
    std::copy(end.begin(), end.end(), last.cells().begin());
    for (auto& c : last.cells()) c = cell_material(c);
    CHECK(last.count() == scene.grid.count());
    std::vector<std::uint8_t> threaded = start;
    reference::plain_run(threaded, size, plain_rules_of(first), 0, kPressureTicks, 3);
    CHECK(threaded == end);
    for (const bool sparse : {true, false})
      for (const int threads : {1, 2}) {
        WorldDef def = test_def(size, "inertial-24-pressure", threads, 9);
        def.sparse = sparse;
        World world(def, scene.grid);
        const std::string departure = departure_from_plain_loop(world, plain);
        CHECK_MESSAGE(departure.empty(), (sparse ? "sparse, " : "dense, ") << threads << " thread(s): " << departure);
      }
  }
}
