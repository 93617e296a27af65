/// @file test_renderer_choice.cpp
/// The automatic renderer choice (--renderer auto): it measures the ray march, marching cubes and
/// cubes in turn and keeps the costliest that held 60 FPS, else the fastest measured; a renderer's
/// first frame (its rebuild) is not counted, and the user's own choice ends it.

#include <doctest/doctest.h>

#include <optional>
#include <string>
#include <vector>

#include "renderers/renderer_choice.hpp"
#include "vulkan/vulkan_check.hpp"

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
  CHECK(choice.report() == "renderer: marching (auto: raymarch 300.0 FPS, measuring the next)");
  CHECK(run_until_decided(choice, 1.0 / 100) == RendererKind::Cubes);
  CHECK(run_until_decided(choice, 1.0 / 70) == std::nullopt);
  CHECK_FALSE(choice.measuring());
  CHECK(choice.report() ==
        "renderer: cubes (auto: raymarch 300.0, marching 100.0, cubes 70.0 FPS; the costliest holding 60: chosen)");
}

TEST_CASE("renderer choice: the costliest that held 60 FPS wins over costlier ones that did not") {
  RendererChoice choice;
  CHECK(run_until_decided(choice, 1.0 / 200) == RendererKind::Marching);
  CHECK(run_until_decided(choice, 1.0 / 90) == RendererKind::Cubes);
  CHECK(run_until_decided(choice, 1.0 / 25) == RendererKind::Marching);
  CHECK_FALSE(choice.measuring());
}

TEST_CASE("renderer choice: when none holds 60 FPS the fastest measured is kept (cubes on a CPU rasteriser)") {
  RendererChoice choice;
  CHECK(run_until_decided(choice, 1.0 / 5) == RendererKind::Marching);
  CHECK(run_until_decided(choice, 1.0 / 4) == RendererKind::Cubes);
  CHECK(run_until_decided(choice, 1.0 / 12) == std::nullopt);
  CHECK(choice.report() == "renderer: cubes (auto: raymarch 5.0, marching 4.0, cubes 12.0 FPS; none held 60, the fastest: chosen)");
  RendererChoice other;
  CHECK(run_until_decided(other, 1.0 / 30) == RendererKind::Marching);
  CHECK(run_until_decided(other, 1.0 / 4) == RendererKind::Cubes);
  CHECK(run_until_decided(other, 1.0 / 3) == RendererKind::Raymarch);
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
  CHECK(slow.frame(0.3) == std::nullopt);
  CHECK(slow.frame(0.3) == std::nullopt);  // 0.6 s, but two frames
  CHECK(slow.frame(0.3) == RendererKind::Marching);
}

TEST_CASE("renderer choice: the user's choice ends it") {
  RendererChoice choice;
  choice.stop();
  CHECK_FALSE(choice.measuring());
  CHECK(choice.frame(1.0) == std::nullopt);
}

TEST_CASE("renderer choice: a renderer that cannot be made here counts as 0 FPS and the next is tried") {
  RendererChoice choice;
  std::vector<std::string> lines;
  const auto print = [&](const std::string& line) { lines.push_back(line); };
  std::vector<RendererKind> made;
  const auto switch_to = [&](RendererKind kind) {
    if (kind == RendererKind::Marching) throw VulkanError("the grid is too large for the marching-cubes renderer");
    made.push_back(kind);
  };
  std::optional<RendererKind> now;
  for (int frame = 0; frame < 100 && !now; ++frame) now = choice.advance(1.0 / 100, switch_to, print);
  CHECK(now == RendererKind::Cubes);  // marching failed to build: skipped
  REQUIRE(lines.size() == 2);
  CHECK(lines[1] == "renderer: cubes (auto: marching unavailable here: the grid is too large for the marching-cubes "
                    "renderer, measuring the next)");
  now.reset();
  for (int frame = 0; frame < 100 && !now && choice.measuring(); ++frame) now = choice.advance(1.0 / 20, switch_to, print);
  CHECK_FALSE(choice.measuring());
  CHECK(now == RendererKind::Raymarch);  // cubes measured 20 FPS, marching 0: the ray march's 100 wins
  CHECK(made == std::vector<RendererKind>{RendererKind::Cubes, RendererKind::Raymarch});
}
