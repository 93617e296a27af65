#pragma once
/// @file brick_reach.hpp
/// Idle bricks under a motion model: a sub-step of sparse stepping leaves out an awake brick when
/// nothing near it can move in that sub-step. Shared by the CPU and CUDA backends.
///
/// A faller at motion level L takes part only in the sub-steps of its window, and in a sub-step
/// s >= 2 only when s + 2 <= 2 L + start (motion::reach_of). Each brick keeps a *reach*: the
/// largest 2 L + start recorded into it in the current tick. A stepped block adds reach_of(its bytes
/// after the step) to its owner brick in sub-steps 0 and 1 (every awake brick is stepped there; the
/// reach restarts at sub-step 0) and, later, when it changed (MotionRule::reach_added). Reaches only
/// grow within a tick, so every faller with 2 L + start >= s + 2 that sits in a block owned by brick
/// c was recorded into the owner of its block when it last moved or changed level, or at sub-step 0
/// or 1 (a faller in a block of an asleep brick is at rest, below every such bound): that owner holds
/// the faller's cell or lies one brick above it along each axis. A block of brick b touches only b's
/// footprint (b and the one-cell layer below it), so the fallers that could take part in b's blocks
/// were recorded into b or one of its 26 neighbours.
///
/// In a sub-step s >= 2 a brick is *idle* when the largest reach of it and its neighbours is below
/// s + 2 (MotionRule::idle): none of its blocks can change. An idle brick that is already dirty in
/// the cycle needs neither stepping nor quiet tests, so sparse stepping leaves it out; the cells,
/// dirty and changed flags are those of stepping it. (An idle brick not yet dirty is stepped: its
/// quiet tests decide whether it stays awake.)

#include <cstdint>

#include "granular/geometry.hpp"
#include "step/brick_grid.hpp"

namespace granular {

/// Neighbours of a brick whose reach decides whether it is idle: itself and its 26 neighbours.
inline constexpr int kReachNeighbours = 27;

/// The index of neighbour `n` (0 .. kReachNeighbours - 1) of brick `b` in a grid of `bricks` bricks
/// per axis, or false when that neighbour lies outside the grid.
constexpr bool reach_neighbour(Int3 bricks, Int3 b, int n, std::uint32_t& index) {
  const int x = b.x + n % 3 - 1, y = b.y + n / 3 % 3 - 1, z = b.z + n / 9 - 1;
  if (x < 0 || y < 0 || z < 0 || x >= bricks.x || y >= bricks.y || z >= bricks.z) return false;
  index = brick_index(bricks, x, y, z);
  return true;
}

}  // namespace granular
