#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>

#include "granular/world.hpp"
#include "session/screenshot_path.hpp"
#include "section/section_pick.hpp"
#include "section/section_plane.hpp"
#include "section/see_inside.hpp"

using namespace viewer;

TEST_CASE("section plane: --section takes AXIS:FRACTION and names the option and value otherwise") {
  const SectionPlane y = parse_section("y:0.5");
  CHECK(y.axis == 1);
  CHECK(y.fraction == 0.5);
  CHECK(parse_section("x:0").axis == 0);
  CHECK(parse_section("Z:1").axis == 2);
  CHECK(parse_section("z:0.25").fraction == 0.25);
  for (const char* bad : {"", "y", "y:", "w:0.5", "y0.5", "y:1.5", "y:-0.1", "y:half", "y:0.5x", "y:nan", "xy:0.5"}) {
    CAPTURE(bad);
    try {
      parse_section(bad);
      FAIL("accepted");
    } catch (const std::invalid_argument& e) {
      CHECK(std::string(e.what()).find("--section '" + std::string(bad) + "'") == 0);
    }
  }
}

TEST_CASE("section plane: V cycles off, x, y, z; comma and period step 1/32 within 0..1; the line it prints") {
  SectionPlane plane;
  CHECK(!plane.on());
  CHECK(plane.describe() == "off");
  plane = plane.cycled();
  CHECK(plane.describe() == "x 0.50");
  plane = plane.cycled();
  CHECK(plane.describe() == "y 0.50");
  plane = plane.moved(-1);
  CHECK(plane.fraction == doctest::Approx(0.5 - 1.0 / 32));
  CHECK(plane.describe() == "y 0.47");
  plane = plane.moved(+2);
  CHECK(plane.describe() == "y 0.53");
  CHECK(plane.moved(100).fraction == 1.0);
  CHECK(plane.moved(-100).fraction == 0.0);
  plane = plane.cycled();
  CHECK(plane.describe() == "z 0.53");
  plane = plane.cycled();
  CHECK(!plane.on());
  CHECK(plane.moved(3).fraction == plane.fraction);  // the plane stays put while off
  CHECK(plane.cycled().describe() == "x 0.53");
}

TEST_CASE("section plane: it removes the half between the eye and the plane") {
  const SectionPlane plane = parse_section("y:0.5");
  const granular::Int3 size{32, 40, 64};
  CHECK(!SectionPlane{}.cut(size, {0, 0, 0}));
  const SectionCut from_high = *plane.cut(size, {10.0f, 100.0f, 10.0f});
  CHECK(from_high.axis == 1);
  CHECK(from_high.plane == 20);
  CHECK(!from_high.keeps_high);
  CHECK(!from_high.removes({0, 19, 0}));
  CHECK(from_high.removes({0, 20, 0}));
  const SectionCut from_low = *plane.cut(size, {10.0f, -5.0f, 10.0f});
  CHECK(from_low.keeps_high);
  CHECK(from_low.removes({0, 19, 0}));
  CHECK(!from_low.removes({0, 20, 0}));
  CHECK(parse_section("z:0.26").cut(size, {0, 0, 100})->plane == 17);  // the nearest cell boundary
}

TEST_CASE("section plane: the push-constant word holds the axis, the kept side, x-ray, the pass and the plane") {
  SeeInside inside;
  const granular::Int3 size{32, 40, 64};
  CHECK(see_inside_word(inside, size, {0, 0, 0}) == 0);
  inside.xray = true;
  CHECK(see_inside_word(inside, size, {0, 0, 0}) == 8);
  inside.section = parse_section("z:0.5");
  const std::int32_t word = see_inside_word(inside, size, {0, 0, -1});  // below: keeps the upper half
  CHECK(word == (3 | 4 | 8 | (32 << 8)));
  CHECK(for_draw(word, DrawPass::Xray) == (word | (2 << 4)));
  CHECK(for_draw(for_draw(word, DrawPass::Xray), DrawPass::Translucent, true) == (word | (1 << 4) | 64));
}

TEST_CASE("section plane: the cursor picks the first kept cell, entered through the plane at the cut") {
  granular::WorldDef def;
  def.backend = granular::BackendKind::Cpu;
  def.size = {16, 16, 16};
  granular::World world(def);
  world.paint(granular::Box{{4, 4, 4}, {12, 12, 12}}, granular::Material::Solid);
  const glm::vec3 eye{8.5f, 40.0f, 8.5f}, down_y{0.0f, -1.0f, 0.0f};
  const auto outside = pick_kept_cell(world, std::nullopt, eye, down_y);
  REQUIRE(outside);
  CHECK(outside->cell == granular::Int3{8, 11, 8});
  const auto cut = parse_section("y:0.5").cut(world.size(), eye);
  const auto at_cut = pick_kept_cell(world, cut, eye, down_y);
  REQUIRE(at_cut);
  CHECK(at_cut->cell == granular::Int3{8, 7, 8});
  CHECK(at_cut->normal == granular::Int3{0, 1, 0});
  CHECK(at_cut->in_front() == granular::Int3{8, 8, 8});
  CHECK(at_cut->distance == doctest::Approx(32.0).epsilon(1e-4));
  CHECK(!pick_kept_cell(world, cut, eye, -down_y));  // looking away from the kept half
  world.paint(granular::Box{{4, 4, 4}, {12, 8, 12}}, granular::Material::Void);  // the kept half of the box
  CHECK(!pick_kept_cell(world, cut, eye, down_y));  // the removed half is not picked through the cut
}

TEST_CASE("screenshot key: granular-screenshot-N.png with the first free N, never an existing file") {
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / "granular-screenshot-path-test";
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  CHECK(next_screenshot_path(folder) == folder / "granular-screenshot-1.png");
  std::ofstream(folder / "granular-screenshot-1.png") << "x";
  std::ofstream(folder / "granular-screenshot-3.png") << "x";
  CHECK(next_screenshot_path(folder) == folder / "granular-screenshot-2.png");
  std::ofstream(folder / "granular-screenshot-2.png") << "x";
  CHECK(next_screenshot_path(folder) == folder / "granular-screenshot-4.png");
  std::filesystem::remove_all(folder);
}
