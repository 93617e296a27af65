#include <doctest/doctest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "granular/errors.hpp"
#include "granular/scene.hpp"
#include "granular/world.hpp"
#include "test_support.hpp"

using namespace granular;

namespace {

#if defined(GRANULAR_TEST_ASSET_DIR)
const std::filesystem::path kAssetDir = GRANULAR_TEST_ASSET_DIR;
#else
const std::filesystem::path kAssetDir = GRANULAR_SOURCE_ASSET_DIR;
#endif

constexpr double kPi = 3.14159265358979323846;

/// Sets (or unsets, for nullptr) an environment variable for one scope, restoring it afterwards.
class EnvVar {
 public:
  EnvVar(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value) ::setenv(name, value, 1);
    else ::unsetenv(name);
  }
  ~EnvVar() {
    if (old_) ::setenv(name_, old_->c_str(), 1);
    else ::unsetenv(name_);
  }
  EnvVar(const EnvVar&) = delete;
  EnvVar& operator=(const EnvVar&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

/// Points the scene lookup at the source tree's assets for one scope.
struct ShippedAssets {
  EnvVar env{"GRANULAR_ASSET_DIR", kAssetDir.c_str()};
};

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::uint64_t count_of(const Grid& g, Material m) { return g.count()[to_cell(m)]; }

/// `text` with its single occurrence of `from` replaced by `to`.
std::string with(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE_MESSAGE(at != std::string::npos, "test bug: '" << from << "' not in the base scene");
  REQUIRE_MESSAGE(text.find(from, at + 1) == std::string::npos, "test bug: '" << from << "' is not unique");
  return text.replace(at, from.size(), to);
}

/// A valid scene using every shape type and an emitter; the malformed cases edit one piece of it.
const std::string kBase = R"({
  "name": "base",
  "description": "test scene",
  "size": [1, 1, 1],
  "default_n": 20,
  "min_n": 10,
  "shapes": [
    {"type": "box", "material": "solid", "min": [0, 0, 0], "max": [1, 1, 0.1]},
    {"type": "sphere", "material": "granular", "center": [0.5, 0.5, 0.5], "radius": 0.2},
    {"type": "cylinder", "material": "solid", "center": [0.25, 0.25], "radius": 0.1, "z0": 0.1, "z1": 0.3},
    {"type": "cone", "material": "void", "center": [0.75, 0.75], "z0": 0.15, "z1": 0.35, "r0": 0.05, "r1": 0.01},
    {"type": "bowl", "material": "solid", "center": [0.5, 0.5, 0.85], "radius": 0.12, "thickness": 0.06}
  ],
  "emitters": [
    {"center": [0.5, 0.5, 0.9], "radius": 0.05, "material": "sand", "rate": 3, "start": 2, "stop": 10}
  ]
})";

constexpr const char* kBadFile = "bad_scene_file.json";

/// Asserts that parsing `text` throws ParseError naming the file, `path` and `value`.
void expect_parse_error(const std::string& text, const std::string& path, const std::string& value) {
  CAPTURE(path);
  CAPTURE(value);
  bool thrown = false;
  try {
    parse_scene(text, kBadFile);
  } catch (const ParseError& e) {
    thrown = true;
    const std::string message = e.what();
    CAPTURE(message);
    CHECK(contains(message, kBadFile));
    CHECK(contains(message, path));
    CHECK(contains(message, value));
  }
  CHECK_MESSAGE(thrown, "no ParseError for " << path);
}

/// Asserts that instantiating `scene` at `n` throws InvalidArgument naming the file and `part`.
void expect_invalid(const Scene& scene, int n, const std::string& part) {
  CAPTURE(part);
  bool thrown = false;
  try {
    (void)instantiate(scene, n);
  } catch (const InvalidArgument& e) {
    thrown = true;
    const std::string message = e.what();
    CAPTURE(message);
    CHECK(contains(message, scene.source));
    CHECK(contains(message, part));
  }
  CHECK_MESSAGE(thrown, "no InvalidArgument for " << part);
}

Scene shipped(const char* name) { return load_scene(kAssetDir / "scenes" / (std::string(name) + ".json")); }

/// True when no grain can leave the cavity of the bowl drawn in `g` except over its rim: a
/// 26-connected flood (the reach of one Margolus block move) through void cells, from the cell
/// above the bowl's lowest solid cell and restricted to layers at or below `rim_layer`, never
/// meets a void cell outside the bowl's outer sphere. Returns false too when no cavity is found.
bool bowl_holds(const Grid& g, double cx, double cy, double cz, double outer_radius, int rim_layer) {
  const Int3 size = g.size();
  const int x = int(std::floor(cx)), y = int(std::floor(cy));
  int z = 0;
  while (z < size.z && g.at({x, y, z}) != Material::Solid) ++z;
  while (z < size.z && g.at({x, y, z}) == Material::Solid) ++z;
  if (z >= size.z || z > rim_layer) return false;
  std::vector<char> seen(std::size_t(g.cell_count()), 0);
  std::vector<Int3> stack{{x, y, z}};
  seen[g.index({x, y, z})] = 1;
  while (!stack.empty()) {
    const Int3 p = stack.back();
    stack.pop_back();
    const double dx = p.x + 0.5 - cx, dy = p.y + 0.5 - cy, dz = p.z + 0.5 - cz;
    if (dx * dx + dy * dy + dz * dz > outer_radius * outer_radius) return false;
    for (int a = -1; a <= 1; ++a)
      for (int b = -1; b <= 1; ++b)
        for (int c = -1; c <= 1; ++c) {
          const Int3 q{p.x + a, p.y + b, p.z + c};
          if (!g.contains(q) || q.z > rim_layer || seen[g.index(q)] || g.at(q) != Material::Void) continue;
          seen[g.index(q)] = 1;
          stack.push_back(q);
        }
  }
  return true;
}

/// Cells reachable from `from` through non-solid cells (26-connected).
std::vector<char> reachable(const Grid& g, Int3 from) {
  std::vector<char> seen(std::size_t(g.cell_count()), 0);
  std::vector<Int3> stack{from};
  seen[g.index(from)] = 1;
  while (!stack.empty()) {
    const Int3 p = stack.back();
    stack.pop_back();
    for (int a = -1; a <= 1; ++a)
      for (int b = -1; b <= 1; ++b)
        for (int c = -1; c <= 1; ++c) {
          const Int3 q{p.x + a, p.y + b, p.z + c};
          if (!g.contains(q) || seen[g.index(q)] || g.at(q) == Material::Solid) continue;
          seen[g.index(q)] = 1;
          stack.push_back(q);
        }
  }
  return seen;
}

/// Highest layer holding `m` in the column (x, y); -1 when none.
int top_of(const Grid& g, int x, int y, Material m) {
  for (int z = g.size().z - 1; z >= 0; --z)
    if (g.at({x, y, z}) == m) return z;
  return -1;
}

/// Lowest layer holding `m` in the column (x, y); -1 when none.
int bottom_of(const Grid& g, int x, int y, Material m) {
  for (int z = 0; z < g.size().z; ++z)
    if (g.at({x, y, z}) == m) return z;
  return -1;
}

}  // namespace

TEST_CASE("scene: the bowl at N=35 has the paper's 863 solid cells and a 35x35x17 block of sand") {
  const Scene scene = shipped("bowl");
  CHECK(scene.name == "bowl");
  CHECK(scene.default_n == 35);
  const SceneInstance bowl = instantiate(scene);
  CHECK(bowl.n == 35);
  REQUIRE(bowl.grid.size() == Int3{35, 35, 35});
  CHECK(count_of(bowl.grid, Material::Solid) == 863);
  CHECK(count_of(bowl.grid, Material::Granular) == 35u * 35u * 17u);
  CHECK(count_of(bowl.grid, Material::Void) == 35u * 35u * 35u - 863u - 35u * 35u * 17u);
  CHECK(bowl.emitters.empty());
  // The sand is exactly the top 17 layers; the bowl floats in the lower half with space below it.
  for (int z = 0; z < 35; ++z) {
    std::uint64_t sand = 0, solid = 0;
    for (int y = 0; y < 35; ++y)
      for (int x = 0; x < 35; ++x) {
        sand += bowl.grid.at({x, y, z}) == Material::Granular;
        solid += bowl.grid.at({x, y, z}) == Material::Solid;
      }
    CAPTURE(z);
    CHECK(sand == (z >= 18 ? 35u * 35u : 0u));
    if (z < 5 || z >= 17) CHECK(solid == 0);
  }
  CHECK(bowl.grid.at({17, 17, 8}) == Material::Solid);  // the bowl's floor under its centre
  CHECK(bowl.grid.at({17, 17, 12}) == Material::Void);  // its cavity
  CHECK(bowl.grid.at({17, 17, 3}) == Material::Void);   // room under it
}

TEST_CASE("scene: the bowl is watertight below its rim and never overlaps the sand, at every N from min_n") {
  const Scene scene = shipped("bowl");
  std::vector<int> sizes;
  for (int n = scene.min_n; n <= 72; ++n) sizes.push_back(n);
  for (int n : {96, 128, 256}) sizes.push_back(n);
  for (int n : sizes) {
    CAPTURE(n);
    const SceneInstance s = instantiate(scene, n);
    const std::uint64_t nn = std::uint64_t(n) * std::uint64_t(n);
    CHECK(count_of(s.grid, Material::Granular) == nn * std::uint64_t(n / 2));
    const double cz = 0.45 * n;
    const int rim_layer = int(std::floor(cz - 0.5));
    CHECK(bowl_holds(s.grid, 0.5 * n, 0.5 * n, cz, 0.24 * n + 0.1, rim_layer));
    CHECK(top_of(s.grid, n / 2, n / 2 - int(0.2 * n), Material::Solid) < n - n / 2);
    CHECK(bottom_of(s.grid, n / 2, n / 2, Material::Solid) >= int(0.2 * n));
  }
  // A bowl too thin for the grid leaks: the check above can fail.
  const Scene thin = parse_scene(with(R"({"name": "thin", "description": "d", "size": [1, 1, 1], "default_n": 40,
      "min_n": 1, "shapes": [{"type": "bowl", "material": "solid", "center": [0.5, 0.5, 0.45], "radius": 0.24,
      "thickness": T}]})", "T", "0.02"), "thin.json");
  const SceneInstance leaky = instantiate(thin, 40);
  CHECK_FALSE(bowl_holds(leaky.grid, 20, 20, 18, 0.24 * 40 + 0.1, 17));
}

TEST_CASE("scene: every shipped scene instantiates at its default N and at N=96 with the expected content") {
  const ShippedAssets assets;
  const std::vector<std::string> names = list_scenes();
  for (const char* expected : {"bowl", "column", "hourglass", "pile", "silo", "dam_break", "u_tube", "reservoir",
                               "sand_into_water", "bubbles", "gravel_and_sand"})
    CHECK(std::find(names.begin(), names.end(), expected) != names.end());
  for (const std::string& name : names) {
    const Scene scene = load_scene(find_scene(name));
    CAPTURE(name);
    CHECK(scene.name == name);
    CHECK(scene.description.size() > 40);
    CHECK(scene.min_n <= scene.default_n);
    for (int n : {0, 96, scene.min_n}) {
      CAPTURE(n);
      const SceneInstance s = instantiate(scene, n);
      CHECK(s.n == (n == 0 ? scene.default_n : n));
      CHECK(count_of(s.grid, Material::Solid) > 0);
      CHECK(count_of(s.grid, Material::Void) > 0);
      // Something that moves: grains, liquid or gas in the grid, or an emitter that pours them.
      const std::uint64_t moving = count_of(s.grid, Material::Granular) + count_of(s.grid, Material::Liquid) +
                                   count_of(s.grid, Material::Gas) + count_of(s.grid, Material::Gravel);
      CHECK((moving > 0 || !s.emitters.empty()));
      for (const Emitter& e : s.emitters) {
        CHECK(e.rate >= 1);
        CHECK(e.radius > 0);
        CHECK(e.stop > e.start);
      }
    }
  }
}

TEST_CASE("scene: the pile scene has a floor and a point source that scales with N") {
  const Scene scene = shipped("pile");
  for (int n : {scene.min_n, 64, 96}) {
    CAPTURE(n);
    const SceneInstance s = instantiate(scene, n);
    const Int3 size = s.grid.size();
    CHECK(count_of(s.grid, Material::Granular) == 0);
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x) REQUIRE(s.grid.at({x, y, 0}) == Material::Solid);
    REQUIRE(s.emitters.size() == 1);
    const Emitter& e = s.emitters[0];
    CHECK(e.material == Material::Granular);
    CHECK(e.center.x == doctest::Approx(n / 2.0));
    CHECK(e.center.y == doctest::Approx(n / 2.0));
    CHECK(e.center.z > top_of(s.grid, n / 2, n / 2, Material::Solid) + 0.5 * n);
    CHECK(e.center.z < size.z);
    CHECK(e.rate == std::llround(0.0025 * n * n));
    CHECK(e.start == 0);
    CHECK(e.stop == std::uint64_t(16 * n));
    // The sphere holds at least one cell centre, so the emitter can pour.
    int inside = 0;
    for (int z = 0; z < size.z; ++z)
      for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x) {
          const double dx = x + 0.5 - e.center.x, dy = y + 0.5 - e.center.y, dz = z + 0.5 - e.center.z;
          inside += dx * dx + dy * dy + dz * dz <= e.radius * e.radius;
        }
    CHECK(inside >= 1);
  }
}

TEST_CASE("scene: the hourglass drains through an open neck into a closed body") {
  const Scene scene = shipped("hourglass");
  for (int n : {scene.min_n, 35, 64, 96}) {
    CAPTURE(n);
    const SceneInstance s = instantiate(scene, n);
    const Int3 size = s.grid.size();
    const int cx = size.x / 2, cy = size.y / 2;
    const int sand_top = top_of(s.grid, cx, cy, Material::Granular);
    const int sand_bottom = bottom_of(s.grid, cx, cy, Material::Granular);
    REQUIRE(sand_top > size.z / 2);
    CHECK(sand_bottom >= size.z / 2 - 1);
    // The lower chamber starts empty and is reachable from the sand through the neck.
    const int lower = size.z / 4;
    REQUIRE(s.grid.at({cx, cy, lower}) == Material::Void);
    const std::vector<char> reach = reachable(s.grid, {cx, cy, sand_top});
    CHECK(reach[s.grid.index({cx, cy, lower})]);
    // The neck is narrow: open, but under a third of the chambers' width.
    auto open_width = [&](int z) {
      int w = 0;
      for (int x = 0; x < size.x; ++x) w += s.grid.at({x, cy, z}) != Material::Solid && x > 0 && x < size.x - 1;
      return w;
    };
    const int neck = open_width(size.z / 2);
    int chamber = 0;
    for (int z = 0; z < size.z; ++z) chamber = std::max(chamber, open_width(z));
    CHECK(neck >= 1);
    CHECK(3 * neck < chamber);
    // The body is closed: the grid's corners (outside it) are not reachable from inside.
    CHECK_FALSE(reach[s.grid.index({0, 0, size.z / 2})]);
    CHECK_FALSE(reach[s.grid.index({0, 0, 0})]);
    CHECK_FALSE(reach[s.grid.index({size.x - 1, size.y - 1, size.z - 1})]);
  }
}

TEST_CASE("scene: the column stands on the floor, about twice as high as its radius") {
  const Scene scene = shipped("column");
  for (int n : {scene.min_n, 64, 96}) {
    CAPTURE(n);
    const SceneInstance s = instantiate(scene, n);
    const Int3 size = s.grid.size();
    const int cx = size.x / 2, cy = size.y / 2;
    const int floor_top = top_of(s.grid, cx, cy, Material::Solid);
    CHECK(bottom_of(s.grid, cx, cy, Material::Granular) == floor_top + 1);
    const int height = top_of(s.grid, cx, cy, Material::Granular) - floor_top;
    const double radius = 0.1 * n;
    CHECK(height == doctest::Approx(2 * radius).epsilon(0.2));
    if (n < 64) continue;  // too few cells across for the volume formula
    const double volume = double(count_of(s.grid, Material::Granular));
    CHECK(volume == doctest::Approx(kPi * radius * radius * height).epsilon(0.1));
  }
}

namespace {

/// The cell boundary at which a scene puts a flat face at fraction `f` of N (the rounding rule: the
/// nearest sixteenth of a cell, halves away from zero, then the nearest boundary, halves up).
int face_at(double f, int n) { return int(std::floor(std::round(16.0 * f * n) / 16.0 + 0.5)); }

/// True when the region `inside` holds what it holds of material `from` at layers lo <= z < hi: no
/// cell reachable from those cells through non-solid cells (26-connected, the reach of one Margolus
/// block move) without leaving those layers lies outside the region. False too when the region holds
/// none of `from` there.
template <class Inside>
bool contained(const Grid& g, Material from, int lo, int hi, Inside inside) {
  const Int3 size = g.size();
  std::vector<char> seen(std::size_t(g.cell_count()), 0);
  std::vector<Int3> stack;
  for (int z = std::max(lo, 0); z < std::min(hi, size.z); ++z)
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x)
        if (g.at({x, y, z}) == from && inside(Int3{x, y, z})) {
          seen[g.index({x, y, z})] = 1;
          stack.push_back({x, y, z});
        }
  if (stack.empty()) return false;
  while (!stack.empty()) {
    const Int3 p = stack.back();
    stack.pop_back();
    if (!inside(p)) return false;
    for (int a = -1; a <= 1; ++a)
      for (int b = -1; b <= 1; ++b)
        for (int c = -1; c <= 1; ++c) {
          const Int3 q{p.x + a, p.y + b, p.z + c};
          if (!g.contains(q) || q.z < lo || q.z >= hi || seen[g.index(q)] || g.at(q) == Material::Solid) continue;
          seen[g.index(q)] = 1;
          stack.push_back(q);
        }
  }
  return true;
}

/// True when the cell centre of `p` lies within `radius` of the vertical axis through (cx, cy).
bool near_axis(Int3 p, double cx, double cy, double radius) {
  const double dx = p.x + 0.5 - cx, dy = p.y + 0.5 - cy;
  return dx * dx + dy * dy <= radius * radius;
}

}  // namespace

TEST_CASE("scene: dam_break: a column of water 0.25 N long and 0.5 N high stands on the floor at one end") {
  const Scene scene = shipped("dam_break");
  for (int n : {scene.min_n, 33, 64, 96}) {
    CAPTURE(n);
    const SceneInstance s = instantiate(scene, n);
    const Int3 size = s.grid.size();
    const int floor = face_at(0.04, n), top = face_at(0.54, n);
    CHECK(top - floor == doctest::Approx(0.5 * n).epsilon(0.05));
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x) {
        // Every column: the floor, then water up to 0.54 N (x < 0.25 N), or void.
        REQUIRE(top_of(s.grid, x, y, Material::Solid) == floor - 1);
        const bool wet = x < face_at(0.25, n);
        CHECK(bottom_of(s.grid, x, y, Material::Liquid) == (wet ? floor : -1));
        CHECK(top_of(s.grid, x, y, Material::Liquid) == (wet ? top - 1 : -1));
      }
    CHECK(count_of(s.grid, Material::Liquid) == std::uint64_t(face_at(0.25, n)) * std::uint64_t(size.y) *
                                                   std::uint64_t(top - floor));
    CHECK(s.emitters.empty());
  }
}

TEST_CASE("scene: u_tube: the legs are joined only through the passage under the wall") {
  const Scene scene = shipped("u_tube");
  for (int n : {scene.min_n, 33, 64, 96}) {
    CAPTURE(n);
    const SceneInstance s = instantiate(scene, n);
    const Int3 size = s.grid.size();
    const int y = size.y / 2, left = 0, right = size.x - 1;
    const int left_top = top_of(s.grid, left, y, Material::Liquid), right_top = top_of(s.grid, right, y, Material::Liquid);
    CHECK(left_top + 1 == face_at(0.9, n));
    CHECK(right_top + 1 == face_at(0.3, n));
    // Under the middle of the wall: the floor, the passage full of water, then the wall to the top.
    const int wall_x = size.x / 2;
    int z = 0;
    while (s.grid.at({wall_x, y, z}) == Material::Solid) ++z;
    const int passage = z;
    while (s.grid.at({wall_x, y, z}) == Material::Liquid) ++z;
    const int wall = z;
    CHECK(wall - passage >= 2);  // open
    for (; z < size.z; ++z) CHECK(s.grid.at({wall_x, y, z}) == Material::Solid);
    // The legs are joined through the passage, and only through it.
    CHECK(reachable(s.grid, {left, y, left_top})[s.grid.index({right, y, size.z - 1})]);
    Grid blocked = s.grid;
    for (int zz = 0; zz < wall; ++zz)
      for (int yy = 0; yy < size.y; ++yy)
        for (int x = 0; x < size.x; ++x) blocked.set({x, yy, zz}, Material::Solid);
    CHECK_FALSE(reachable(blocked, {left, y, left_top})[blocked.index({right, y, right_top})]);
  }
}

TEST_CASE("scene: reservoir: the tower is joined to the reservoir only through the closed pipe under the wall") {
  const Scene scene = shipped("reservoir");
  for (int n : {scene.min_n, 25, 26, 33, 64, 96}) {
    CAPTURE(n);
    const SceneInstance s = instantiate(scene, n);
    const Int3 size = s.grid.size();
    const int y = size.y / 2;
    const int pipe_floor = face_at(0.1, n), pipe_roof = face_at(0.25, n);
    const int wall_x0 = face_at(0.5, n), tower_x0 = face_at(0.8, n), tower_x1 = face_at(0.9, n);
    // The reservoir: water from its floor at 0.4 N up to 0.85 N, air above it.
    CHECK(bottom_of(s.grid, 0, y, Material::Liquid) == face_at(0.4, n));
    CHECK(top_of(s.grid, 0, y, Material::Liquid) + 1 == face_at(0.85, n));
    CHECK(top_of(s.grid, 0, y, Material::Solid) + 1 == face_at(0.4, n));
    // The tower, at least 2 cells wide: the pipe's last stretch full of water, empty above it to the
    // open top, solid below the pipe.
    CHECK(tower_x1 - tower_x0 >= 2);
    for (int x = tower_x0; x < tower_x1; ++x) {
      CHECK(top_of(s.grid, x, y, Material::Solid) + 1 == pipe_floor);
      CHECK(bottom_of(s.grid, x, y, Material::Liquid) == pipe_floor);
      CHECK(top_of(s.grid, x, y, Material::Liquid) + 1 == pipe_roof);
      CHECK(bottom_of(s.grid, x, y, Material::Void) == pipe_roof);
      CHECK(top_of(s.grid, x, y, Material::Void) == size.z - 1);
    }
    // Under the middle of the wall: solid, the pipe full of water and at least 3 cells high, then the
    // wall to the top of the grid: the pipe is closed above and below.
    const int wall_x = (wall_x0 + tower_x0) / 2;
    int z = 0;
    while (s.grid.at({wall_x, y, z}) == Material::Solid) ++z;
    CHECK(z == pipe_floor);
    while (s.grid.at({wall_x, y, z}) == Material::Liquid) ++z;
    CHECK(z == pipe_roof);
    CHECK(pipe_roof - pipe_floor >= 3);
    for (; z < size.z; ++z) CHECK(s.grid.at({wall_x, y, z}) == Material::Solid);
    // The reservoir reaches the tower's open top through the pipe, and only through its run under
    // the wall.
    const Int3 reservoir_surface{0, y, face_at(0.85, n) - 1}, tower_top{tower_x0, y, size.z - 1};
    CHECK(reachable(s.grid, reservoir_surface)[s.grid.index(tower_top)]);
    Grid blocked = s.grid;
    for (int zz = pipe_floor; zz < pipe_roof; ++zz)
      for (int yy = 0; yy < size.y; ++yy)
        for (int x = wall_x0; x < tower_x0; ++x) blocked.set({x, yy, zz}, Material::Solid);
    CHECK_FALSE(reachable(blocked, reservoir_surface)[blocked.index(tower_top)]);
  }
}

TEST_CASE("scene: sand_into_water: a closed tank holds the water below its rim, under an emitter of sand") {
  const Scene scene = shipped("sand_into_water");
  for (int n : {scene.min_n, 25, 33, 64, 96}) {
    CAPTURE(n);
    const SceneInstance s = instantiate(scene, n);
    const int rim = face_at(0.6, n), c = s.grid.size().x / 2;
    CHECK(bottom_of(s.grid, c, c, Material::Liquid) == face_at(0.04, n));
    CHECK(top_of(s.grid, c, c, Material::Liquid) + 1 == face_at(0.4, n));
    // No drop leaves the tank below its rim, whatever way it moves (outer radius 0.42 N).
    CHECK(contained(s.grid, Material::Liquid, 0, rim, [&](Int3 p) { return near_axis(p, 0.5 * n, 0.5 * n, 0.42 * n); }));
    REQUIRE(s.emitters.size() == 1);
    CHECK(s.emitters[0].material == Material::Granular);
    CHECK(s.emitters[0].center.z > rim);
  }
  // A wall a fraction of a cell thick leaks: the check above can fail.
  Scene thin = scene;
  REQUIRE(std::holds_alternative<CylinderShape>(thin.shapes.at(1).geometry));
  std::get<CylinderShape>(thin.shapes[1].geometry).radius = 0.415;  // the hollow, inside the 0.42 N shell
  const SceneInstance leaky = instantiate(thin, 64);
  CHECK_FALSE(contained(leaky.grid, Material::Liquid, 0, face_at(0.6, 64),
                        [&](Int3 p) { return near_axis(p, 32, 32, 0.42 * 64); }));
}

TEST_CASE("scene: bubbles: the tank holds the water and the inverted cup holds its gas above its opening") {
  const Scene scene = shipped("bubbles");
  for (int n : {scene.min_n, 33, 64, 96}) {
    CAPTURE(n);
    const SceneInstance s = instantiate(scene, n);
    const Int3 size = s.grid.size();
    // The tank: walls 0.06 N thick, open above 0.75 N.
    CHECK(contained(s.grid, Material::Liquid, 0, face_at(0.75, n), [&](Int3 p) {
      return p.x >= face_at(0.06, n) && p.x < face_at(0.94, n) && p.y >= face_at(0.06, n) && p.y < face_at(0.44, n);
    }));
    // The cup (outer radius 0.14 N, from 0.25 N to 0.45 N): gas in it cannot get out at or above the
    // layer of its opening; it lies under the roof, water below it.
    const double cx = 0.72 * n, cy = 0.25 * n;
    const int mouth = face_at(0.25, n), roof = face_at(0.45, n);
    auto in_cup = [&](Int3 p) { return near_axis(p, cx, cy, 0.14 * n) && p.z >= mouth && p.z < roof; };
    CHECK(contained(s.grid, Material::Gas, mouth, size.z, in_cup));
    const int ix = int(cx), iy = int(cy);
    CHECK(s.grid.at({ix, iy, mouth}) == Material::Liquid);
    CHECK(s.grid.at({ix, iy, top_of(s.grid, ix, iy, Material::Gas) + 1}) == Material::Solid);
    // Free pockets: gas outside the cup, deep under the water's surface.
    std::uint64_t free_gas = 0;
    for (int z = 0; z < size.z; ++z)
      for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x) free_gas += s.grid.at({x, y, z}) == Material::Gas && !in_cup({x, y, z});
    CHECK(free_gas > 0);
    CHECK(top_of(s.grid, size.x / 5, size.y / 2, Material::Gas) < mouth);
  }
  // A cup wall a fraction of a cell thick leaks: the check above can fail.
  Scene thin = scene;
  REQUIRE(std::holds_alternative<CylinderShape>(thin.shapes.at(3).geometry));
  REQUIRE(thin.shapes[3].material == Material::Solid);
  std::get<CylinderShape>(thin.shapes[3].geometry).radius = 0.085;  // the cup's shell, around its 0.08 N hollow
  const SceneInstance leaky = instantiate(thin, 64);
  CHECK_FALSE(contained(leaky.grid, Material::Gas, face_at(0.25, 64), leaky.grid.size().z, [&](Int3 p) {
    return near_axis(p, 0.72 * 64, 0.25 * 64, 0.14 * 64) && p.z < face_at(0.45, 64);
  }));
}

TEST_CASE("scene: gravel_and_sand: the same stream of sand and of gravel, side by side") {
  const Scene scene = shipped("gravel_and_sand");
  for (int n : {scene.min_n, 64, 96}) {
    CAPTURE(n);
    const SceneInstance s = instantiate(scene, n);
    REQUIRE(s.emitters.size() == 2);
    const Emitter &a = s.emitters[0], &b = s.emitters[1];
    CHECK(a.material == Material::Granular);
    CHECK(b.material == Material::Gravel);
    CHECK(a.rate == b.rate);
    CHECK(a.start == b.start);
    CHECK(a.stop == b.stop);
    CHECK(a.center.z == b.center.z);
    CHECK(b.center.x - a.center.x >= 0.75 * n);  // each heap spreads to about 0.39 N
    CHECK(count_of(s.grid, Material::Granular) + count_of(s.grid, Material::Gravel) == 0);
  }
}

TEST_CASE("scene: volumes scale as N^3 and a given N always gives the same cells") {
  struct Case {
    const char* scene;
    Material material;
  };
  for (const Case c : {Case{"bowl", Material::Solid}, Case{"bowl", Material::Granular},
                       Case{"column", Material::Granular}, Case{"hourglass", Material::Granular},
                       Case{"hourglass", Material::Solid}}) {
    CAPTURE(c.scene);
    CAPTURE(material_name(c.material));
    const Scene scene = shipped(c.scene);
    const double small = double(count_of(instantiate(scene, 64).grid, c.material));
    const double large = double(count_of(instantiate(scene, 128).grid, c.material));
    CHECK(large / small == doctest::Approx(8.0).epsilon(0.12));
  }
  const Scene bowl = shipped("bowl");
  CHECK(instantiate(bowl, 50).grid.hash() == instantiate(bowl, 50).grid.hash());
  CHECK(instantiate(bowl, 50).grid.hash() != instantiate(bowl, 51).grid.hash());
}

TEST_CASE("scene: rounding rule: faces snap to the nearest cell boundary, curved surfaces test cell centres") {
  const std::string text = R"({"name": "r", "description": "d", "size": [1, 1, SZ], "default_n": 35, "min_n": 1,
      "shapes": [SHAPE]})";
  auto build = [&](const std::string& size_z, const std::string& shape, int n) {
    return instantiate(parse_scene(with(with(text, "SZ", size_z), "SHAPE", shape), "r.json"), n).grid;
  };
  // [0.5, 1] of 35 is 17.5..35: 17.5 rounds up to 18, leaving floor(35/2) layers.
  const std::string half = R"({"type": "box", "material": "granular", "min": [0, 0, 0.5], "max": [1, 1, 1]})";
  Grid g = build("1", half, 35);
  CHECK(count_of(g, Material::Granular) == 35u * 35u * 17u);
  CHECK(g.at({0, 0, 17}) == Material::Void);
  CHECK(g.at({0, 0, 18}) == Material::Granular);
  CHECK(count_of(build("1", half, 36), Material::Granular) == 36u * 36u * 18u);
  // The grid extent rounds the same way: 0.5 * 35 = 17.5 -> 18 layers.
  CHECK(build("0.5", half, 35).size() == Int3{35, 35, 18});
  // A sphere of radius 1 cell around a cell centre holds the centre and its 6 face neighbours
  // (boundary included), not the 12 edge neighbours at distance 1.41.
  g = build("1", R"({"type": "sphere", "material": "solid", "center": [0.53125, 0.53125, 0.53125], "radius": 0.0625})",
            16);
  CHECK(count_of(g, Material::Solid) == 7);
  CHECK(g.at({8, 8, 8}) == Material::Solid);
  CHECK(g.at({9, 8, 8}) == Material::Solid);
  CHECK(g.at({9, 9, 8}) == Material::Void);
  // A bowl's shell includes both of its spheres and the rim plane: radius 1, wall 1 around a cell
  // centre gives the centre, its 4 horizontal neighbours and the one below.
  g = build("1", R"({"type": "bowl", "material": "solid", "center": [0.53125, 0.53125, 0.53125], "radius": 0.0625,
      "thickness_cells": 1})", 16);
  CHECK(count_of(g, Material::Solid) == 6);
  CHECK(g.at({8, 8, 7}) == Material::Solid);
  CHECK(g.at({8, 8, 9}) == Material::Void);
  // A cylinder's ends round like box faces: shapes sharing a height meet without gap or overlap.
  g = build("1", R"({"type": "box", "material": "solid", "min": [0, 0, 0], "max": [1, 1, 0.3]},
      {"type": "cylinder", "material": "granular", "only": "void", "center": [0.5, 0.5], "radius": 0.2, "z0": 0.3, "z1": 0.6})",
            35);
  CHECK(top_of(g, 17, 17, Material::Solid) + 1 == bottom_of(g, 17, 17, Material::Granular));
  CHECK(bottom_of(g, 17, 17, Material::Granular) == 11);  // 0.3 * 35 = 10.5 -> 11
  CHECK(top_of(g, 17, 17, Material::Granular) == 20);     // 0.6 * 35 = 21 -> layers up to 20
}

TEST_CASE("scene: shape volumes match their formulas and 'only' protects other cells") {
  const std::string text = R"({"name": "v", "description": "d", "size": [1, 1, 1], "default_n": 96, "min_n": 1,
      "shapes": [SHAPE]})";
  auto build = [&](const std::string& shape) { return instantiate(parse_scene(with(text, "SHAPE", shape), "v.json")).grid; };
  const double n = 96;
  Grid g = build(R"({"type": "sphere", "material": "solid", "center": [0.5, 0.5, 0.5], "radius": 0.4})");
  CHECK(double(count_of(g, Material::Solid)) == doctest::Approx(4.0 / 3.0 * kPi * std::pow(0.4 * n, 3)).epsilon(0.01));
  g = build(R"({"type": "cylinder", "material": "solid", "center": [0.5, 0.5], "radius": 0.3, "z0": 0.25, "z1": 0.75})");
  CHECK(double(count_of(g, Material::Solid)) == doctest::Approx(kPi * std::pow(0.3 * n, 2) * 0.5 * n).epsilon(0.01));
  g = build(R"({"type": "cone", "material": "solid", "center": [0.5, 0.5], "z0": 0.25, "z1": 0.75, "r0": 0.4, "r1": 0})");
  CHECK(double(count_of(g, Material::Solid)) == doctest::Approx(kPi * std::pow(0.4 * n, 2) * 0.5 * n / 3).epsilon(0.02));
  CHECK(g.at({48, 48, 24}) == Material::Solid);  // wide at the bottom
  CHECK(g.at({48 + 30, 48, 24}) == Material::Solid);
  CHECK(g.at({48 + 30, 48, 70}) == Material::Void);  // narrow at the top
  g = build(R"({"type": "frustum", "material": "solid", "center": [0.5, 0.5], "z0": 0.25, "z1": 0.75, "r0": 0.1, "r1": 0.3})");
  const double r0 = 0.1 * n, r1 = 0.3 * n;
  CHECK(double(count_of(g, Material::Solid)) ==
        doctest::Approx(kPi * 0.5 * n / 3 * (r0 * r0 + r0 * r1 + r1 * r1)).epsilon(0.02));
  g = build(R"({"type": "bowl", "material": "solid", "center": [0.5, 0.5, 0.6], "radius": 0.4, "thickness": 0.1})");
  CHECK(double(count_of(g, Material::Solid)) ==
        doctest::Approx(2.0 / 3.0 * kPi * (std::pow(0.4 * n, 3) - std::pow(0.3 * n, 3))).epsilon(0.03));
  CHECK(g.at({48, 48, 60}) == Material::Void);  // nothing above the rim
  g = build(R"({"type": "bowl", "material": "solid", "center": [0.5, 0.5, 0.6], "radius": 0.4, "thickness_cells": 2})");
  CHECK(double(count_of(g, Material::Solid)) ==
        doctest::Approx(2.0 / 3.0 * kPi * (std::pow(0.4 * n, 3) - std::pow(0.4 * n - 2, 3))).epsilon(0.05));
  g = build(R"({"type": "box", "material": "solid", "min": [0, 0, 0], "max": [0.5, 1, 1]},
      {"type": "box", "material": "granular", "only": "void", "min": [0.25, 0, 0], "max": [1, 1, 1]},
      {"type": "box", "material": "void", "only": "solid", "min": [0, 0, 0.5], "max": [1, 1, 1]})");
  CHECK(count_of(g, Material::Solid) == 48u * 96u * 48u);
  CHECK(count_of(g, Material::Granular) == 48u * 96u * 96u);
  CHECK(count_of(g, Material::Void) == 48u * 96u * 48u);
  // Shapes reaching outside the grid are clipped, not rejected.
  g = build(R"({"type": "sphere", "material": "solid", "center": [0, 0, 0], "radius": 0.5})");
  CHECK(double(count_of(g, Material::Solid)) == doctest::Approx(kPi / 6 * std::pow(0.5 * n, 3)).epsilon(0.03));
}

TEST_CASE("scene: the base test scene parses every field") {
  const Scene s = parse_scene(kBase, "base.json");
  CHECK(s.name == "base");
  CHECK(s.source == "base.json");
  CHECK(s.size == std::array<double, 3>{1, 1, 1});
  CHECK(s.default_n == 20);
  CHECK(s.min_n == 10);
  REQUIRE(s.shapes.size() == 5);
  CHECK(std::holds_alternative<BoxShape>(s.shapes[0].geometry));
  CHECK(std::holds_alternative<SphereShape>(s.shapes[1].geometry));
  CHECK(std::holds_alternative<CylinderShape>(s.shapes[2].geometry));
  CHECK(std::holds_alternative<ConeShape>(s.shapes[3].geometry));
  REQUIRE(std::holds_alternative<BowlShape>(s.shapes[4].geometry));
  CHECK(std::get<BowlShape>(s.shapes[4].geometry).thickness == 0.06);
  CHECK(s.shapes[1].material == Material::Granular);
  CHECK(s.shapes[3].material == Material::Void);
  CHECK(s.shapes[2].field == "shapes[2]");
  REQUIRE(s.emitters.size() == 1);
  const SceneInstance in = instantiate(s);
  REQUIRE(in.emitters.size() == 1);
  const Emitter& e = in.emitters[0];
  CHECK(e.center == Vec3{10, 10, 18});
  CHECK(e.radius == 1.0);
  CHECK(e.material == Material::Granular);
  CHECK(e.rate == 3);
  CHECK(e.start == 2);
  CHECK(e.stop == 10);
  // Scaled rates and ticks, and an emitter that never stops.
  const Scene scaled = parse_scene(with(kBase, R"("rate": 3, "start": 2, "stop": 10)", R"("rate_per_n2": 0.01, "start_per_n": 0.5)"),
                                   "scaled.json");
  const Emitter f = instantiate(scaled, 40).emitters.at(0);
  CHECK(f.rate == 16);
  CHECK(f.start == 20);
  CHECK(f.stop == std::numeric_limits<std::uint64_t>::max());
  // Every state's name, and the aliases "sand" and "water".
  for (const auto& [name, m] : std::vector<std::pair<std::string, Material>>{
           {"void", Material::Void}, {"solid", Material::Solid}, {"granular", Material::Granular},
           {"sand", Material::Granular}, {"liquid", Material::Liquid}, {"water", Material::Liquid},
           {"gas", Material::Gas}, {"gravel", Material::Gravel}, {"state6", Material::State6},
           {"state7", Material::State7}}) {
    CAPTURE(name);
    const Scene named = parse_scene(with(kBase, R"("material": "granular")", R"("material": ")" + name + "\""), "m.json");
    CHECK(named.shapes[1].material == m);
  }
}

TEST_CASE("scene: malformed scenes throw ParseError naming the file, the field and the value") {
  SUBCASE("malformed JSON reports line and column") {
    const std::string broken = with(kBase, R"("min_n": 10,)", R"("min_n": 10 oops)");
    expect_parse_error(broken, "line 6, column", "");
    expect_parse_error("", "line 1, column 1", "");
  }
  SUBCASE("missing required fields") {
    expect_parse_error(with(kBase, R"("size": [1, 1, 1],)", ""), "size", "missing");
    expect_parse_error(with(kBase, R"("name": "base",)", ""), "name", "missing");
    expect_parse_error(with(kBase, R"(, "radius": 0.2})", "}"), "shapes[1].radius", "missing");
    expect_parse_error(with(kBase, R"("type": "cone", )", ""), "shapes[3].type", "missing");
    expect_parse_error(with(kBase, R"("material": "solid", "center": [0.5, 0.5, 0.85])", R"("center": [0.5, 0.5, 0.85])"),
                       "shapes[4].material", "missing");
    expect_parse_error(with(kBase, R"("thickness": 0.06)", R"("comment": "no wall")"), "shapes[4].thickness", "missing");
    expect_parse_error(with(kBase, R"("rate": 3, )", ""), "emitters[0].rate", "missing");
  }
  SUBCASE("wrong types") {
    expect_parse_error(with(kBase, R"("default_n": 20)", R"("default_n": "20")"), "default_n", "\"20\"");
    expect_parse_error(with(kBase, R"("default_n": 20)", R"("default_n": 20.5)"), "default_n", "20.5");
    expect_parse_error(with(kBase, R"("size": [1, 1, 1])", R"("size": [1, 1])"), "size", "[1,1]");
    expect_parse_error(with(kBase, R"("center": [0.5, 0.5, 0.5])", R"("center": [0.5, "x", 0.5])"), "shapes[1].center[1]",
                       "\"x\"");
    expect_parse_error(with(kBase, R"("center": [0.25, 0.25])", R"("center": [0.25, 0.25, 0.1])"), "shapes[2].center",
                       "[0.25,0.25,0.1]");
    expect_parse_error(with(kBase, R"("shapes": [)", R"("shapes": {"a": [)") + "}", "shapes", "{");
    expect_parse_error(R"([1, 2])", "top level", "[1,2]");
    expect_parse_error(with(kBase, R"({"type": "box",)", R"(7, {"type": "box",)"), "shapes[0]", "7");
    expect_parse_error(with(kBase, R"("name": "base")", R"("name": 5)"), "name", "5");
    expect_parse_error(with(kBase, R"("material": "sand")", R"("material": 2)"), "emitters[0].material", "2");
  }
  SUBCASE("unknown shape type, material or field") {
    const std::string type = with(kBase, R"("type": "cone")", R"("type": "pyramid")");
    expect_parse_error(type, "shapes[3].type", "\"pyramid\"");
    expect_parse_error(type, "shapes[3].type", "cylinder");  // lists the valid types
    const std::string material = with(kBase, R"("material": "granular")", R"("material": "mud")");
    expect_parse_error(material, "shapes[1].material", "\"mud\"");
    expect_parse_error(material, "shapes[1].material", "granular");  // lists the valid names
    expect_parse_error(material, "shapes[1].material", "gravel");
    expect_parse_error(material, "shapes[1].material", "liquid (or water)");
    // State 5 is gravel now: its old placeholder name is no material.
    expect_parse_error(with(kBase, R"("material": "granular")", R"("material": "state5")"), "shapes[1].material",
                       "\"state5\"");
    expect_parse_error(with(kBase, R"("material": "void")", R"("material": "void", "only": "clay")"), "shapes[3].only",
                       "\"clay\"");
    expect_parse_error(with(kBase, R"("radius": 0.2})", R"("radus": 0.2, "radius": 0.2})"), "shapes[1].radus", "0.2");
    expect_parse_error(with(kBase, R"("min_n": 10,)", R"("min_n": 10, "gravity": 9.8,)"), "gravity", "9.8");
    expect_parse_error(with(kBase, R"("stop": 10)", R"("stop": 10, "speed": 1)"), "emitters[0].speed", "1");
  }
  SUBCASE("negative, zero and non-finite lengths") {
    expect_parse_error(with(kBase, R"("radius": 0.2})", R"("radius": -0.2})"), "shapes[1].radius", "-0.2");
    expect_parse_error(with(kBase, R"("r0": 0.05)", R"("r0": -0.05)"), "shapes[3].r0", "-0.05");
    expect_parse_error(with(kBase, R"("thickness": 0.06)", R"("thickness": 0)"), "shapes[4].thickness", "0");
    expect_parse_error(with(kBase, R"("thickness": 0.06)", R"("thickness": 0.5)"), "shapes[4].thickness", "0.5");
    expect_parse_error(with(kBase, R"("thickness": 0.06)", R"("thickness": 0.06, "thickness_cells": 2)"),
                       "shapes[4].thickness_cells", "2");
    expect_parse_error(with(kBase, R"("radius": 0.05, "material": "sand")", R"("radius": 0, "material": "sand")"),
                       "emitters[0].radius", "0");
    expect_parse_error(with(kBase, R"("radius": 0.2})", R"("radius": 1e999})"), "malformed JSON", "1e999");
    expect_parse_error(with(kBase, R"("center": [0.5, 0.5, 0.5])", R"("center": [0.5, 0.5, 5000])"), "shapes[1].center[2]",
                       "5000");
  }
  SUBCASE("inverted ranges and zero sizes") {
    expect_parse_error(with(kBase, R"("max": [1, 1, 0.1])", R"("max": [1, -1, 0.1])"), "shapes[0].max", "[1,-1,0.1]");
    expect_parse_error(with(kBase, R"("z1": 0.3})", R"("z1": 0.05})"), "shapes[2].z1", "0.05");
    expect_parse_error(with(kBase, R"("z1": 0.35)", R"("z1": 0.1)"), "shapes[3].z1", "0.1");
    expect_parse_error(with(kBase, R"("size": [1, 1, 1])", R"("size": [1, 0, 1])"), "size[1]", "0");
    expect_parse_error(with(kBase, R"("size": [1, 1, 1])", R"("size": [1, 1, -2])"), "size[2]", "-2");
    expect_parse_error(with(kBase, R"("min_n": 10)", R"("min_n": 30)"), "min_n", "30");
    expect_parse_error(with(kBase, R"("min_n": 10)", R"("min_n": 0)"), "min_n", "0");
    expect_parse_error(with(kBase, R"("stop": 10)", R"("stop": 1)"), "emitters[0].stop", "1");
  }
  SUBCASE("bad emitters") {
    expect_parse_error(with(kBase, R"("material": "sand")", R"("material": "void")"), "emitters[0].material", "\"void\"");
    expect_parse_error(with(kBase, R"("rate": 3)", R"("rate": 3, "rate_per_n2": 0.1)"), "emitters[0].rate_per_n2", "0.1");
    expect_parse_error(with(kBase, R"("rate": 3)", R"("rate": 0)"), "emitters[0].rate", "0");
    expect_parse_error(with(kBase, R"("rate": 3)", R"("rate_per_n2": -1)"), "emitters[0].rate_per_n2", "-1");
    expect_parse_error(with(kBase, R"("start": 2)", R"("start": -2)"), "emitters[0].start", "-2");
    expect_parse_error(with(kBase, R"("emitters": [)", R"("emitters": 3, "comment": [)"), "emitters", "3");
  }
}

TEST_CASE("scene: instantiate rejects N below min_n and values that do not resolve at that N") {
  const Scene base = parse_scene(kBase, "inst.json");
  expect_invalid(base, 9, "min_n");
  expect_invalid(base, 9, "N=9");
  expect_invalid(base, -1, "-1");
  CHECK_NOTHROW(instantiate(base, 10));
  const Scene flat = parse_scene(with(kBase, R"("size": [1, 1, 1])", R"("size": [1, 1, 0.01])"), "flat.json");
  expect_invalid(flat, 20, "size[2]");
  const Scene slow = parse_scene(with(kBase, R"("rate": 3)", R"("rate_per_n2": 0.001)"), "slow.json");
  expect_invalid(slow, 20, "emitters[0].rate_per_n2");
  CHECK(instantiate(slow, 40).emitters.at(0).rate == 2);
  const Scene outside = parse_scene(with(kBase, R"("center": [0.5, 0.5, 0.9])", R"("center": [0.5, 0.5, 1.5])"), "out.json");
  expect_invalid(outside, 20, "emitters[0].center[2]");
  const Scene late = parse_scene(with(kBase, R"("stop": 10)", R"("stop_per_n": 0.05)"), "late.json");
  expect_invalid(late, 20, "emitters[0].stop_per_n");
  const Scene thick =
      parse_scene(with(kBase, R"("thickness": 0.06)", R"("thickness_cells": 2)"), "thick.json");
  CHECK_NOTHROW(instantiate(thick, 20));
  expect_invalid(thick, 10, "shapes[4]");
  expect_invalid(base, 100000, "size");
}

TEST_CASE("scene: a default_n whose grid exceeds 256^3 cells is refused with the memory it would need") {
  expect_parse_error(with(kBase, R"("default_n": 20)", R"("default_n": 1000)"), "default_n",
                     "1000x1000x1000 grid (1000000000 cells, about 1.86 GiB to run)");
  expect_parse_error(with(kBase, R"("default_n": 20)", R"("default_n": 100000)"), "default_n", "100000x100000x100000");
  expect_parse_error(with(kBase, R"("default_n": 20)", R"("default_n": 16000000)"), "default_n", "more than");
  // 256^3 itself is a valid default, and a flat scene may have a larger N within the same cells.
  CHECK(parse_scene(with(kBase, R"("default_n": 20)", R"("default_n": 256)"), "d.json").default_n == 256);
  const std::string flat = with(with(kBase, R"("default_n": 20)", R"("default_n": 512)"), R"("size": [1, 1, 1])",
                                R"("size": [1, 1, 0.0625])");
  CHECK(parse_scene(flat, "flat.json").default_n == 512);
  // Asked for explicitly, a larger N is instantiate's (and check_grid_size's) to judge.
  CHECK(instantiate(parse_scene(kBase, "base.json"), 300).grid.size() == Int3{300, 300, 300});
}

TEST_CASE("scene: JSON nested 100,000 levels deep is a ParseError, not a stack overflow") {
  for (const char* open : {"[", "{\"a\":"}) {
    std::string deep;
    for (int i = 0; i < 100000; ++i) deep += open;
    expect_parse_error(deep, "line 1, column", "deeper than 32 levels");
    // Valid JSON, deep inside a field: refused before nlohmann builds (or prints) it.
    std::string closed = deep;
    closed += "1";
    for (int i = 0; i < 100000; ++i) closed += open[0] == '[' ? "]" : "}";
    expect_parse_error(with(kBase, R"("name": "base")", R"("name": )" + closed), "column", "deeper than 32 levels");
  }
  // Brackets inside strings do not count.
  const std::string brackets(1000, '[');
  CHECK(parse_scene(with(kBase, R"("description": "test scene")", R"("description": ")" + brackets + "\""), "b.json")
            .description == brackets);
}

TEST_CASE("scene: messages quote a bounded excerpt of long values and keys") {
  const std::string long_text(1 << 20, 'x');
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {R"("name": "base")", R"("name": [")" + long_text + R"("])"},
           {R"("material": "granular")", R"("material": ")" + long_text + "\""},
           {R"("min_n": 10,)", R"("min_n": 10, ")" + long_text + R"(": 1,)"},
           {R"("radius": 0.2})", R"("radius": [)" + std::string(100000, '1') + "]}"},
       }) {
    bool thrown = false;
    try {
      parse_scene(with(kBase, from, to), "long.json");
    } catch (const ParseError& e) {
      thrown = true;
      const std::string message = e.what();
      CAPTURE(message.substr(0, 400));
      CHECK(message.size() < 400);
      CHECK(contains(message, "..."));
    }
    CHECK(thrown);
  }
  expect_parse_error(with(kBase, R"("name": "base")", R"("name": ")" + std::string(300, 'n') + "\""), "name",
                     "at most 256 bytes");
}

TEST_CASE("scene: load_scene reads only regular files of at most 16 MiB") {
  const auto dir = std::filesystem::temp_directory_path() / ("granular-test-fifo-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto fifo = dir / "pipe.json";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  CHECK_THROWS_WITH_AS(load_scene(fifo), doctest::Contains("FIFO"), FileError);
  if (std::filesystem::exists("/dev/zero")) {
    std::filesystem::create_symlink("/dev/zero", dir / "zero.json");
    CHECK_THROWS_WITH_AS(load_scene(dir / "zero.json"), doctest::Contains("character device"), FileError);
  }
  {
    std::ofstream big(dir / "big.json");
    big << std::string(std::size_t(kMaxSceneFileBytes) + 1, ' ');
  }
  CHECK_THROWS_WITH_AS(load_scene(dir / "big.json"), doctest::Contains("16 MiB"), FileError);
  std::filesystem::remove_all(dir);
}

TEST_CASE("scene: find_scene resolves names and paths; unknown names list the available scenes") {
  const ShippedAssets assets;
  CHECK(scene_dir() == kAssetDir / "scenes");
  const std::filesystem::path by_name = find_scene("bowl");
  CHECK(by_name == kAssetDir / "scenes" / "bowl.json");
  CHECK(find_scene("bowl.json") == by_name);
  const std::filesystem::path file = kAssetDir / "scenes" / "pile.json";
  CHECK(find_scene(file.string()) == file);
  CHECK(load_scene(find_scene("hourglass")).name == "hourglass");
  for (const char* bad : {"no_such_scene", "", "scenes/bowl"}) {
    CAPTURE(bad);
    bool thrown = false;
    try {
      (void)find_scene(bad);
    } catch (const InvalidArgument& e) {
      thrown = true;
      const std::string message = e.what();
      CAPTURE(message);
      for (const char* name : {"bowl", "column", "hourglass", "pile"}) CHECK(contains(message, name));
      CHECK(contains(message, bad));
    }
    CHECK(thrown);
  }
}

TEST_CASE("scene: $GRANULAR_ASSET_DIR selects the scene folder") {
  const auto dir = std::filesystem::temp_directory_path() / ("granular-test-scenes-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "scenes");
  std::ofstream(dir / "scenes" / "custom.json") << kBase;
  std::ofstream(dir / "scenes" / "notes.txt") << "not a scene";
  {
    const EnvVar env("GRANULAR_ASSET_DIR", dir.c_str());
    CHECK(scene_dir() == dir / "scenes");
    CHECK(list_scenes() == std::vector<std::string>{"custom"});
    CHECK(find_scene("custom") == dir / "scenes" / "custom.json");
    CHECK(load_scene(find_scene("custom")).name == "base");
    CHECK_THROWS_AS(find_scene("bowl"), InvalidArgument);
  }
  {
    const EnvVar env("GRANULAR_ASSET_DIR", (dir / "missing").c_str());
    CHECK(list_scenes().empty());
    CHECK_THROWS_WITH_AS(find_scene("bowl"), doctest::Contains("available scenes: none"), InvalidArgument);
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("scene: load_scene reports unreadable files and names the file in parse errors") {
  const auto dir = std::filesystem::temp_directory_path() / ("granular-test-load-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  CHECK_THROWS_WITH_AS(load_scene(dir / "absent.json"), doctest::Contains("absent.json"), FileError);
  CHECK_THROWS_AS(load_scene(dir), FileError);
  const auto bad = dir / "broken_file.json";
  std::ofstream(bad) << "{\n  \"name\": \"x\",\n  \"size\": [1, 1,\n";
  bool thrown = false;
  try {
    (void)load_scene(bad);
  } catch (const ParseError& e) {
    thrown = true;
    const std::string message = e.what();
    CAPTURE(message);
    CHECK(contains(message, bad.string()));
    CHECK(contains(message, "line 4"));
  }
  CHECK(thrown);
  std::filesystem::remove_all(dir);
}

#if defined(GRANULAR_TEST_ASSET_DIR)
// Needs World's definitions, so only in the full build (whose test target defines GRANULAR_TEST_ASSET_DIR).
TEST_CASE("scene: run_emitters pours `rate` cells on each tick in [start, stop) and none after") {
  const Scene scene = parse_scene(R"({"name": "e", "description": "d", "size": [1, 1, 1], "default_n": 16, "min_n": 1,
      "shapes": [{"type": "box", "material": "solid", "min": [0, 0, 0], "max": [1, 1, 0.125]}],
      "emitters": [{"center": [0.5, 0.5, 0.75], "radius": 0.2, "rate": 5, "start": 2, "stop": 6}]})",
                                  "emit.json");
  const SceneInstance s = instantiate(scene);
  REQUIRE(s.emitters.size() == 1);
  World world(test::test_def(s.grid.size()), s.grid);
  const std::uint64_t solid = count_of(s.grid, Material::Solid);
  const MaterialCounts start = world.count();
  MaterialCounts all_poured{};
  for (std::uint64_t tick = 0; tick < 12; ++tick) {
    CAPTURE(tick);
    REQUIRE(world.tick() == tick);
    const MaterialCounts poured = run_emitters(world, s.emitters);
    for (int m = 0; m < kMaterialCount; ++m) all_poured[m] += poured[m];
    CHECK(world.count() == counts_after_pouring(start, all_poured));
    CHECK(poured[to_cell(Material::Granular)] == (tick >= 2 && tick < 6 ? 5u : 0u));
    const std::uint64_t active_ticks = tick < 2 ? 0 : std::min<std::uint64_t>(tick, 5) - 1;
    CHECK(world.count()[to_cell(Material::Granular)] == 5 * active_ticks);
    CHECK(world.count()[to_cell(Material::Solid)] == solid);
    world.step(1);
  }
  CHECK(world.count()[to_cell(Material::Granular)] == 20);
}

TEST_CASE("scene: run_emitters checks every active emitter first: a failing call changes nothing") {
  const Scene scene = parse_scene(R"({"name": "e", "description": "d", "size": [1, 1, 1], "default_n": 16, "min_n": 1,
      "shapes": [], "emitters": [{"center": [0.5, 0.5, 0.75], "radius": 0.2, "rate": 5}]})",
                                  "emit.json");
  const SceneInstance s = instantiate(scene);
  World world(test::test_def(s.grid.size()), s.grid);
  const std::uint64_t hash = world.hash();
  const std::uint64_t version = world.change_version();
  std::vector<Emitter> emitters = s.emitters;
  Emitter bad = emitters[0];
  SUBCASE("outside the grid") { bad.center = {500, 500, 500}; }
  SUBCASE("void") { bad.material = Material::Void; }
  SUBCASE("negative rate") { bad.rate = -1; }
  SUBCASE("zero radius") { bad.radius = 0; }
  SUBCASE("non-finite centre") { bad.center.x = std::numeric_limits<double>::quiet_NaN(); }
  emitters.push_back(bad);
  CHECK_THROWS_WITH_AS(run_emitters(world, emitters), doctest::Contains("emitter 1"), InvalidArgument);
  CHECK(world.hash() == hash);
  CHECK(world.change_version() == version);
  CHECK(world.count()[to_cell(Material::Granular)] == 0);
  // An inactive invalid emitter is not checked: it does not pour.
  emitters.back().start = 100;
  run_emitters(world, emitters);
  CHECK(world.count()[to_cell(Material::Granular)] == 5);
}
#endif
