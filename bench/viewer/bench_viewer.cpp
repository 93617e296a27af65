/// @file bench_viewer.cpp
/// bench_viewer: simulation + rendering frames per second of each renderer, offscreen, and where
/// the frame time goes: simulation (host timer around World::step), recording (host: reading the
/// changed bricks into staging and recording commands), and on the GPU (timestamp queries) the
/// upload, the build pass (instance build / meshing / ray march) and the render pass. The GPU works
/// on frame i while the host simulates frame i+1 (two frames in flight). A first row, "sim-only",
/// times the simulation alone (the device time of the asynchronous CUDA step is not visible to the
/// host timers of the rendered rows). Prints a table and appends CSV rows.
///
///   bench_viewer --size 512 --ticks-per-frame 4 --frames 200 --csv bench/viewer_results.csv
///   bench_viewer --size 1024 --real-time --frames 200   (the sandbox's rate: one tick per tick of wall time)

#include <cstdint>
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include "session/camera.hpp"
#include "granular/external_memory.hpp"
#include "granular/scene.hpp"
#include "granular/time_scale.hpp"
#include "renderers/offscreen_renderer.hpp"
#include "renderers/renderer_factory.hpp"
#include "session/scene_loader.hpp"
#include "cells/shared_cells.hpp"
#include "vulkan/vulkan_context.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

struct Row {
  std::string renderer;
  double fps = 0, frame_ms = 0, sim_ms = 0, record_ms = 0, upload_ms = 0, build_ms = 0, draw_ms = 0;
  double bricks_rebuilt = 0;
  double ticks_per_frame = 0;  ///< ticks stepped per measured frame (a mean with --real-time)
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bench_viewer: offscreen frames per second of the sandbox's renderers"};
  viewer::WorldChoice choice;
  choice.size = 256;
  int width = 1920, height = 1080, ticks = 4, frames = 120, warmup = 10;
  std::uint64_t skip_ticks = 0;
  std::string renderers = "cubes,marching,raymarch", csv, camera_text;
  bool validation = false, no_interop = false, real_time = false;
  viewer::RenderDetail detail;
  app.add_option("--scene", choice.scene, "scene");
  app.add_option("--size", choice.size, "scene size parameter N");
  app.add_option("--backend", choice.backend, "auto, cpu or cuda");
  app.add_option("--rules", choice.rules, "rule-set preset (default: the library's, " + choice.rules + ")");
  app.add_option("--threads", choice.threads, "CPU threads (0: all)");
  app.add_option("--width", width, "image width");
  app.add_option("--height", height, "image height");
  app.add_option("--ticks-per-frame", ticks, "world ticks per frame (0: render only, nothing changes)");
  app.add_option("--frames", frames, "measured frames per renderer");
  app.add_option("--warmup", warmup, "frames before measuring (the first one builds everything)");
  app.add_option("--skip-ticks", skip_ticks, "ticks simulated before the first frame (e.g. to measure a settled scene)");
  app.add_option("--renderers", renderers, "comma-separated: cubes, marching, raymarch");
  app.add_option("--camera", camera_text, "yaw,pitch,distance[,tx,ty,tz]");
  app.add_option("--coarse-below", detail.coarse_below_pixels,
                 "marching cubes meshes a brick at half resolution where its cells cover fewer pixels than this (0: never)")
      ->check(CLI::Range(0.0f, 1000.0f));
  app.add_option("--csv", csv, "append CSV rows to this file");
  app.add_flag("--validation", validation, "Vulkan validation layers (slow; for checking, not timing)");
  app.add_flag("--no-interop", no_interop, "with --backend cuda: upload through the host instead of sharing the cells");
  app.add_flag("--real-time", real_time,
               "step the ticks the wall clock owes before each frame (the sandbox's rate: one tick per "
               "granular::tick_seconds of the rules), at most --ticks-per-frame of them (default 4 then)");
  try {
    app.parse(argc, argv);
    if (ticks < 0 || frames < 1 || warmup < 0) throw std::invalid_argument("--ticks-per-frame >= 0, --frames >= 1, --warmup >= 0");
    if (real_time && ticks < 1) throw std::invalid_argument("--real-time needs --ticks-per-frame >= 1 (the most ticks a frame may step)");
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  try {
    viewer::ContextOptions context_options;
    context_options.validation = validation;
    // CUDA interop (shared cells) whenever the CUDA backend will be used, unless --no-interop.
    if (!no_interop && choice.backend != "cpu")
      if (const auto uuid = granular::cuda_device_uuid()) {
        context_options.external_memory = true;
        context_options.device_uuid = *uuid;
      }
    viewer::VulkanContext context(context_options);
    std::string cells_path = "upload";
    std::vector<Row> rows;
    std::string backend;
    if (ticks > 0 && !real_time) {
      // The simulation alone (no rendering): on the CUDA backend step() is asynchronous, so the
      // host timers of the rendered runs do not show its device time; this row does.
      viewer::SandboxWorld sandbox = viewer::load_world(choice);
      if (skip_ticks) sandbox.world->step(int(skip_ticks));
      for (int frame = 0; frame < warmup; ++frame) sandbox.world->step(ticks);
      (void)sandbox.world->hash();  // waits for the device
      const auto start = Clock::now();
      for (int frame = 0; frame < frames; ++frame) sandbox.world->step(ticks);
      (void)sandbox.world->hash();
      Row row;
      row.renderer = "sim-only";
      row.frame_ms = ms_since(start) / frames;
      row.fps = 1000.0 / row.frame_ms;
      row.sim_ms = row.frame_ms;
      row.ticks_per_frame = ticks;
      rows.push_back(row);
    }
    std::stringstream list(renderers);
    std::string name;
    while (std::getline(list, name, ',')) {
      const auto kind = viewer::parse_renderer_kind(name);
      if (!kind) throw std::invalid_argument("--renderers: unknown renderer '" + name + "'");
      std::unique_ptr<viewer::SharedCells> shared;  // declared before the world: destroyed after it
      viewer::SandboxWorld sandbox = viewer::load_world(choice);
      granular::World& world = *sandbox.world;
      if (skip_ticks) world.step(int(skip_ticks));
      backend = world.backend_description();
      if (context.external_memory() && world.backend() == granular::BackendKind::Cuda) {
        shared = std::make_unique<viewer::SharedCells>(context, world);
        cells_path = "interop";
      }
      const viewer::OrbitCamera camera = camera_text.empty() ? viewer::OrbitCamera::framing(world.size())
                                                             : viewer::OrbitCamera::parse(camera_text, world.size());
      viewer::OffscreenRenderer renderer(context, world, {std::uint32_t(width), std::uint32_t(height)}, *kind, shared.get(),
                                         detail);
      Row row;
      row.renderer = name;
      // The ticks a frame steps: `ticks`, or with --real-time those the wall clock owes since
      // `clock_start` (at most `ticks`; the rest is dropped, as the sandbox drops it).
      const double tick_ms = 1000.0 * granular::tick_seconds(world.rules());
      Clock::time_point clock_start = Clock::now();
      std::uint64_t ticks_owed_done = 0, ticks_stepped = 0;
      auto frame_ticks = [&] {
        if (!real_time) return ticks;
        const auto owed = std::uint64_t(ms_since(clock_start) / tick_ms);
        const std::uint64_t due = owed > ticks_owed_done ? owed - ticks_owed_done : 0;
        ticks_owed_done = owed;
        return int(std::min<std::uint64_t>(due, std::uint64_t(ticks)));
      };
      for (int frame = 0; frame < warmup; ++frame) {
        if (const int k = frame_ticks()) world.step(k);
        renderer.render(camera);
      }
      renderer.wait_idle();
      renderer.take_finished_timings();
      double sim_ms = 0, record_ms = 0, rebuilt = 0;
      const auto start = Clock::now();
      clock_start = start;
      ticks_owed_done = 0;
      for (int frame = 0; frame < frames; ++frame) {
        const auto sim_start = Clock::now();
        if (const int k = frame_ticks()) {
          world.step(k);
          ticks_stepped += std::uint64_t(k);
        }
        sim_ms += ms_since(sim_start);
        const auto record_start = Clock::now();
        rebuilt += double(renderer.render(camera).bricks_rebuilt);
        record_ms += ms_since(record_start);
      }
      renderer.wait_idle();
      const double total_ms = ms_since(start);
      renderer.render(camera);  // collects the timings of the last measured frames
      renderer.wait_idle();
      std::vector<viewer::GpuTimings> gpu = renderer.take_finished_timings();
      if (gpu.size() > std::size_t(frames)) gpu.resize(std::size_t(frames));
      const double n = double(std::max<std::size_t>(1, gpu.size()));
      for (const auto& t : gpu) {
        row.upload_ms += t.upload_ms / n;
        row.build_ms += t.build_ms / n;
        row.draw_ms += t.draw_ms / n;
      }
      row.frame_ms = total_ms / frames;
      row.fps = 1000.0 / row.frame_ms;
      row.sim_ms = sim_ms / frames;
      row.record_ms = record_ms / frames;
      row.bricks_rebuilt = rebuilt / frames;
      row.ticks_per_frame = real_time ? double(ticks_stepped) / frames : ticks;
      rows.push_back(row);
    }
    const std::string rate = real_time ? "real time (at most " + std::to_string(ticks) + " ticks/frame)"
                                       : std::to_string(ticks) + " ticks/frame";
    std::printf("device %s, backend %s, cells %s, rules %s, scene %s N=%d, %dx%d, %s, %d frames after tick %llu, "
                "marching coarse below %g px\n",
                context.device_name().c_str(), backend.c_str(), cells_path.c_str(), choice.rules.c_str(), choice.scene.c_str(),
                choice.size, width, height, rate.c_str(), frames, static_cast<unsigned long long>(skip_ticks),
                double(detail.coarse_below_pixels));
    std::printf("%-9s %8s %9s %8s %9s %10s %9s %8s %9s %7s\n", "renderer", "fps", "frame_ms", "sim_ms", "record_ms",
                "upload_ms", "build_ms", "draw_ms", "rebuilt", "ticks");
    for (const Row& r : rows)
      std::printf("%-9s %8.1f %9.2f %8.2f %9.2f %10.2f %9.2f %8.2f %9.0f %7.2f\n", r.renderer.c_str(), r.fps, r.frame_ms,
                  r.sim_ms, r.record_ms, r.upload_ms, r.build_ms, r.draw_ms, r.bricks_rebuilt, r.ticks_per_frame);
    if (!csv.empty()) {
      const bool fresh = !std::ifstream(csv).good();
      std::ofstream out(csv, std::ios::app);
      if (!out) throw std::runtime_error("cannot write " + csv);
      if (fresh)
        out << "device,backend,cells,rules,scene,n,width,height,ticks_per_frame,skip_ticks,frames,renderer,fps,frame_ms,sim_ms,record_ms,gpu_upload_ms,"
               "gpu_build_ms,gpu_draw_ms,bricks_rebuilt_per_frame,ticks_stepped_per_frame,coarse_below_px\n";
      for (const Row& r : rows)
        out << '"' << context.device_name() << "\",\"" << backend << "\"," << cells_path << ',' << choice.rules << ',' << choice.scene << ',' << choice.size << ','
            << width << ',' << height << ',' << ticks << ',' << skip_ticks << ',' << frames << ',' << r.renderer << ',' << r.fps << ',' << r.frame_ms << ','
            << r.sim_ms << ',' << r.record_ms << ',' << r.upload_ms << ',' << r.build_ms << ',' << r.draw_ms << ','
            << r.bricks_rebuilt << ',' << r.ticks_per_frame << ',' << detail.coarse_below_pixels << '\n';
    }
    if (validation && context.validation_messages()) {
      std::fprintf(stderr, "error: %llu validation messages\n", static_cast<unsigned long long>(context.validation_messages()));
      return 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
