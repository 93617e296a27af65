/// @file test_cuda_golden.cpp
/// The CUDA backend against the pinned hashes of golden_table.hpp (the table the CPU is checked
/// against in test_golden.cpp): every preset on every golden scene, sparse and dense.

#include <doctest/doctest.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "granular/rule_presets.hpp"
#include "../golden_table.hpp"
#include "granular/world.hpp"

using namespace granular;
using granular::test::GoldenCase;
using granular::test::golden_def;
using granular::test::kGoldenCases;

namespace {

/// A 64-bit hash as "0x" and 16 hex digits.
std::string hex(std::uint64_t v) {
  char s[24];
  std::snprintf(s, sizeof s, "0x%016llx", static_cast<unsigned long long>(v));
  return s;
}

}  // namespace

TEST_CASE("cuda golden: the CUDA step, sparse and dense, reaches the pinned hash of every preset on every scene") {
  for (const GoldenCase& c : kGoldenCases) {
    const Grid initial = granular::test::golden_initial(c);
    for (const bool sparse : {true, false}) {
      World world(golden_def(c, BackendKind::Cuda, sparse), initial);
      REQUIRE(world.backend() == BackendKind::Cuda);
      world.step(c.ticks);
      const std::uint64_t got = world.hash();
      if (got == c.hash) continue;
      World cpu(golden_def(c, BackendKind::Cpu, false), initial);
      cpu.step(c.ticks);
      const std::uint64_t on_cpu = cpu.hash();
      const std::string failure =
          "preset '" + std::string(c.preset) + "', scene '" + std::string(c.scene) + "' (N = " + std::to_string(c.n) +
          ", " + std::to_string(c.ticks) + " ticks), CUDA " + (sparse ? "sparse" : "dense") + ": got " + hex(got) +
          ", expected " + hex(c.hash) + "; the CPU (dense) gives " + hex(on_cpu) +
          (on_cpu == c.hash ? ", the pinned value: the CUDA step departs from the CPU"
                            : ": the CPU misses the pinned value too (see test_golden.cpp)");
      FAIL_CHECK(failure);
    }
  }
}
