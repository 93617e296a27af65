#include "run_command.hpp"

#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "distributed_run.hpp"
#include "json_text.hpp"
#include "output_paths.hpp"
#include "granular/extend/hex.hpp"
#include "granular/extend/lut.hpp"
#include "granular/rule_set.hpp"
#include "granular/scene.hpp"
#include "granular/time_scale.hpp"
#include "granular/world_snapshot.hpp"

namespace granular::cli {

namespace {

nlohmann::json counts_json(const MaterialCounts& c) {
  nlohmann::json j = nlohmann::json::object();
  for (int m = 0; m < kMaterialCount; ++m)
    if (c[m] > 0) j[std::string(material_name(Material(m)))] = c[m];
  return j;
}

/// "26, 26, 25" layers of the slabs.
std::string slab_heights(const SplitSummary& split) {
  std::string text;
  for (const auto& s : split.slabs) text += (text.empty() ? "" : ", ") + std::to_string(s[1] - s[0]);
  return text;
}

void print_json(const RunSummary& r) {
  const double cells = double(r.size.x) * r.size.y * r.size.z;
  const double rate = r.seconds > 0 ? cells * double(r.ticks) / r.seconds : 0;
  nlohmann::json s;
  s["scene"] = r.scene_name;
  s["n"] = r.n ? nlohmann::json(*r.n) : nlohmann::json(nullptr);  // null: a grid file has no N
  s["size"] = {r.size.x, r.size.y, r.size.z};
  s["cells"] = std::int64_t(cells);
  s["rules"] = r.rules;
  s["seed"] = r.seed;
  s["backend"] = r.backend;
  s["ticks"] = r.ticks;
  s["seconds"] = r.seconds;
  s["cell_updates_per_second"] = rate;
  s["ms_per_tick"] = r.ticks ? r.seconds * 1000.0 / double(r.ticks) : 0.0;
  // Simulated time for 5 mm cells (time_scale.hpp): >= 1 simulated second per wall second is real time.
  s["tick_seconds"] = r.tick_seconds;
  s["real_time_factor"] = r.seconds > 0 ? r.tick_seconds * double(r.ticks) / r.seconds : 0.0;
  s["lut"] = {{"seconds", r.lut_seconds}, {"from_cache", r.lut_from_cache}, {"hash", hex64(r.lut_hash)}};
  s["grains_before"] = counts_json(r.before);
  s["grains_after"] = counts_json(r.after);
  s["poured"] = counts_json(r.poured);
  s["mass_conserved"] = r.after == counts_after_pouring(r.before, r.poured);
  s["hash"] = hex64(r.hash);
  if (r.snapshot_tick) s["from_tick"] = *r.snapshot_tick;
  s["tick"] = r.tick;
  if (!r.saved.empty()) s["saved"] = r.saved;
  if (r.activity) {
    const ActivitySummary& a = *r.activity;
    s["activity"] = {{"sparse", r.sparse},
                     {"total_bricks", a.last.total_bricks},
                     {"brick_size", kBrickSize},
                     {"last_tick_active_bricks", a.last.active_bricks},
                     {"last_tick_active_cells", a.last.active_cells},
                     {"mean_active_bricks_per_tick", r.ticks ? double(a.brick_ticks) / double(r.ticks) : 0.0},
                     {"mean_active_cells_per_tick", r.ticks ? double(a.cell_ticks) / double(r.ticks) : 0.0}};
  }
  if (r.split) {
    const SplitSummary& d = *r.split;
    s["split"] = {{"transport", d.transport},
                  {"ranks", d.slabs.size()},
                  {"halo", d.halo},
                  {"slabs", d.slabs},
                  {"exchange_seconds", d.exchange_seconds},
                  {"exchange_bytes", d.exchange_bytes}};
  }
  std::cout << json_text(s);
}

void print_text(const RunSummary& r) {
  const double cells = double(r.size.x) * r.size.y * r.size.z;
  const double rate = r.seconds > 0 ? cells * double(r.ticks) / r.seconds : 0;
  const std::string n_text = r.n              ? "N=" + std::to_string(*r.n)
                             : r.snapshot_tick ? "snapshot at tick " + std::to_string(*r.snapshot_tick)
                                               : std::string("grid file");
  std::printf("scene          %s (%s, %dx%dx%d = %.0f cells)\n", r.scene_name.c_str(), n_text.c_str(), r.size.x,
              r.size.y, r.size.z, cells);
  std::printf("rules          %s (seed %llu)\n", r.rules.c_str(), static_cast<unsigned long long>(r.seed));
  std::printf("backend        %s%s\n", r.backend.c_str(), r.split ? " per rank" : "");
  if (r.split)
    std::printf("split          %s: z-slabs of %s layers, halo %d\n", r.split->transport.c_str(),
                slab_heights(*r.split).c_str(), r.split->halo);
  std::printf("table          %s in %.3f s, hash %s\n", r.lut_from_cache ? "loaded" : "built", r.lut_seconds,
              hex64(r.lut_hash).c_str());
  std::printf("ticks          %llu in %.3f s (%.3f ms/tick)\n", static_cast<unsigned long long>(r.ticks), r.seconds,
              r.ticks ? r.seconds * 1000.0 / double(r.ticks) : 0.0);
  std::printf("cell-updates/s %.3g\n", rate);
  if (r.split) {
    double slowest = 0, sum = 0;
    for (const double s : r.split->exchange_seconds) {
      slowest = std::max(slowest, s);
      sum += s;
    }
    const double mean = r.split->exchange_seconds.empty() ? 0 : sum / double(r.split->exchange_seconds.size());
    std::printf("exchange       %.3f s (slowest rank; mean %.3f s), %.2f MiB sent\n", slowest, mean,
                double(r.split->exchange_bytes) / (1024.0 * 1024.0));
  }
  std::printf("stepping       %s, bricks of %d^3\n", r.sparse ? "sparse" : "dense (--dense)", kBrickSize);
  if (r.activity) {
    const ActivitySummary& a = *r.activity;
    const double mean_cells = r.ticks ? double(a.cell_ticks) / double(r.ticks) : 0.0;
    std::printf("active         last tick %llu of %llu bricks (%llu cells); mean %.0f cells/tick (%.2f%% of the grid)\n",
                static_cast<unsigned long long>(a.last.active_bricks), static_cast<unsigned long long>(a.last.total_bricks),
                static_cast<unsigned long long>(a.last.active_cells), mean_cells,
                cells > 0 ? 100.0 * mean_cells / cells : 0.0);
  }
  const bool poured = r.poured != MaterialCounts{};
  std::printf("%-14s %14s %14s%s\n", "material", "before", "after", poured ? "         poured" : "");
  for (int m = 0; m < kMaterialCount; ++m)
    if (r.before[m] || r.after[m]) {
      std::printf("%-14s %14llu %14llu", std::string(material_name(Material(m))).c_str(),
                  static_cast<unsigned long long>(r.before[m]), static_cast<unsigned long long>(r.after[m]));
      if (poured) std::printf(" %14llu", static_cast<unsigned long long>(r.poured[m]));
      std::printf("\n");
    }
  const bool conserved = r.after == counts_after_pouring(r.before, r.poured);
  std::printf("mass conserved %s\n", conserved ? (poured ? "yes (after = before + poured)" : "yes") : "NO");
  std::printf("checksum       %s\n", hex64(r.hash).c_str());
  if (!r.saved.empty())
    std::printf("saved          %s (tick %llu, hash %s)\n", r.saved.c_str(), static_cast<unsigned long long>(r.tick),
                hex64(r.hash).c_str());
}

void run(const RunOptions& o) {
  if (run_split_if_asked(o)) return;
  // Everything about the snapshot to write that can be wrong is found before any tick is run.
  if (!o.save.empty()) check_snapshot_save_path(o.save);
  PreparedWorld p = prepare_world(o.world, o.save.empty() ? kRunBytesPerCell : kSaveBytesPerCell);
  World& w = *p.world;
  RunSummary r;
  r.before = w.count();
  r.seconds = run_ticks(p, o.ticks, !o.no_progress);
  r.after = w.count();
  r.scene_name = p.scene_name;
  r.n = p.n;
  r.snapshot_tick = p.snapshot_tick;
  r.size = w.size();
  describe_world(r, w);
  r.ticks = o.ticks;
  r.poured = p.poured;
  r.hash = w.hash();
  r.tick = w.tick();
  r.activity = ActivitySummary{w.activity(), p.brick_ticks, p.cell_ticks};
  if (!o.save.empty()) {
    save_snapshot(w.capture(), o.save);
    r.saved = o.save;
  }
  print_run_summary(r, o.json);
}

}  // namespace

void describe_world(RunSummary& r, const World& w) {
  r.rules = w.rules().name;
  r.seed = w.def().seed;
  r.backend = w.backend_description();
  r.sparse = w.def().sparse;
  r.lut_seconds = w.lut_seconds();
  r.lut_from_cache = w.lut_from_cache();
  r.lut_hash = w.lut().content_hash();
  r.tick_seconds = tick_seconds(w.rules());
}

void print_run_summary(const RunSummary& summary, bool json) {
  if (json)
    print_json(summary);
  else
    print_text(summary);
}

void add_run_command(CLI::App& app) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "run a scene headless and print a summary");
  add_world_options(*cmd, options->world);
  add_ticks_option(*cmd, options->ticks, "ticks to run");
  cmd->add_option("--save", options->save,
                  "write a snapshot (.gsnap) of the world after the last tick, which `run --scene FILE` continues")
      ->check(non_empty_path());
  cmd->add_flag("--json", options->json, "print the summary as JSON");
  cmd->add_flag("--no-progress", options->no_progress, "do not draw the progress bar");
  add_split_options(*cmd, *options);
  cmd->callback([options] { run(*options); });
}

}  // namespace granular::cli
