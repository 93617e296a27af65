/// @file main.cpp
/// `granular`: the headless command-line front end of the granular module. Every failure, a bad
/// command line and output that standard output could not take included, is one `error:` line on
/// stderr and exit status 1; --help exits 0. Under
/// mpirun only rank 0 prints the line (distributed_run.hpp), and every rank exits 1.

#include <CLI/CLI.hpp>
#include <cstdio>

#include "accuracy_command.hpp"
#include "distributed_run.hpp"
#include "export_command.hpp"
#include "granular/errors.hpp"
#include "lut_command.hpp"
#include "output_paths.hpp"
#include "run_command.hpp"
#include "signal_cleanup.hpp"

int main(int argc, char** argv) {
  granular::cli::install_signal_cleanup();
  CLI::App app{"granular: a block-cellular-automaton sand simulator"};
  app.require_subcommand(1);
  // A later option wins, so scripts can pass defaults and users override them.
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  granular::cli::add_run_command(app);
  granular::cli::add_export_command(app);
  granular::cli::add_lut_command(app);
  granular::cli::add_accuracy_command(app);
  try {
    app.parse(argc, argv);
    granular::cli::flush_standard_output();
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);  // --help
    if (granular::cli::prints_errors()) std::fprintf(stderr, "error: %s (see granular --help)\n", e.what());
    return 1;
  } catch (const granular::cli::ErrorReported& reported) {
    return reported.status;
  } catch (...) {
    if (granular::cli::prints_errors())
      std::fprintf(stderr, "error: %s\n", granular::cli::error_text(std::current_exception()).c_str());
    return 1;
  }
  return 0;
}
