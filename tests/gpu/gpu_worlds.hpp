#pragma once
/// @file gpu_worlds.hpp
/// What the GPU tests share to set worlds side by side: a WorldDef per backend, and the first cell
/// where two worlds differ.

#include <doctest/doctest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "granular/rule_presets.hpp"
#include "granular/world.hpp"

namespace granular::test {

/// The presets the CUDA backend steps: every preset but those with MotionParams::momentum, which
/// the CUDA backend refuses (it has no side plane yet: docs/design/momentum.md). Says so, once per
/// call, in the test log.
inline std::vector<std::string> cuda_presets() {
  std::vector<std::string> out;
  for (const std::string& name : rule_preset_names())
    if (preset(name).motion.momentum)
      MESSAGE("preset " << name << " skipped on CUDA: the CUDA backend refuses MotionParams::momentum");
    else
      out.push_back(name);
  return out;
}

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
