/// @file main.cpp
/// granular-sandbox: the Vulkan sandbox. Windowed (GLFW + Dear ImGui) by default; --headless
/// renders offscreen with no window for tests, screenshots and servers.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "session/headless_session.hpp"
#include "window/sandbox_app.hpp"
#include "session/sandbox_options.hpp"

int main(int argc, char** argv) {
  CLI::App app{"granular-sandbox: dig and pour sand in a Vulkan viewer"};
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  viewer::SandboxOptions options;
  viewer::add_sandbox_options(app, options);
  try {
    app.parse(argc, argv);
    viewer::validate(options);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  try {
    return options.headless ? viewer::run_headless(options) : viewer::run_windowed(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
