#include "run_command.hpp"

#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "granular/hex.hpp"
#include "granular/lut.hpp"
#include "granular/rule_set.hpp"
#include "granular/scene.hpp"
#include "granular/time_scale.hpp"
#include "granular/world_snapshot.hpp"
#include "scene_runner.hpp"

namespace granular::cli {

namespace {

struct RunOptions {
  WorldOptions world;
  std::uint64_t ticks = 1000;
  std::string save;  ///< snapshot written after the last tick ("" for none)
  bool json = false;
  bool no_progress = false;
};

nlohmann::json counts_json(const MaterialCounts& c) {
  nlohmann::json j = nlohmann::json::object();
  for (int m = 0; m < kMaterialCount; ++m)
    if (c[m] > 0) j[std::string(material_name(Material(m)))] = c[m];
  return j;
}

void run(const RunOptions& o) {
  // Everything about the snapshot to write that can be wrong is found before any tick is run.
  if (!o.save.empty()) check_snapshot_save_path(o.save);
  PreparedWorld p = prepare_world(o.world, o.save.empty() ? kRunBytesPerCell : kSaveBytesPerCell);
  World& w = *p.world;
  const MaterialCounts before = w.count();
  const double seconds = run_ticks(p, o.ticks, !o.no_progress);
  const MaterialCounts after = w.count();
  const double cells = double(w.size().x) * w.size().y * w.size().z;
  const double rate = seconds > 0 ? cells * double(o.ticks) / seconds : 0;
  nlohmann::json s;
  s["scene"] = p.scene_name;
  s["n"] = p.n ? nlohmann::json(*p.n) : nlohmann::json(nullptr);  // null: a grid file has no N
  s["size"] = {w.size().x, w.size().y, w.size().z};
  s["cells"] = std::int64_t(cells);
  s["rules"] = w.rules().name;
  s["seed"] = w.def().seed;
  s["backend"] = w.backend_description();
  s["ticks"] = o.ticks;
  s["seconds"] = seconds;
  s["cell_updates_per_second"] = rate;
  s["ms_per_tick"] = o.ticks ? seconds * 1000.0 / double(o.ticks) : 0.0;
  // Simulated time for 5 mm cells (time_scale.hpp): >= 1 simulated second per wall second is real time.
  s["tick_seconds"] = tick_seconds(w.rules());
  s["real_time_factor"] = seconds > 0 ? tick_seconds(w.rules()) * double(o.ticks) / seconds : 0.0;
  s["lut"] = {{"seconds", w.lut_seconds()}, {"from_cache", w.lut_from_cache()}, {"hash", hex64(w.lut().content_hash())}};
  s["grains_before"] = counts_json(before);
  s["grains_after"] = counts_json(after);
  const MaterialCounts expected = counts_after_pouring(before, p.poured);
  const bool poured = p.poured != MaterialCounts{};
  s["poured"] = counts_json(p.poured);
  s["mass_conserved"] = after == expected;
  s["hash"] = hex64(w.hash());
  const ActivityStats a = w.activity();
  const double mean_cells = o.ticks ? double(p.cell_ticks) / double(o.ticks) : 0.0;
  if (p.snapshot_tick) s["from_tick"] = *p.snapshot_tick;
  s["tick"] = w.tick();
  if (!o.save.empty()) {
    save_snapshot(w.capture(), o.save);
    s["saved"] = o.save;
  }
  s["activity"] = {{"sparse", w.def().sparse},
                   {"total_bricks", a.total_bricks},
                   {"brick_size", kBrickSize},
                   {"last_tick_active_bricks", a.active_bricks},
                   {"last_tick_active_cells", a.active_cells},
                   {"mean_active_bricks_per_tick", o.ticks ? double(p.brick_ticks) / double(o.ticks) : 0.0},
                   {"mean_active_cells_per_tick", mean_cells}};
  if (o.json) {
    std::cout << s.dump(2) << "\n";
    return;
  }
  const std::string n_text = p.n              ? "N=" + std::to_string(*p.n)
                             : p.snapshot_tick ? "snapshot at tick " + std::to_string(*p.snapshot_tick)
                                               : std::string("grid file");
  std::printf("scene          %s (%s, %dx%dx%d = %.0f cells)\n", p.scene_name.c_str(), n_text.c_str(), w.size().x,
              w.size().y, w.size().z, cells);
  std::printf("rules          %s (seed %llu)\n", w.rules().name.c_str(), static_cast<unsigned long long>(w.def().seed));
  std::printf("backend        %s\n", w.backend_description().c_str());
  std::printf("table          %s in %.3f s, hash %s\n", w.lut_from_cache() ? "loaded" : "built", w.lut_seconds(),
              hex64(w.lut().content_hash()).c_str());
  std::printf("ticks          %llu in %.3f s (%.3f ms/tick)\n", static_cast<unsigned long long>(o.ticks), seconds,
              o.ticks ? seconds * 1000.0 / double(o.ticks) : 0.0);
  std::printf("cell-updates/s %.3g\n", rate);
  std::printf("stepping       %s, bricks of %d^3\n", w.def().sparse ? "sparse" : "dense (--dense)", kBrickSize);
  std::printf("active         last tick %llu of %llu bricks (%llu cells); mean %.0f cells/tick (%.2f%% of the grid)\n",
              static_cast<unsigned long long>(a.active_bricks), static_cast<unsigned long long>(a.total_bricks),
              static_cast<unsigned long long>(a.active_cells), mean_cells, cells > 0 ? 100.0 * mean_cells / cells : 0.0);
  std::printf("%-14s %14s %14s%s\n", "material", "before", "after", poured ? "         poured" : "");
  for (int m = 0; m < kMaterialCount; ++m)
    if (before[m] || after[m]) {
      std::printf("%-14s %14llu %14llu", std::string(material_name(Material(m))).c_str(),
                  static_cast<unsigned long long>(before[m]), static_cast<unsigned long long>(after[m]));
      if (poured) std::printf(" %14llu", static_cast<unsigned long long>(p.poured[m]));
      std::printf("\n");
    }
  std::printf("mass conserved %s\n", after == expected ? (poured ? "yes (after = before + poured)" : "yes") : "NO");
  std::printf("checksum       %s\n", hex64(w.hash()).c_str());
  if (!o.save.empty())
    std::printf("saved          %s (tick %llu, hash %s)\n", o.save.c_str(), static_cast<unsigned long long>(w.tick()),
                hex64(w.hash()).c_str());
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "run a scene headless and print a summary");
  add_world_options(*cmd, options->world);
  add_ticks_option(*cmd, options->ticks, "ticks to run");
  cmd->add_option("--save", options->save,
                  "write a snapshot (.gsnap) of the world after the last tick, which `run --scene FILE` continues");
  cmd->add_flag("--json", options->json, "print the summary as JSON");
  cmd->add_flag("--no-progress", options->no_progress, "do not draw the progress bar");
  cmd->callback([options] { run(*options); });
}

}  // namespace granular::cli
