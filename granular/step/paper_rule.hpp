#pragma once
/// @file paper_rule.hpp
/// The paper's block rule as a header-only constexpr function on plain integers, so the CPU table
/// build and a GPU table build (nvcc with --expt-relaxed-constexpr) compile the very same code.

#include <cstdint>

namespace granular::rules {

/// The void and grain table codes (step_materials.hpp): the rule sees behaviours, not materials.
inline constexpr std::uint32_t kRuleVoid = 0, kRuleGrain = 2;

/// Gravity, then flow, on the block whose states are packed in `key` (3 bits per cell, cell i at
/// bits [3i, 3i+3), cell order as in block.hpp). Returns the transition: cell i moves to the
/// position held in bits [3i, 3i+3).
constexpr std::uint32_t paper_rule(std::uint32_t key) {
  std::uint32_t state[8] = {};
  std::uint32_t at[8] = {};  // at[p]: the original cell now at position p
  for (int i = 0; i < 8; ++i) {
    state[i] = (key >> (3 * i)) & 7u;
    at[i] = std::uint32_t(i);
  }
  auto swap = [&](int p, int q) {
    const std::uint32_t s = state[p], a = at[p];
    state[p] = state[q];
    at[p] = at[q];
    state[q] = s;
    at[q] = a;
  };
  // Gravity: a grain in the top layer falls into the void below it.
  for (int column = 0; column < 4; ++column)
    if (state[column + 4] == kRuleGrain && state[column] == kRuleVoid) swap(column + 4, column);
  // Flow: a supported grain topples into a bottom cell of another column when that cell and the
  // cell above it are void; preference: the x neighbour, then y, then the diagonal.
  for (int column = 0; column < 4; ++column) {
    const int top = column + 4;
    if (state[top] != kRuleGrain) continue;
    for (int flip = 1; flip <= 3; ++flip) {
      const int target = column ^ flip;
      if (state[target] == kRuleVoid && state[target + 4] == kRuleVoid) {
        swap(top, target);
        break;
      }
    }
  }
  std::uint32_t transition = 0;
  for (int p = 0; p < 8; ++p) transition |= std::uint32_t(p) << (3 * at[p]);
  return transition;
}

static_assert(paper_rule(0) == 0xFAC688u, "uniform void is the identity");

}  // namespace granular::rules
