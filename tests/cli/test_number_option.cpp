#include <doctest/doctest.h>

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "granular/errors.hpp"
#include "number_option.hpp"

using granular::InvalidArgument;
using granular::cli::NumberRange;
using granular::cli::parse_whole_number;

namespace {

std::string error_of(const char* name, const char* text, const NumberRange& range) {
  try {
    parse_whole_number(name, text, range);
  } catch (const InvalidArgument& e) {
    return e.what();
  }
  FAIL("no InvalidArgument for " << name << " " << text);
  return {};
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("parse_whole_number accepts decimal numbers within the range") {
  const NumberRange ticks{0, 1'000'000'000'000ull, ""};
  CHECK(parse_whole_number("--ticks", "0", ticks) == 0);
  CHECK(parse_whole_number("--ticks", "1000", ticks) == 1000);
  CHECK(parse_whole_number("--ticks", "010", ticks) == 10);  // decimal, never octal
  CHECK(parse_whole_number("--ticks", "1000000000000", ticks) == 1'000'000'000'000ull);
  CHECK(parse_whole_number("--seed", "18446744073709551615", NumberRange{}) == UINT64_MAX);
}

TEST_CASE("parse_whole_number refuses negative, out-of-range and malformed numbers, naming option and value") {
  const NumberRange ticks{0, 1'000'000'000'000ull, ""};
  const std::string negative = error_of("--ticks", "-1", ticks);
  CHECK(negative.rfind("--ticks -1: must not be negative", 0) == 0);
  CHECK(contains(negative, "0 to 1000000000000"));
  CHECK(contains(error_of("--ticks", "18446744073709551616", ticks), "--ticks 18446744073709551616: is too large"));
  CHECK(contains(error_of("--ticks", "1000000000001", ticks), "is too large"));
  CHECK(contains(error_of("--seed", "18446744073709551616", NumberRange{}), "--seed 18446744073709551616: is too large"));
  CHECK(contains(error_of("--seed", "-1", NumberRange{}), "--seed -1: must not be negative"));
  for (const char* bad : {"abc", "1e6", "0x10", "+5", " 5", "5 ", "1.5", "--", "-x"})
    CHECK(contains(error_of("--size", bad, NumberRange{1, 65536, ""}), "is not a whole number"));
  CHECK(contains(error_of("--size", "", NumberRange{1, 65536, ""}), "--size needs a value"));
  const std::string zero = error_of("--size", "0", NumberRange{1, 65536, "omit --size for the scene's default N"});
  CHECK(zero == "--size 0: must be at least 1 (omit --size for the scene's default N)");
  CHECK(granular::cli::threads_range().max == std::uint64_t(granular::max_threads()));
  CHECK(contains(error_of("--threads", "100000", granular::cli::threads_range()),
                 "is too large (expected a whole number from 0 to " + std::to_string(granular::max_threads()) + ")"));
  const std::string long_value(500, '9');
  CHECK(error_of("--ticks", long_value.c_str(), ticks).size() < 200);
}

TEST_CASE("add_number_option parses through CLI11 and keeps the default when the option is absent") {
  CLI::App app;
  int size = 0;
  std::uint64_t seed = 7;
  granular::cli::add_number_option(app, "-n,--size", size, {1, 65536, ""}, "size");
  granular::cli::add_number_option(app, "--seed", seed, {}, "seed");
  std::vector<std::string> args = {"--size=42"};  // CLI11 parses a reversed argument vector
  app.parse(args);
  CHECK(size == 42);
  CHECK(seed == 7);
  std::vector<std::string> bad = {"-1", "--seed"};
  CHECK_THROWS_WITH_AS(app.parse(bad), doctest::Contains("--seed -1: must not be negative"), InvalidArgument);
}
