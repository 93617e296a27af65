#include "accuracy_plot_script.hpp"

#include <system_error>

namespace granular::cli {

std::filesystem::path accuracy_plot_script(const std::filesystem::path& program) {
  std::error_code ec;
  if (program.empty()) return GRANULAR_INSTALLED_PLOT_SCRIPT;
  const std::filesystem::path installed =
      (program.parent_path() / GRANULAR_PLOT_SCRIPT_FROM_BINDIR).lexically_normal();
  if (std::filesystem::is_regular_file(installed, ec)) return installed;
  // The source tree serves only the program built in the build tree, never an installed one.
  if (std::filesystem::equivalent(program.parent_path(), GRANULAR_CLI_BUILD_DIR, ec) &&
      std::filesystem::is_regular_file(GRANULAR_SOURCE_PLOT_SCRIPT, ec))
    return GRANULAR_SOURCE_PLOT_SCRIPT;
  return installed;
}

std::filesystem::path accuracy_plot_script() {
  std::error_code ec;
  const std::filesystem::path program = std::filesystem::read_symlink("/proc/self/exe", ec);
  return accuracy_plot_script(ec ? std::filesystem::path() : program);
}

}  // namespace granular::cli
