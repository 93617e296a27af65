/// @file test_backend_factory.cpp
/// Backends plugged in: a World whose backend the game's factory creates (WorldDef::backend_factory)
/// gets exactly that backend from exactly the WorldDef's values; the CPU factory and the backend
/// registry refuse what they cannot use, naming the field. (Which backends a program has by what it
/// links is checked by examples/backend_choice.cpp, built once on the umbrella and once on the core.)

#include <doctest/doctest.h>

#include <memory>
#include <optional>
#include <string>

#include "granular/extend/backend.hpp"
#include "granular/extend/backend_factory.hpp"
#include "granular/extend/backend_registry.hpp"
#include "granular/errors.hpp"
#include "granular/extend/lut.hpp"
#include "granular/rule_presets.hpp"
#include "granular/rule_set.hpp"
#include "granular/world.hpp"
#include "test_support.hpp"

using namespace granular;
using namespace granular::test;

TEST_CASE("backend factory: the game's factory creates the world's backend from the WorldDef's values") {
  const Grid initial = random_grid({30, 26, 22}, 3);
  WorldDef def = test_def(initial.size(), "inertial-24", 2, 41);
  def.sparse = false;
  def.cuda.dense_fraction = 0.5;
  int calls = 0;
  std::optional<BackendCreateInfo> seen;
  WorldDef own = def;
  own.backend = BackendKind::Cuda;  // the factory wins over the kind
  own.backend_factory = [&](const BackendCreateInfo& info) {
    ++calls;
    seen.emplace(info);
    CHECK(info.initial.hash() == initial.hash());
    BackendCreateInfo one_thread = info;
    one_thread.threads = 1;
    return make_cpu_backend(one_thread);
  };
  World mine(own, initial);
  World plain(def, initial);
  CHECK(calls == 1);
  REQUIRE(seen.has_value());
  CHECK(seen->lut.get() == &mine.lut());
  CHECK(seen->rules.get() == &mine.rules());
  CHECK(seen->rules->name == "inertial-24");
  CHECK(seen->seed == 41u);
  CHECK_FALSE(seen->sparse);
  CHECK(seen->threads == 2);
  CHECK(seen->task_system == nullptr);
  CHECK(seen->cuda.dense_fraction == 0.5);
  CHECK(mine.backend() == BackendKind::Cpu);
  CHECK(mine.backend_description() == "cpu (1 thread)");
  CHECK(plain.backend_description() == "cpu (2 threads)");
  mine.step(25);
  plain.step(25);
  CHECK(mine.hash() == plain.hash());
}

TEST_CASE("backend factory: a factory's error passes through; no backend at all is a BackendError") {
  WorldDef def = test_def({8, 8, 8});
  def.backend_factory = [](const BackendCreateInfo&) -> std::unique_ptr<Backend> {
    throw BackendError("game backend: no device");
  };
  check_has(error_of<BackendError>([&] { World w(def); }), {"game backend: no device"});
  def.backend_factory = [](const BackendCreateInfo&) { return std::unique_ptr<Backend>(); };
  check_has(error_of<BackendError>([&] { World w(def); }), {"WorldDef::backend_factory", "no backend"});
}

TEST_CASE("backend factory: make_cpu_backend refuses what it cannot step, naming the field") {
  const Grid g({8, 8, 8});
  const auto rules = make_rule_set("paper");
  const auto lut = std::make_shared<const Lut>(Lut::build(*rules, 2));
  check_has(error_of<InvalidArgument>([&] { make_cpu_backend({.initial = g, .lut = nullptr, .rules = rules}); }),
            {"BackendCreateInfo::lut"});
  check_has(error_of<InvalidArgument>([&] { make_cpu_backend({.initial = g, .lut = lut, .rules = nullptr}); }),
            {"BackendCreateInfo::rules"});
  check_has(error_of<InvalidArgument>(
                [&] { make_cpu_backend({.initial = g, .lut = lut, .rules = rules, .threads = 0}); }),
            {"BackendCreateInfo::threads = 0"});
  check_has(error_of<InvalidArgument>([&] { make_cpu_backend({.initial = Grid(), .lut = lut, .rules = rules}); }),
            {"empty"});
  const auto backend = make_cpu_backend({.initial = g, .lut = lut, .rules = rules, .threads = 2});
  CHECK(backend->kind() == BackendKind::Cpu);
  CHECK(backend->hash() == g.hash());
}

TEST_CASE("backend registry: only a complete provider of a pluggable kind is registered") {
  BackendProvider cpu;
  cpu.kind = BackendKind::Cpu;
  check_has(error_of<InvalidArgument>([&] { register_backend(cpu); }), {"BackendProvider::kind = cpu"});
  BackendProvider automatic;
  automatic.kind = BackendKind::Auto;
  check_has(error_of<InvalidArgument>([&] { register_backend(automatic); }), {"BackendProvider::kind = auto"});
  BackendProvider incomplete;  // kind cuda, no functions
  check_has(error_of<InvalidArgument>([&] { register_backend(incomplete); }), {"unusable_reason, create and device_uuid"});
  CHECK_FALSE(registered_backend(BackendKind::Cpu).has_value());
  CHECK_FALSE(registered_backend(BackendKind::Auto).has_value());
}
