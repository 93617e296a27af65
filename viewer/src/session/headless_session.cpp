#include "session/headless_session.hpp"

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>

#include "session/camera.hpp"
#include "session/content_framing.hpp"
#include "granular/engine/clock.hpp"
#include "granular/engine/engine_loop.hpp"
#include "granular/engine/granular_subsystem.hpp"
#include "granular/world_snapshot.hpp"
#include "renderers/offscreen_renderer.hpp"
#include "session/png_writer.hpp"
#include "session/render_subsystem.hpp"
#include "renderers/renderer_choice.hpp"
#include "renderers/renderer_factory.hpp"
#include "session/sandbox_tools.hpp"
#include "vulkan/shader_loader.hpp"
#include "cells/shared_cells.hpp"
#include "vulkan/vulkan_context.hpp"
#include "session/world_files.hpp"

namespace viewer {

int run_headless(const SandboxOptions& options) {
  const WorldChoice choice = start_choice(options);
  SandboxWorld sandbox = load_world(choice);
  granular::World& world = *sandbox.world;
  const std::uint64_t first_tick = world.tick();  // a snapshot's
  if (granular::is_snapshot_file(choice.scene)) std::printf("%s\n", loaded_line(world, choice.scene).c_str());
  ContextOptions context_options;
  context_options.validation = options.validation;
  const std::optional<ContextOptions> interop = options.no_interop ? std::nullopt : interop_context(world, context_options);
  VulkanContext context(interop.value_or(context_options));
  std::unique_ptr<SharedCells> shared;
  if (interop) shared = std::make_unique<SharedCells>(context, world);
  const OrbitCamera camera = initial_camera(options.camera, world, float(options.width) / float(options.height));
  const bool automatic = options.renderer == "auto";
  RendererChoice renderer_choice;
  RendererKind kind = automatic ? renderer_choice.first() : *parse_renderer_kind(options.renderer);
  OffscreenRenderer offscreen(context, world,
                              {std::uint32_t(options.width), std::uint32_t(options.height)}, kind, shared.get(),
                              options.detail);
  offscreen.world_renderer().set_see_inside(options.inside);

  // One fixed update per frame: the manual clock advances exactly one tick length per frame.
  granular::engine::ManualClock clock;
  granular::engine::EngineLoop loop(clock);
  ToolSubsystem tools(world, sandbox.emitters);
  granular::engine::GranularSubsystem simulation(world, options.ticks_per_frame);
  RenderSubsystem render([&] { offscreen.render(camera); });
  loop.add(tools);
  loop.add(simulation);
  loop.add(render);
  const int frames = headless_frames(options);
  for (int frame = 0; frame < frames; ++frame) {
    const auto start = std::chrono::steady_clock::now();
    loop.run_frame();
    clock.advance(loop.timestep().tick_seconds());
    if (automatic && renderer_choice.measuring()) {
      // The choice measures the frames as drawn here, back to back (two in flight).
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (const auto now = renderer_choice.advance(
              seconds, [&](RendererKind next) { offscreen.set_kind(next); },
              [](const std::string& line) { std::printf("%s\n", line.c_str()); }))
        kind = *now;
      if (!renderer_choice.measuring()) offscreen.world_renderer().release_inactive();
    }
  }
  if (!options.save.empty()) std::printf("%s\n", save_world(world, options.save).c_str());
  const GpuTimings gpu = offscreen.last_timings();
  if (!options.screenshot.empty()) {
    write_png(options.screenshot, offscreen.extent().width, offscreen.extent().height, offscreen.pixels());
  }
  offscreen.wait_idle();
  const std::uint64_t ticks = world.tick() - first_tick;
  const double ms_per_tick = ticks ? simulation.total_step_seconds() * 1e3 / double(ticks) : 0.0;
  std::printf("device         %s\n", context.device_name().c_str());
  std::printf("shaders        %s\n", shader_dir().string().c_str());
  std::printf("scene          %s (N=%d), backend %s\n", sandbox.scene_name.c_str(), sandbox.n, world.backend_description().c_str());
  std::printf("renderer       %s%s, %dx%d\n", to_string(kind), automatic ? " (auto)" : "", options.width, options.height);
  std::printf("see inside     section %s, x-ray %s\n", options.inside.section.describe().c_str(), options.inside.xray ? "on" : "off");
  std::printf("cells          %s\n", shared ? (shared->dedicated() ? "shared with CUDA (dedicated allocation)" : "shared with CUDA")
                                             : "uploaded through staging (changed bricks)");
  std::printf("frames         %d, ticks %llu (%.3f ms/tick)\n", frames, static_cast<unsigned long long>(ticks), ms_per_tick);
  std::printf("last frame gpu upload %.3f ms, build %.3f ms, draw %.3f ms\n", gpu.upload_ms, gpu.build_ms, gpu.draw_ms);
  if (!options.screenshot.empty()) std::printf("screenshot     %s\n", options.screenshot.c_str());
  std::printf("validation     %s, %llu messages\n", options.validation ? "on" : "off",
              static_cast<unsigned long long>(context.validation_messages()));
  const std::uint64_t messages = context.validation_messages();
  sandbox.world.reset();  // the world stops using the shared memory before it is freed
  return messages == 0 ? 0 : 1;
}

}  // namespace viewer
