/// @file test_renderer_choice.cpp
/// The automatic renderer choice (--renderer auto): starting from the cheapest renderer (the ray
/// march), it tries the next costlier one (marching, then cubes) while the current one holds 60 FPS
/// and keeps the costliest that held it, or the ray march when even it did not; a renderer's first
/// frame (its rebuild) is not counted, and the user's own choice ends it.

#include <doctest/doctest.h>

#include <optional>
#include <string>

#include "renderer_choice.hpp"

using namespace viewer;

namespace {

/// Feeds frames of `seconds` until the choice switches or ends; the switch, if any.
std::optional<RendererKind> run_until_decided(RendererChoice& choice, double seconds) {
  for (int frame = 0; frame < 10000; ++frame) {
    const bool measuring = choice.measuring();
    if (const auto next = choice.frame(seconds)) return next;
    if (measuring && !choice.measuring()) return std::nullopt;
  }
  FAIL("the choice never decided");
  return std::nullopt;
}

}  // namespace

TEST_CASE("renderer choice: every renderer holds 60 FPS: the costliest, cubes, is kept") {
  RendererChoice choice;
  CHECK(choice.first() == RendererKind::Raymarch);
  CHECK(choice.frame(2.0) == std::nullopt);  // the first frame rebuilds everything: not measured
  CHECK(run_until_decided(choice, 1.0 / 300) == RendererKind::Marching);
  CHECK(choice.report() == "renderer: marching (auto: raymarch 300.0 FPS holds 60, trying the next)");
  CHECK(run_until_decided(choice, 1.0 / 100) == RendererKind::Cubes);
  CHECK(run_until_decided(choice, 1.0 / 70) == std::nullopt);
  CHECK_FALSE(choice.measuring());
  CHECK(choice.report() == "renderer: cubes (auto: cubes 70.0 FPS, holds 60: chosen)");
}

TEST_CASE("renderer choice: a renderer below 60 FPS hands back to the previous one") {
  RendererChoice choice;
  CHECK(run_until_decided(choice, 1.0 / 200) == RendererKind::Marching);
  CHECK(run_until_decided(choice, 1.0 / 25) == RendererKind::Raymarch);
  CHECK_FALSE(choice.measuring());
  CHECK(choice.report() == "renderer: raymarch (auto: marching 25.0 FPS, below 60: the previous one chosen)");
}

TEST_CASE("renderer choice: when even the ray march is below 60 FPS it stays, and nothing costlier is tried") {
  RendererChoice choice;
  CHECK(run_until_decided(choice, 1.0 / 30) == std::nullopt);
  CHECK_FALSE(choice.measuring());
  CHECK(choice.report() == "renderer: raymarch (auto: raymarch 30.0 FPS, below 60, the cheapest: chosen)");
}

TEST_CASE("renderer choice: measures at least half a second and three frames") {
  RendererChoice choice;
  choice.frame(0.1);
  choice.frame(0.001);
  choice.frame(0.001);
  choice.frame(0.001);  // three frames, but 3 ms
  CHECK(choice.measuring());
  RendererChoice slow;
  slow.frame(0.1);
  slow.frame(0.3);
  slow.frame(0.3);  // 0.6 s, but two frames
  CHECK(slow.measuring());
  slow.frame(0.3);
  CHECK_FALSE(slow.measuring());
  CHECK(slow.report() == "renderer: raymarch (auto: raymarch 3.3 FPS, below 60, the cheapest: chosen)");
}

TEST_CASE("renderer choice: the user's choice ends it") {
  RendererChoice choice;
  choice.stop();
  CHECK_FALSE(choice.measuring());
  CHECK(choice.frame(1.0) == std::nullopt);
}
