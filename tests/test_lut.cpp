#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

#include "granular/errors.hpp"
#include "granular/extend/lut.hpp"
#include "granular/rule_presets.hpp"

using namespace granular;

namespace {

constexpr std::uint8_t V = 0, S = 1, G = 2, L = 3, A = 4, R = 5;  // void, solid, sand, liquid, gas, gravel

BlockCells after(const BlockCells& cells) {
  return apply_transition(cells, paper_transition(cells, default_materials()));
}

std::filesystem::path fresh_dir(const char* name) {
  auto dir = std::filesystem::temp_directory_path() / ("granular-test-" + std::string(name) + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

Transition moves_solid(const BlockCells& cells, const MaterialTable&) {
  // Swaps cells 0 and 1 whatever they hold: moves solid whenever one of them is solid.
  return cells[0] == cells[1] ? kIdentityTransition : (kIdentityTransition & ~077u) | 001u;  // cell 0 -> 1, cell 1 -> 0
}

Transition not_a_permutation(const BlockCells&, const MaterialTable&) { return 0; }

}  // namespace

TEST_CASE("lut: every one of the 16,777,216 entries is a permutation that conserves materials and keeps solid") {
  const auto rules = make_rule_set("paper");
  const LutObtained got = obtain_lut(*rules);
  const Lut& lut = *got.lut;
  REQUIRE(lut.entries().size() == 16777216u);
  std::uint64_t bad_permutation = 0, bad_mass = 0, moved_solid = 0, moving = 0;
  for (BlockKey key = 0; key < kBlockKeyCount; ++key) {
    const Transition t = lut[key];
    unsigned seen = 0;
    for (int i = 0; i < 8; ++i) seen |= 1u << ((t >> (3 * i)) & 7u);
    if (seen != 0xFFu || (t >> 24) != 0) {
      ++bad_permutation;
      continue;
    }
    const BlockCells in = decode_key(key), out = apply_transition(in, t);
    int count_in[8] = {}, count_out[8] = {};
    for (int i = 0; i < 8; ++i) {
      ++count_in[in[i]];
      ++count_out[out[i]];
      if (in[i] == S && out[i] != S) ++moved_solid;
    }
    for (int m = 0; m < 8; ++m) bad_mass += count_in[m] != count_out[m];
    moving += t != kIdentityTransition;
  }
  CHECK(bad_permutation == 0);
  CHECK(bad_mass == 0);
  CHECK(moved_solid == 0);
  CHECK(moving == lut.moving_keys());
  CHECK(moving > 0);
}

TEST_CASE("lut: the paper's rules: gravity first, then flow into a clear diagonal") {
  SUBCASE("a grain above void falls") {
    const BlockCells out = after({V, V, V, V, G, V, V, V});
    CHECK(out == BlockCells{G, V, V, V, V, V, V, V});
  }
  SUBCASE("a grain on a grain topples sideways when the column beside it is empty") {
    const BlockCells out = after({G, V, S, S, G, V, S, S});
    CHECK(out == BlockCells{G, G, S, S, V, V, S, S});
  }
  SUBCASE("a grain on a grain stays when every neighbouring bottom cell is full") {
    const BlockCells in{G, S, G, S, G, V, V, V};
    CHECK(after(in) == in);
  }
  SUBCASE("grains above void all fall before any topples") {
    const BlockCells in{G, V, V, V, G, G, G, G};
    CHECK(after(in) == BlockCells{G, G, G, G, G, V, V, V});
  }
  SUBCASE("a grain cannot pass when the cell above the target is occupied") {
    const BlockCells in{S, V, S, S, G, S, S, S};
    CHECK(after(in) == in);
  }
  SUBCASE("solid never falls") {
    const BlockCells in{V, V, V, V, S, S, S, S};
    CHECK(after(in) == in);
  }
  SUBCASE("the presets' static states 6 and 7 are obstacles") {
    const BlockCells in{6, 7, 6, 7, G, G, G, G};
    CHECK(after(in) == in);
  }
}

TEST_CASE("lut: the paper's rules move liquid, gas and gravel by the material table") {
  SUBCASE("a liquid above void falls") {
    CHECK(after({V, V, V, V, L, V, V, V}) == BlockCells{L, V, V, V, V, V, V, V});
  }
  SUBCASE("a liquid standing on liquid spreads sideways into void") {
    CHECK(after({L, L, S, S, L, V, S, S}) == BlockCells{L, L, S, S, V, L, S, S});
  }
  SUBCASE("a liquid on a floor stays: a pool spreads to one layer and stops") {
    const BlockCells in{S, S, S, S, L, V, V, V};
    CHECK(after(in) == in);
  }
  SUBCASE("sand sinks through liquid, and a liquid falls through gas") {
    CHECK(after({L, S, S, S, G, S, S, S}) == BlockCells{G, S, S, S, L, S, S, S});
    CHECK(after({A, S, S, S, L, S, S, S}) == BlockCells{L, S, S, S, A, S, S, S});
  }
  SUBCASE("gas rises through void, and spreads under gas") {
    CHECK(after({A, S, S, S, V, S, S, S}) == BlockCells{V, S, S, S, A, S, S, S});
    CHECK(after({A, V, S, S, A, S, S, S}) == BlockCells{V, A, S, S, A, S, S, S});
  }
  SUBCASE("gas under a ceiling rises around its edge, and stays under a closed one") {
    CHECK(after({A, V, S, S, S, V, S, S}) == BlockCells{V, V, S, S, S, A, S, S});
    const BlockCells cup{A, S, S, S, S, S, S, S};
    CHECK(after(cup) == cup);
  }
  SUBCASE("gravel on sand at rest stays: grains pass each other only while they move") {
    const BlockCells in{G, S, S, S, R, S, S, S};
    CHECK(after(in) == in);
  }
}

TEST_CASE("lut: a rule that moves solid or is no permutation is rejected with the key") {
  RuleSet bad = preset("paper");
  bad.name = "moves-solid";
  bad.transition = &moves_solid;
  try {
    (void)Lut::build(bad, 2);
    FAIL("expected RuleError");
  } catch (const RuleError& e) {
    const std::string msg = e.what();
    CHECK(msg.find("moves-solid") != std::string::npos);
    CHECK(msg.find("moves the fixed (static) cell") != std::string::npos);
  }
  bad.name = "not-a-permutation";
  bad.transition = &not_a_permutation;
  CHECK_THROWS_WITH_AS((void)Lut::build(bad, 2), doctest::Contains("is not a permutation"), RuleError);
}

TEST_CASE("lut: cached on disk by rule fingerprint, a corrupt cache is rebuilt, never trusted") {
  const auto dir = fresh_dir("lut-cache");
  const auto rules = make_rule_set("paper");
  LutCacheOptions options;
  options.directory = dir;
  const LutObtained first = obtain_lut(*rules, options);
  CHECK_FALSE(first.from_cache);
  REQUIRE(std::filesystem::exists(first.cache_file));
  const LutObtained second = obtain_lut(*rules, options);
  CHECK(second.from_cache);
  CHECK(second.lut->content_hash() == first.lut->content_hash());

  // Flip bytes in the middle of the compressed body.
  {
    std::fstream f(first.cache_file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(200);
    const char junk[16] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
    f.write(junk, sizeof junk);
  }
  const LutObtained third = obtain_lut(*rules, options);
  CHECK_FALSE(third.from_cache);
  CHECK(third.notice.find("ignored") != std::string::npos);
  CHECK(third.lut->content_hash() == first.lut->content_hash());
  std::filesystem::remove_all(dir);
}

TEST_CASE("lut: the fingerprint follows the rule's behaviour, name, version and flags") {
  const auto paper = make_rule_set("paper");
  const auto isotropic = make_rule_set("isotropic");
  CHECK(rule_fingerprint(*paper) == rule_fingerprint(*make_rule_set("paper")));
  CHECK(rule_fingerprint(*paper) != rule_fingerprint(*isotropic));
  RuleSet bumped = *paper;
  bumped.version += 1;
  CHECK(rule_fingerprint(bumped) != rule_fingerprint(*paper));
  RuleSet changed = *paper;
  changed.transition = &moves_solid;
  CHECK(rule_fingerprint(changed) != rule_fingerprint(*paper));
  RuleSet renamed = *paper;
  renamed.materials[5].name = "pebbles";
  CHECK(rule_fingerprint(renamed) != rule_fingerprint(*paper));
  RuleSet grain = *paper;
  grain.materials[2].grain.roll_cost = 7;
  CHECK(rule_fingerprint(grain) != rule_fingerprint(*paper));
  RuleSet heavier = *paper;
  heavier.materials[3].density = 5;
  CHECK(rule_fingerprint(heavier) != rule_fingerprint(*paper));
  RuleSet slower = *paper;
  slower.materials[3].spread = 64;
  CHECK(rule_fingerprint(slower) != rule_fingerprint(*paper));
  CHECK_THROWS_AS(make_rule_set("no-such-rules"), InvalidArgument);
  CHECK_THROWS_WITH(make_rule_set("no-such-rules"), doctest::Contains("paper, isotropic"));
}
