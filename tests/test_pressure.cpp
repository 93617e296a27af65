/// @file test_pressure.cpp
/// The pressure lever (MotionParams::pressure, preset inertial-24-pressure; head_field.hpp and the
/// fluid pass's pressure stage): connected vessels level under it and not without it, a pool at rest
/// sleeps, sparse = dense on any thread count, a world without liquid steps as without the lever,
/// and every material is conserved. (The plain loop and the golden pins cover it cell for cell:
/// test_plain_step.cpp, test_golden.cpp; the GPU: tests/gpu/test_cuda_pressure.cpp.)

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "granular/world.hpp"
#include "quick_u_tube.hpp"
#include "test_support.hpp"

using namespace granular;
using granular::test::test_def;
using granular::test::with_sparse;
using UTube = granular::test::QuickUTube;

TEST_CASE("pressure: the legs of a U-tube level within a cell under the lever, and stay apart without it") {
  const Grid initial = UTube::build();
  World pressed(test_def(UTube::size(), "inertial-24-pressure", 2, 1), initial);
  World plain(test_def(UTube::size(), "inertial-24-flow", 2, 1), initial);
  const MaterialCounts before = pressed.count();
  pressed.step(480);  // the accuracy suite's limit: 20 oscillation periods
  plain.step(480);
  const double left = UTube::level(pressed, 0), right = UTube::level(pressed, UTube::kRight);
  CAPTURE(left);
  CAPTURE(right);
  CHECK(std::abs(left - right) <= 1.0);
  CHECK(right >= 18.0);  // half the head, less a cell or two for the water in transit
  CHECK(pressed.count() == before);
  // Without the lever the right leg never fills: water has no way up.
  CHECK(UTube::level(plain, UTube::kRight) < 2.0);
}

TEST_CASE("pressure: sparse = dense on 1 and 2 threads, and the U-tube comes to rest and sleeps") {
  Grid initial = UTube::build();
  initial.fill(Box{{2, 2, 30}, {6, 6, 34}}, Material::Granular);  // a block of sand dropped into the full leg
  std::vector<std::uint64_t> hashes;
  std::uint64_t awake = 1;
  for (const int threads : {1, 2})
    for (const bool sparse : {false, true}) {
      World w(with_sparse(test_def(UTube::size(), "inertial-24-pressure", threads, 7), sparse), initial);
      w.step(300);
      hashes.push_back(w.hash());
      w.step(1200);
      hashes.push_back(w.hash());
      if (sparse && threads == 2) awake = w.activity().active_bricks;
    }
  for (std::size_t i = 2; i < hashes.size(); ++i) CHECK(hashes[i] == hashes[i % 2]);
  CHECK(awake == 0);  // a level pool with a partly filled top layer costs nothing
}

TEST_CASE("pressure: a world without liquid steps as without the lever") {
  const Int3 size{24, 24, 40};
  Grid initial(size);
  initial.fill(Box{{0, 0, 0}, {size.x, size.y, 1}}, Material::Solid);
  initial.fill(Box{{6, 6, 20}, {18, 18, 32}}, Material::Granular);
  initial.fill(Box{{2, 2, 4}, {6, 6, 8}}, Material::Gravel);
  World pressed(test_def(size, "inertial-24-pressure", 2, 3), initial);
  World plain(test_def(size, "inertial-24-flow", 2, 3), initial);
  pressed.step(96);
  plain.step(96);
  CHECK(pressed.hash() == plain.hash());
}
