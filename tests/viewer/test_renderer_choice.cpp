/// @file test_renderer_choice.cpp
/// The automatic renderer choice (--renderer auto): it keeps the first renderer, in the order cubes,
/// marching, raymarch, that holds 60 FPS, and otherwise the fastest it measured; a renderer's first
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

TEST_CASE("renderer choice: keeps the first renderer that holds 60 FPS") {
  RendererChoice choice;
  CHECK(choice.first() == RendererKind::Cubes);
  CHECK(choice.frame(2.0) == std::nullopt);  // the first frame rebuilds everything: not measured
  CHECK(run_until_decided(choice, 1.0 / 70) == std::nullopt);
  CHECK_FALSE(choice.measuring());
  CHECK(choice.report().find("cubes 70.0 FPS, holds 60") != std::string::npos);
}

TEST_CASE("renderer choice: a renderer below 60 FPS hands over to the next") {
  RendererChoice choice;
  CHECK(run_until_decided(choice, 1.0 / 20) == RendererKind::Marching);
  CHECK(choice.report() == "renderer: marching (auto: cubes 20.0 FPS, below 60)");
  CHECK(run_until_decided(choice, 1.0 / 90) == std::nullopt);
  CHECK_FALSE(choice.measuring());
}

TEST_CASE("renderer choice: when none holds 60 FPS it keeps the fastest measured") {
  RendererChoice choice;
  CHECK(run_until_decided(choice, 1.0 / 10) == RendererKind::Marching);
  CHECK(run_until_decided(choice, 1.0 / 40) == RendererKind::Raymarch);
  CHECK(run_until_decided(choice, 1.0 / 30) == RendererKind::Marching);
  CHECK(choice.report().find("none held 60") != std::string::npos);
  CHECK_FALSE(choice.measuring());
}

TEST_CASE("renderer choice: measures at least half a second and three frames") {
  RendererChoice choice;
  choice.frame(0.1);
  CHECK(choice.frame(0.4) == std::nullopt);
  CHECK(choice.frame(0.4) == std::nullopt);  // 0.8 s, but two frames
  CHECK(choice.measuring());
  CHECK(choice.frame(0.4) == RendererKind::Marching);
}

TEST_CASE("renderer choice: the user's choice ends it") {
  RendererChoice choice;
  choice.stop();
  CHECK_FALSE(choice.measuring());
  CHECK(choice.frame(1.0) == std::nullopt);
}
