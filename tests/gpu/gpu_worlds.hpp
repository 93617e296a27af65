#pragma once
/// @file gpu_worlds.hpp
/// What the GPU tests share to set worlds side by side: a WorldDef per backend, and the first cell
/// where two worlds differ.

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "granular/rule_presets.hpp"
#include "granular/world.hpp"
#include "granular/world_snapshot.hpp"

namespace granular::test {

/// A WorldDef on `backend` (the CPU with 2 threads), sparse or dense, under `rules` and `seed`, with
/// both of CUDA's dense fractions (CudaOptions::dense_fraction and motion_dense_fraction) set to
/// `dense_fraction`.
inline WorldDef gpu_test_def(BackendKind backend, bool sparse, const char* rules, std::uint64_t seed,
                             double dense_fraction) {
  WorldDef def;
  def.rules = rules;
  def.seed = seed;
  def.backend = backend;
  def.threads = 2;
  def.sparse = sparse;
  def.cuda.dense_fraction = def.cuda.motion_dense_fraction = dense_fraction;
  return def;
}

/// "" when `x` and `y` (the bytes of every cell of world `a`'s grid, or empty for all zero) are
/// equal, else the first cell where they differ, both values and the tick, after `what`.
inline std::string first_byte_difference(const World& a, const char* what, const std::vector<std::uint8_t>& x,
                                         const std::vector<std::uint8_t>& y) {
  if (x == y) return {};
  const std::size_t n = std::max(x.size(), y.size());
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned u = i < x.size() ? x[i] : 0u, v = i < y.size() ? y[i] : 0u;
    if (u == v) continue;
    const std::int64_t sx = a.size().x, sy = a.size().y;
    return std::string(what) + " first difference at (" + std::to_string(std::int64_t(i) % sx) + ", " +
           std::to_string(std::int64_t(i) / sx % sy) + ", " + std::to_string(std::int64_t(i) / (sx * sy)) + "): " +
           std::to_string(u) + " vs " + std::to_string(v) + " at tick " + std::to_string(a.tick());
  }
  return {};
}

/// "" when both worlds report the same cells, the same side plane (MotionParams::momentum's
/// velocities) and the same face plane (MotionParams::shallow's), else the first differing cell or
/// face value, both values and the tick.
inline std::string first_difference(const World& a, const World& b) {
  const Box whole{{0, 0, 0}, a.size()};
  std::string d = first_byte_difference(a, "cells:", a.read_region(whole), b.read_region(whole));
  const WorldSnapshot sa = a.capture(), sb = b.capture();
  if (d.empty()) d = first_byte_difference(a, "side plane:", sa.side, sb.side);
  if (d.empty() && sa.faces != sb.faces) {
    const std::size_t n = std::max(sa.faces.size(), sb.faces.size());
    for (std::size_t i = 0; i < n && d.empty(); ++i) {
      const std::int32_t u = i < sa.faces.size() ? sa.faces[i] : 0, v = i < sb.faces.size() ? sb.faces[i] : 0;
      if (u != v)
        d = "face plane: first difference at value " + std::to_string(i) + ": " + std::to_string(u) + " vs " +
            std::to_string(v) + " at tick " + std::to_string(a.tick());
    }
  }
  return d;
}

}  // namespace granular::test
