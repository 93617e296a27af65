#pragma once
/// @file gpu_worlds.hpp
/// What the GPU tests share to set worlds side by side: a WorldDef per backend, and the first cell
/// where two worlds differ.

#include <cstdint>
#include <string>
#include <vector>

#include "granular/world.hpp"

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

/// "" when both worlds report the same region, else the first differing cell, both values and the tick.
inline std::string first_difference(const World& a, const World& b) {
  const Box whole{{0, 0, 0}, a.size()};
  const std::vector<std::uint8_t> x = a.read_region(whole), y = b.read_region(whole);
  for (std::size_t i = 0; i < x.size(); ++i)
    if (x[i] != y[i]) {
      const std::int64_t sx = a.size().x, sy = a.size().y;
      return "first difference at (" + std::to_string(std::int64_t(i) % sx) + ", " +
             std::to_string(std::int64_t(i) / sx % sy) + ", " + std::to_string(std::int64_t(i) / (sx * sy)) + "): " +
             std::to_string(unsigned(x[i])) + " vs " + std::to_string(unsigned(y[i])) + " at tick " +
             std::to_string(a.tick());
    }
  return {};
}

}  // namespace granular::test
