/// @file test_rule_set_input.cpp
/// A game's rule set as hostile input: its name becomes part of a cache file name and of messages,
/// so it is checked (non-empty, bounded, printable ASCII) and never leads a file outside the cache
/// folder; a block rule that throws leaves as a RuleError naming the rule set and the block key.

#include <doctest/doctest.h>

#include <unistd.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "granular/errors.hpp"
#include "granular/extend/lut.hpp"
#include "granular/rule_presets.hpp"

using namespace granular;

namespace {

/// A fresh, empty folder of this test process's own.
std::filesystem::path fresh_dir(const char* name) {
  auto dir = std::filesystem::temp_directory_path() / ("granular-test-" + std::string(name) + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// Throws on every block.
Transition throws_always(const BlockCells&, const MaterialTable&) { throw std::runtime_error("the game's rule gave up"); }

/// Throws on the one block of eight gravel cells (state 5), a key the rule fingerprint's samples
/// (every key over void, solid and sand, and 4096 pseudo-random keys) do not reach, so only the
/// table build meets it; every other block stays as it is.
Transition throws_on_all_gravel(const BlockCells& cells, const MaterialTable&) {
  for (auto c : cells)
    if (c != 5) return kIdentityTransition;
  throw std::out_of_range("no rule for a gravel block");
}

/// Throws something that is not a std::exception.
Transition throws_an_int(const BlockCells&, const MaterialTable&) { throw 42; }

}  // namespace

TEST_CASE("rule set input: the name is checked, and a bad one is named in the message, cut short") {
  RuleSet r = preset("paper");
  r.name = "";
  CHECK_THROWS_WITH_AS(validate_rule_set(r), doctest::Contains("RuleSet::name is empty"), RuleError);
  r.name = std::string(10 << 20, 'x');
  try {
    validate_rule_set(r);
    FAIL("expected RuleError for a 10 MiB name");
  } catch (const RuleError& e) {
    const std::string msg = e.what();
    CHECK(msg.find("RuleSet::name has 10485760 bytes; at most 64") != std::string::npos);
    CHECK(msg.size() < 300);
  }
  r.name = "two\nlines";
  CHECK_THROWS_WITH_AS(validate_rule_set(r), doctest::Contains("RuleSet::name byte 3 is \\x0A; a name is printable ASCII"),
                       RuleError);
  r.name = "caf\xC3\xA9";
  CHECK_THROWS_WITH_AS(validate_rule_set(r), doctest::Contains("rule set 'caf\\xC3\\xA9': RuleSet::name byte 3"), RuleError);
  r.name = std::string(kMaxRuleSetNameBytes, 'a');
  CHECK_NOTHROW(validate_rule_set(r));
  r.name = "x/../../escaped";  // printable: allowed as a name, never as a path
  CHECK_NOTHROW(validate_rule_set(r));
}

TEST_CASE("rule set input: the table cache's file lies in the cache folder whatever the name") {
  const std::filesystem::path dir = fresh_dir("rule-names") / "cache";
  RuleSet r = preset("paper");
  for (const std::string& name : std::vector<std::string>{"x/../../escaped", "..", "/etc/passwd", "a\\b c", std::string(200, '/')}) {
    r.name = name;
    const std::filesystem::path file = lut_cache_file(r, dir);
    CHECK_MESSAGE(file.parent_path() == dir, "name '", name, "' gives ", file);
    CHECK(file.filename().string().rfind("lut-", 0) == 0);
    CHECK(file.filename().string().size() < 100);
  }
  r.name = "x/../../escaped";
  CHECK(lut_cache_file(r, dir).filename().string().find("lut-x_.._.._escaped-") == 0);
  // Two names that read alike on disk keep their own files (the fingerprint covers the whole name).
  RuleSet other = r;
  other.name = "x_.._.._escaped";
  CHECK(lut_cache_file(r, dir) != lut_cache_file(other, dir));
  // An invalid name is refused before the cache folder is touched.
  r.name = "";
  LutCacheOptions options;
  options.directory = dir;
  CHECK_THROWS_AS(obtain_lut(r, options), RuleError);
  CHECK_FALSE(std::filesystem::exists(dir));
  std::filesystem::remove_all(dir.parent_path());
}

TEST_CASE("rule set input: a block rule that throws is a RuleError naming the rule set and the block key") {
  RuleSet r = preset("paper");
  r.name = "thrower";
  r.transition = &throws_always;
  CHECK_THROWS_WITH_AS((void)Lut::build(r, 2),
                       doctest::Contains("rule set 'thrower': RuleSet::transition threw on block key 00 (cells void void void "
                                         "void void void void void): the game's rule gave up"),
                       RuleError);
  CHECK_THROWS_AS(rule_fingerprint(r), RuleError);
  LutCacheOptions no_cache;
  no_cache.enabled = false;
  CHECK_THROWS_WITH_AS(obtain_lut(r, no_cache), doctest::Contains("the game's rule gave up"), RuleError);

  r.transition = &throws_on_all_gravel;
  CHECK_NOTHROW(rule_fingerprint(r));
  CHECK_THROWS_WITH_AS((void)Lut::build(r, 2),
                       doctest::Contains("RuleSet::transition threw on block key 055555555 (cells gravel gravel gravel "
                                         "gravel gravel gravel gravel gravel): no rule for a gravel block"),
                       RuleError);

  r.transition = &throws_an_int;
  CHECK_THROWS_WITH_AS((void)Lut::build(r, 1), doctest::Contains("threw on block key 00 (cells void"), RuleError);
  CHECK_THROWS_WITH_AS((void)Lut::build(r, 1), doctest::Contains("an exception that is not a std::exception"), RuleError);
}
