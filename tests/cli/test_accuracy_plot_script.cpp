#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

#include "accuracy_plot_script.hpp"

using granular::cli::accuracy_plot_script;

namespace {

/// A fresh install-like folder under the test's working directory: <root>/bin/granular is the program.
std::filesystem::path fresh_prefix(const std::string& name) {
  const std::filesystem::path root = std::filesystem::current_path() / name;
  std::filesystem::remove_all(root);
  std::filesystem::create_directories(root / "bin");
  return root;
}

}  // namespace

TEST_CASE("an installed program finds the plot script in its own prefix") {
  const std::filesystem::path prefix = fresh_prefix("plot-script-installed");
  std::filesystem::create_directories(prefix / "share/granular");
  std::ofstream(prefix / "share/granular/plot_accuracy.py") << "# the installed copy\n";
  CHECK(accuracy_plot_script(prefix / "bin/granular") == prefix / "share/granular/plot_accuracy.py");
}

TEST_CASE("an installed program without the script names its own prefix, not the source tree") {
  const std::filesystem::path prefix = fresh_prefix("plot-script-missing");
  REQUIRE(std::filesystem::is_regular_file(GRANULAR_TEST_SOURCE_PLOT_SCRIPT));
  CHECK(accuracy_plot_script(prefix / "bin/granular") == prefix / "share/granular/plot_accuracy.py");
}

TEST_CASE("the program in the build tree takes the source tree's script") {
  const std::filesystem::path program = GRANULAR_TEST_CLI_PROGRAM;
  REQUIRE_FALSE(std::filesystem::exists(program.parent_path() / "../share/granular/plot_accuracy.py"));
  CHECK(accuracy_plot_script(program) == std::filesystem::path(GRANULAR_TEST_SOURCE_PLOT_SCRIPT));
}
