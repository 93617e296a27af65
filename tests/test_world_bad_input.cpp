// Absurd input to the library: far-away tools, enormous boxes, bad enums, thread counts past the
// bound, a thread pool the system cannot start, calls on a moved-from World. Each is a typed error
// naming the value, with bounded resources, and leaves the world as it was.

#include <doctest/doctest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <climits>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <limits>
#include <utility>

#include "granular/errors.hpp"
#include "granular/extend/lut.hpp"
#include "granular/rule_presets.hpp"
#include "granular/extend/threads.hpp"
#include "granular/world.hpp"
#include "test_support.hpp"
#include "cpu/thread_pool.hpp"

using namespace granular;
using granular::test::test_def;

namespace {

World sand_world() {
  World world(test_def({16, 16, 16}));
  world.paint(Box{{0, 0, 0}, {16, 16, 4}}, Material::Granular);
  return world;
}

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

/// Bytes of address space this process has mapped (/proc/self/statm, first field in pages).
long mapped_bytes() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0;
  statm >> pages;
  return pages * sysconf(_SC_PAGESIZE);
}

}  // namespace

TEST_CASE("bad input: tools centred far outside the grid are InvalidArgument, not bad_alloc") {
  World world = sand_world();
  const std::uint64_t hash = world.hash();
  for (const double far : {1e10, -1e10, 3e9, double(INT_MAX) + 10.0, 1e300}) {
    CAPTURE(far);
    CHECK_THROWS_WITH_AS(world.dig(Sphere{{far, 8, 8}, 2}), doctest::Contains("covers no cell"), InvalidArgument);
    CHECK_THROWS_WITH_AS(world.pour({8, far, 8}, 3, Material::Granular, 10), doctest::Contains("covers no cell"),
                         InvalidArgument);
    CHECK_THROWS_WITH_AS(world.paint(Sphere{{8, 8, far}, 1}, Material::Solid), doctest::Contains("covers no cell"),
                         InvalidArgument);
  }
  CHECK(world.hash() == hash);
  // A sphere too large for any int still only touches the grid.
  const ChangeReport all = world.dig(Sphere{{8, 8, 8}, 1e300});
  CHECK(all.region == Box{{0, 0, 0}, {16, 16, 16}});
  CHECK(all.clipped);
  CHECK(all.cells_changed == 16 * 16 * 4);
}

TEST_CASE("bad input: enormous boxes are checked before anything is allocated") {
  constexpr Box everything{{INT_MIN, INT_MIN, INT_MIN}, {INT_MAX, INT_MAX, INT_MAX}};
  static_assert(everything.volume() == std::numeric_limits<std::int64_t>::max());
  static_assert(Box{{0, 0, 0}, {INT_MAX, INT_MAX, 1}}.volume() == std::int64_t(INT_MAX) * INT_MAX);
  static_assert(Box{{-2, 0, 0}, {2, 3, 5}}.volume() == 60);
  World world = sand_world();
  CHECK_THROWS_WITH_AS(world.read_region(everything), doctest::Contains("not inside the 16x16x16 grid"),
                       InvalidArgument);
  CHECK_THROWS_WITH_AS(world.read_region(Box{{0, 0, 0}, {1200, 1200, 1200}}), doctest::Contains("not inside"),
                       InvalidArgument);
  const ChangeReport painted = world.paint(everything, Material::Void);
  CHECK(painted.region == Box{{0, 0, 0}, {16, 16, 16}});
  CHECK(painted.clipped);
}

TEST_CASE("bad input: a BackendKind outside the enum is refused") {
  WorldDef def = test_def({8, 8, 8});
  def.backend = static_cast<BackendKind>(7);
  CHECK_THROWS_WITH_AS(World{def}, doctest::Contains("WorldDef::backend = 7"), InvalidArgument);
}

TEST_CASE("bad input: thread counts past max_threads() are refused before any thread starts") {
  CHECK(max_threads() == 4 * hardware_threads());
  CHECK(resolve_threads(0, "t") == hardware_threads());
  CHECK(resolve_threads(max_threads(), "t") == max_threads());
  WorldDef def = test_def({8, 8, 8});
  def.threads = 100000;
  CHECK_THROWS_WITH_AS(World{def}, doctest::Contains("WorldDef::threads = 100000"), InvalidArgument);
  def.threads = max_threads() + 1;
  CHECK_THROWS_AS(World{def}, InvalidArgument);
  const auto rules = make_rule_set("paper");
  CHECK_THROWS_WITH_AS(Lut::build(*rules, 100000), doctest::Contains("threads = 100000"), InvalidArgument);
  CHECK_THROWS_WITH_AS(Lut::build(*rules, -1), doctest::Contains("threads = -1"), InvalidArgument);
}

TEST_CASE("bad input: a thread pool the system cannot start is an error, not a hang" *
          doctest::skip(kAddressSanitizer)) {
  // In a child process whose address space leaves room for a few thread stacks only; the alarm
  // turns a hang into a failure.
  std::fflush(nullptr);
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    alarm(20);
    const rlim_t limit = rlim_t(mapped_bytes()) + (64u << 20);
    const rlimit as{limit, limit};
    if (setrlimit(RLIMIT_AS, &as) != 0) _exit(3);
    try {
      ThreadPool pool(512);
      _exit(4);  // every thread started: the limit did not bite
    } catch (const BackendError& e) {
      const std::string what = e.what();
      _exit(what.find("of 512") != std::string::npos && what.find("fewer threads") != std::string::npos ? 0 : 5);
    } catch (...) {
      _exit(6);
    }
  }
  int status = 0;
  REQUIRE(waitpid(child, &status, 0) == child);
  CHECK_MESSAGE(WIFEXITED(status), "the child was killed (signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0)
                                                                   << "): the pool hung or crashed");
  if (WIFEXITED(status)) CHECK(WEXITSTATUS(status) == 0);
}

TEST_CASE("bad input: a moved-from World throws StateError instead of crashing") {
  World world = sand_world();
  World moved(std::move(world));
  CHECK(moved.count()[to_cell(Material::Granular)] == 16 * 16 * 4);
  CHECK_THROWS_WITH_AS(world.step(1), doctest::Contains("moved from"), StateError);
  CHECK_THROWS_AS(world.count(), StateError);
  CHECK_THROWS_AS(world.hash(), StateError);
  CHECK_THROWS_AS(world.read_grid(), StateError);
  CHECK_THROWS_AS(world.rules(), StateError);
  CHECK_THROWS_AS(world.lut(), StateError);
  CHECK_THROWS_AS(world.backend(), StateError);
  CHECK_THROWS_AS(world.dig(Sphere{{8, 8, 8}, 2}), StateError);
  CHECK_THROWS_AS(world.read_region(Box{{0, 0, 0}, {1, 1, 1}}), StateError);
  CHECK_THROWS_AS(world.bricks_changed_since(0), StateError);
  world = std::move(moved);  // assignment brings it back
  CHECK(world.count()[to_cell(Material::Granular)] == 16 * 16 * 4);
}

TEST_CASE("bad input: a World is checked for the memory its backend copy needs, not the grid alone") {
  struct MemoryLimit {
    explicit MemoryLimit(const char* bytes) { setenv("GRANULAR_MEMORY_LIMIT", bytes, 1); }
    ~MemoryLimit() { unsetenv("GRANULAR_MEMORY_LIMIT"); }
  } limit("300M");
  // 2 x 128 MiB of cells + the table fit no 300 MiB budget, though the grid alone would.
  CHECK_THROWS_WITH_AS(World{test_def({512, 512, 512})}, doctest::Contains("WorldDef::size"), OutOfMemory);
  const Grid grid({64, 64, 64});
  World small(test_def({64, 64, 64}), grid);
  CHECK(small.count()[to_cell(Material::Void)] == 64 * 64 * 64);
}

TEST_CASE("bad input: the tick and tool-call counters are refused before they wrap, and nothing changes") {
  World world(test_def({16, 16, 16}, "paper", 1, 1), Grid({16, 16, 16}));
  world.paint(Box{{4, 4, 4}, {12, 12, 12}}, Material::Granular);
  WorldSnapshot near_end = world.capture();
  constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();
  near_end.tick = kMax - 1;
  near_end.tool_calls = kMax;
  world.restore(near_end);
  const std::uint64_t hash = world.hash();
  granular::test::check_has(granular::test::error_of<StateError>([&] { world.step(2); }), {"World::step", "ticks = 2", "wrap"});
  CHECK(world.tick() == kMax - 1);
  CHECK(world.hash() == hash);
  world.step(1);
  CHECK(world.tick() == kMax);
  granular::test::check_has(granular::test::error_of<StateError>([&] { world.step(1); }), {"World::step", "wrap"});
  const std::uint64_t stepped = world.hash();
  granular::test::check_has(granular::test::error_of<StateError>([&] { world.dig(Sphere{{8.0, 8.0, 8.0}, 3.0}); }), {"tool-call counter", "no cell was changed"});
  CHECK(world.hash() == stepped);
  CHECK(world.tool_calls() == kMax);
}
