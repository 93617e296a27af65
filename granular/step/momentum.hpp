#pragma once
/// @file momentum.hpp
/// The side plane of MotionParams::momentum: one byte per cell beside the cell byte, carried with
/// it by every permutation of the block step (the paper's "concurrent buffers that map properties to
/// specific cells"). A liquid's side byte is its sideways velocity, two signed nibbles: bits 0..3 its
/// x component, bits 4..7 its y component, each -kTopSpeed .. kTopSpeed. Every other cell's side byte
/// is 0: only the fluid pass sets one, and only on a liquid.
///
/// Speed n (a component's magnitude) lets the liquid take a sideways step along that axis in the
/// first n / kTopSpeed of a tick's sub-steps (in_window). Under the lever a cell finds its x (and y)
/// neighbour in its block in about 3 of every 4 sub-steps (motion::motion_offset), so speed kTopSpeed is
/// top_cells(substeps) = 3 substeps / 4 cells a tick (18 under 24 sub-steps), the schedule's top
/// sideways speed, and speed n about n / kTopSpeed of it.

#include <cstdint>

namespace granular::momentum {

/// The largest speed of a component.
inline constexpr int kTopSpeed = 7;

/// Chance out of 256 that a push handed on to the liquid ahead loses one speed unit.
inline constexpr int kHandOnLoss = 32;

/// The component along axis `axis` (0: x, bits 0..3; 1: y, bits 4..7) of side byte `side`.
constexpr int component(std::uint32_t side, int axis) {
  const int v = int((side >> (4 * axis)) & 15u);
  return v >= 8 ? v - 16 : v;
}

/// `v` clamped to -kTopSpeed .. kTopSpeed.
constexpr int clamp_speed(int v) { return v > kTopSpeed ? kTopSpeed : (v < -kTopSpeed ? -kTopSpeed : v); }

/// `side` with its component along `axis` set to `v` (clamped).
constexpr std::uint32_t with_component(std::uint32_t side, int axis, int v) {
  const int shift = 4 * axis;
  return (side & (0xF0u >> shift)) | (std::uint32_t(clamp_speed(v) & 15) << shift);
}

/// True when a component of speed `speed` (its magnitude) may take a step in sub-step `substep` of
/// a tick of `substeps`: in the first speed / kTopSpeed of the tick.
constexpr bool in_window(int speed, int substep, int substeps) { return substep * kTopSpeed < speed * substeps; }

/// The cells a tick of speed kTopSpeed under `substeps` sub-steps: the schedule's top sideways speed.
constexpr int top_cells(int substeps) { return 3 * substeps / 4; }

/// The speed of `cells_per_tick` cells a tick under `substeps` sub-steps, rounded, at most kTopSpeed.
constexpr int speed_of(int cells_per_tick, int substeps) {
  const int top = top_cells(substeps);
  return clamp_speed((2 * kTopSpeed * cells_per_tick + top) / (2 * top));
}

}  // namespace granular::momentum
