#include <doctest/doctest.h>

#include <CLI/CLI.hpp>
#include <string>

#include "accuracy_command.hpp"
#include "choices_text.hpp"
#include "granular/rule_presets.hpp"
#include "lut_command.hpp"
#include "run_command.hpp"

using granular::cli::choices_text;

TEST_CASE("choices_text lists names as a sentence does") {
  CHECK(choices_text({}) == "");
  CHECK(choices_text({"cpu"}) == "cpu");
  CHECK(choices_text({"cpu", "cuda"}) == "cpu or cuda");
  CHECK(choices_text({"auto", "cpu", "cuda"}) == "auto, cpu or cuda");
}

TEST_CASE("every command's --rules help lists the registry's presets") {
  CLI::App app{"granular"};
  granular::cli::add_run_command(app);
  granular::cli::add_lut_command(app);
  granular::cli::add_accuracy_command(app);
  const std::string presets = granular::cli::rule_preset_choices();
  REQUIRE(presets == choices_text(granular::rule_preset_names()));
  for (const char* command : {"run", "lut", "accuracy"}) {
    CAPTURE(command);
    CHECK(app.get_subcommand(command)->help().find(presets) != std::string::npos);
  }
}
