#include "export_command.hpp"

#include <cstdio>
#include <memory>

#include "granular/grid_io.hpp"
#include "output_paths.hpp"
#include "scene_runner.hpp"

namespace granular::cli {

namespace {

struct ExportOptions {
  WorldOptions world;
  std::uint64_t ticks = 0;
  std::string out;
  bool no_progress = false;
};

void run(const ExportOptions& o) {
  // Everything about the output that can be wrong is found before any tick is run.
  check_grid_save_path(o.out);
  PreparedWorld p = prepare_world(o.world, kExportBytesPerCell);
  run_ticks(p, o.ticks, !o.no_progress);
  const Grid grid = p.world->read_grid();
  save_grid(grid, o.out);
  const MaterialCounts c = grid.count();
  std::printf("wrote %s: %s after %llu ticks, %llu solid, %llu granular, hash %016llx\n", o.out.c_str(),
              to_string(grid.size()).c_str(), static_cast<unsigned long long>(o.ticks),
              static_cast<unsigned long long>(c[to_cell(Material::Solid)]),
              static_cast<unsigned long long>(c[to_cell(Material::Granular)]),
              static_cast<unsigned long long>(grid.hash()));
}

}  // namespace

void add_export_command(CLI::App& app) {
  auto options = std::make_shared<ExportOptions>();
  CLI::App* cmd = app.add_subcommand("export", "run a scene for N ticks and write the grid to .raw or .vox");
  add_world_options(*cmd, options->world);
  add_ticks_option(*cmd, options->ticks, "ticks to run before writing");
  cmd->add_option("-o,--out", options->out, "output file: .raw (granular raw grid) or .vox (MagicaVoxel)")
      ->required()
      ->check(non_empty_path());
  cmd->add_flag("--no-progress", options->no_progress, "do not draw the progress bar");
  cmd->callback([options] { run(*options); });
}

}  // namespace granular::cli
