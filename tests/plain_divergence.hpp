#pragma once
/// @file plain_divergence.hpp
/// Where a World departs from the plain per-block loop (tests/reference): the plain loop's cells
/// after every tick from an initial grid, and a tick-by-tick comparison of a World with them that
/// names the first tick and cell where they differ.

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "granular/grid.hpp"
#include "granular/world.hpp"
#include "plain_step.hpp"
#include "test_support.hpp"

namespace granular::test {

/// The plain loop's run from an initial grid: its cells (motion bits included) after each tick,
/// under MotionParams::momentum its side plane, and under MotionParams::shallow its face plane.
struct PlainTrajectory {
  Int3 size{};                                      ///< grid extent
  std::vector<std::vector<std::uint8_t>> after_tick;  ///< after_tick[t]: the cells after tick t (0-based)
  std::vector<std::vector<std::uint8_t>> side_after_tick;  ///< the side plane after tick t (momentum; else empty)
  std::vector<std::vector<std::int32_t>> faces_after_tick;  ///< the face plane after tick t (shallow; else empty)
};

/// The World::hash() of a grid of `size` holding `cells`, the side plane `side` and the face plane
/// `faces` (empty: none).
inline std::uint64_t plain_hash(Int3 size, const std::vector<std::uint8_t>& cells, const std::vector<std::uint8_t>& side,
                                const std::vector<std::int32_t>& faces = {}) {
  return finish_hash(size, hash_words(cells, 0, (cells.size() + 7) / 8) + side_hash_term(side) + faces_hash_term(faces));
}

/// The hash of the plain loop's state after tick t.
inline std::uint64_t plain_hash_after(const PlainTrajectory& plain, std::size_t t) {
  return plain_hash(plain.size, plain.after_tick[t],
                    plain.side_after_tick.empty() ? std::vector<std::uint8_t>() : plain.side_after_tick[t],
                    plain.faces_after_tick.empty() ? std::vector<std::int32_t>() : plain.faces_after_tick[t]);
}

/// Runs the plain loop `ticks` ticks from `initial` with the rule set, table and seed of `world`.
inline PlainTrajectory plain_trajectory(const World& world, const Grid& initial, int ticks) {
  const reference::PlainRules rules = reference::plain_rules(world.rules(), world.lut(), world.def().seed);
  PlainTrajectory run{initial.size(), {}, {}, {}};
  std::vector<std::uint8_t> cells(initial.cells().begin(), initial.cells().end());
  std::vector<std::uint8_t> side(rules.momentum ? cells.size() : 0, 0);
  std::vector<std::int32_t> faces(rules.shallow ? 4 * std::size_t(initial.size().x) * std::size_t(initial.size().y) : 0, 0);
  for (int t = 0; t < ticks; ++t) {
    reference::plain_step(cells, initial.size(), rules, std::uint64_t(t), 1, side, faces);
    run.after_tick.push_back(cells);
    if (rules.momentum) run.side_after_tick.push_back(side);
    if (rules.shallow) run.faces_after_tick.push_back(faces);
  }
  return run;
}

/// A 64-bit hash as "0x" and 16 hex digits.
inline std::string hex64(std::uint64_t v) {
  char s[24];
  std::snprintf(s, sizeof s, "0x%016llx", static_cast<unsigned long long>(v));
  return s;
}

/// Steps `world`, which must be at tick 0 holding the trajectory's initial grid, one tick at a time
/// over the trajectory; "" when its hash equals the plain loop's after every tick, else a message
/// naming the first tick where they differ and the first cell whose material differs then, or,
/// when every material agrees, that the difference lies in grains' motion bits (World reads
/// materials only; its hash covers the whole byte).
inline std::string departure_from_plain_loop(World& world, const PlainTrajectory& plain) {
  for (std::size_t t = 0; t < plain.after_tick.size(); ++t) {
    world.step(1);
    const std::vector<std::uint8_t>& expected = plain.after_tick[t];
    const std::uint64_t got = world.hash(), want = plain_hash_after(plain, t);
    if (got == want) continue;
    std::string where = "after tick " + std::to_string(t) + " the world's hash is " + hex64(got) +
                        ", the plain loop's " + hex64(want) + "; ";
    std::vector<std::uint8_t> materials(expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) materials[i] = cell_material(expected[i]);
    const Grid snapshot = world.read_grid();
    const std::string cell = first_differing_cell(plain.size, materials, snapshot.cells(), "plain loop", "world");
    return where + (cell.empty() ? "every material agrees, so they differ in grains' motion bits or liquids' velocities only"
                                 : "materials only (World reads no motion bits): " + cell);
  }
  return {};
}

}  // namespace granular::test
