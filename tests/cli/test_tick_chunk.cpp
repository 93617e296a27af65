#include <doctest/doctest.h>

#include <climits>
#include <cstdint>

#include "scene_runner.hpp"

using granular::cli::tick_chunk;

namespace {

/// Steps as run_ticks does and returns the number of World::step calls; every chunk must be >= 1.
std::uint64_t calls_for(std::uint64_t total, bool per_tick, std::uint64_t max_calls) {
  std::uint64_t done = 0, calls = 0;
  while (done < total) {
    const int n = tick_chunk(total, done, per_tick);
    REQUIRE(n >= 1);
    REQUIRE(std::uint64_t(n) <= total - done);
    done += std::uint64_t(n);
    REQUIRE(++calls <= max_calls);
  }
  CHECK(tick_chunk(total, done, per_tick) == 0);
  return calls;
}

}  // namespace

TEST_CASE("tick_chunk steps about 1/200 of the run per call, at least one tick") {
  CHECK(calls_for(1000, false, 1000) == 200);
  CHECK(calls_for(7, false, 7) == 7);
  CHECK(calls_for(1, false, 1) == 1);
  CHECK(calls_for(0, false, 0) == 0);
  CHECK(calls_for(123, true, 123) == 123);
}

TEST_CASE("tick_chunk never overflows an int: 858993459200 and 429496729600 ticks advance") {
  // total / 200 = 2^32 and 2^31: cast to int these were 0 (a run that never advanced) and
  // INT_MIN (a negative step count); the chunk is capped at INT_MAX instead.
  CHECK(tick_chunk(858993459200ull, 0, false) == INT_MAX);
  CHECK(tick_chunk(429496729600ull, 0, false) == INT_MAX);
  CHECK(tick_chunk(858993459200ull, 858993459200ull - 5, false) == 5);
  CHECK(calls_for(858993459200ull, false, 500) == 401);
  CHECK(tick_chunk(granular::cli::kMaxTicks, 0, false) == INT_MAX);
}
