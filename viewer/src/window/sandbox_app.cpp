#include "window/sandbox_app.hpp"

#include <cstdint>
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include "session/camera.hpp"
#include "session/content_framing.hpp"
#include "window/control_dispatch.hpp"
#include "window/controls.hpp"
#include "granular/engine/clock.hpp"
#include "granular/engine/engine_loop.hpp"
#include "granular/engine/granular_subsystem.hpp"
#include "window/glfw_window.hpp"
#include "granular/errors.hpp"
#include "granular/extend/hex.hpp"
#include "granular/raycast.hpp"
#include "granular/scene.hpp"
#include "granular/stroke_history.hpp"
#include "granular/time_scale.hpp"
#include "granular/world_snapshot.hpp"
#include "session/history_lines.hpp"
#include "window/hud.hpp"
#include "window/input_tracker.hpp"
#include "session/material_choices.hpp"
#include "window/material_panel.hpp"
#include "session/png_writer.hpp"
#include "renderers/renderer_choice.hpp"
#include "renderers/renderer_factory.hpp"
#include "vulkan/vulkan_check.hpp"
#include "session/sandbox_tools.hpp"
#include "session/screenshot_path.hpp"
#include "section/section_pick.hpp"
#include "cells/shared_cells.hpp"
#include "granular/external_memory.hpp"
#include "window/swapchain.hpp"
#include "vulkan/vulkan_context.hpp"
#include "session/world_files.hpp"
#include "renderers/world_renderer.hpp"
#ifdef GRANULAR_SANDBOX_BODIES
#include "bodies/body_throw.hpp"
#include "bodies/sandbox_bodies.hpp"
#include "window/body_panel.hpp"
#endif

namespace viewer {
namespace {

/// What a scene reset rebuilds: the world and what borrows it.
struct Session {
  std::unique_ptr<SharedCells> shared;  ///< CUDA interop; declared first so the world goes first
  SandboxWorld sandbox;
#ifdef GRANULAR_SANDBOX_BODIES
  std::unique_ptr<SandboxBodies> bodies;  ///< the thrown bodies in Bullet; steps the world (the simulation's stepper)
#endif
  std::unique_ptr<ToolSubsystem> tools;
  std::unique_ptr<granular::engine::GranularSubsystem> simulation;
  std::unique_ptr<granular::StrokeHistory> history;  ///< undo and redo of the tools' strokes
};

/// Prints one line on stdout for a user action and flushes it, so that whoever started the sandbox
/// (a user's terminal, a test) sees it at once.
[[gnu::format(printf, 1, 2)]] void report(const char* format, ...) {
  va_list args;
  va_start(args, format);
  std::vprintf(format, args);
  va_end(args);
  std::fputc('\n', stdout);
  std::fflush(stdout);
}

/// What the Tab line on stdout says the left button now does with `tool` under `rules`.
std::string left_button_description(Tool tool, const granular::RuleSet& rules) {
  switch (tool) {
    case Tool::Dig: return "dig (static materials stay)";
    case Tool::Erase: return "erase (everything, static materials included)";
    case Tool::Shake:
      return "shake (sets grains and liquids moving at motion level " + std::to_string(shake_level(rules)) + ")";
    case Tool::Pour:
    case Tool::Place: break;
  }
  return to_string(tool);
}

/// The left button's tools under `rules` in Tab's order, as the HUD lists them ("dig / erase / shake").
std::string left_button_cycle(const granular::RuleSet& rules) {
  std::string cycle;
  for (Tool tool : left_button_tools(rules)) cycle += (cycle.empty() ? "" : " / ") + std::string(to_string(tool));
  return cycle;
}

/// A mouse button held down with a tool: from its press to its release.
struct Stroke {
  int button;                       ///< GLFW_MOUSE_BUTTON_* that started it
  std::int64_t cells_at_start;      ///< ToolSubsystem::cells_changed() at the press
  std::int64_t applications_at_start;  ///< ToolSubsystem::applications() at the press
  std::uint64_t tick_at_start;      ///< World::tick() at the press
  std::uint64_t hash_at_start;      ///< World::hash() at the press: what an undo of the stroke gives back
};

/// The windowed sandbox: an engine subsystem (input and camera in update(), drawing in render())
/// next to the tools and the simulation.
class SandboxApp final : public granular::engine::Subsystem {
 public:
  explicit SandboxApp(const SandboxOptions& options)
      : granular::engine::Subsystem("sandbox"),
        options_(options),
        window_(options.width, options.height, "granular sandbox"),
        context_(context_options(options, window_)),
        swapchain_(context_, window_.framebuffer_extent()),
        input_(window_.handle()),
        hud_(context_, window_, swapchain_.target().compatible_pass(), swapchain_.min_image_count(), swapchain_.image_count()),
        kind_(options.renderer == "auto" ? automatic_renderer_.first() : *parse_renderer_kind(options.renderer)),
        inside_(options.inside),
        requested_extent_(window_.framebuffer_extent()),
        snapshot_file_(snapshot_file(options)) {
    bind_controls();
    load(start_choice(options));
    camera_ = initial_camera(options.camera, world(), aspect());
  }

  int run() {
    std::printf("device         %s\n", context_.device_name().c_str());
    std::printf("scene          %s (N=%d), backend %s\n", session_->sandbox.scene_name.c_str(), session_->sandbox.n,
                world().backend_description().c_str());
    report("materials      %s (number keys; the right button pours or paints the chosen one)", describe(offered_materials_).c_str());
    report("window         %ux%u, renderer %s; Esc or closing the window quits", swapchain_.target().extent().width,
           swapchain_.target().extent().height, to_string(kind_));
    report("snapshots      %s (Ctrl+S saves, Ctrl+O loads)", snapshot_file_.c_str());
    if (granular::is_snapshot_file(world_choice_.scene)) report("%s", loaded_line(world(), world_choice_.scene).c_str());
    std::uint64_t frames = 0;
    const double start = clock_.now_seconds();
    while (!window_.should_close()) {
      glfwPollEvents();
      loop_->run_frame();
      ++frames;
      if (screenshot_requested_) {
        screenshot_requested_ = false;
        take_screenshot();
      }
      if (options_.frames && frames >= std::uint64_t(*options_.frames)) break;
      if (pending_load_) {
        pending_load_ = false;
        const bool same_scene = world_choice_.scene == session_->sandbox.scene_name && world_choice_.size == session_->sandbox.n;
        load(world_choice_);
        report("%s %s (N=%d)", same_scene ? "reset:" : "scene:", session_->sandbox.scene_name.c_str(), session_->sandbox.n);
        if (!same_scene) camera_ = frame_content(world(), aspect());
      }
      if (!pending_file_.empty()) open_file(std::exchange(pending_file_, std::string()));
    }
    const double seconds = clock_.now_seconds() - start;
    vkDeviceWaitIdle(context_.device());
    if (!options_.save.empty()) save();
    if (!options_.screenshot.empty()) {
      write_last_frame(options_.screenshot);
      std::printf("screenshot     %s\n", options_.screenshot.c_str());
    }
    std::printf("frames         %llu in %.1f s (%.1f FPS)\n", static_cast<unsigned long long>(frames), seconds,
                seconds > 0 ? double(frames) / seconds : 0.0);
    std::printf("validation     %s, %llu messages\n", options_.validation ? "on" : "off",
                static_cast<unsigned long long>(context_.validation_messages()));
    return context_.validation_messages() == 0 ? 0 : 1;
  }

  void update(double frame_seconds) override {
    input_.sample();
    frame_seconds_ = frame_seconds;
    if (frame_seconds > 0) fps_ = fps_ * 0.95 + 0.05 / frame_seconds;
    if (options_.renderer == "auto" && automatic_renderer_.measuring()) {
      if (const auto now = automatic_renderer_.advance(
              frame_seconds, [this](RendererKind kind) { renderer_->set_kind(kind); },
              [this](const std::string& line) { report("%s", line.c_str()); }))
        kind_ = *now;
      if (!automatic_renderer_.measuring()) renderer_->release_inactive();
    }
    pick();
    handle_events();
    controls_.dispatch_held(input_, frame_seconds, claims());
#ifdef GRANULAR_SANDBOX_BODIES
    for (const std::string& line : session_->bodies->take_lines()) report("%s", line.c_str());
#endif
  }

  void render(double) override {
    const VkExtent2D extent = window_.framebuffer_extent();
    if (extent.width == 0 || extent.height == 0) return;  // minimised
    // Recreate when the window's size changed since the swapchain was made for it (compared with
    // the size asked for: the surface may round it).
    if (extent.width != requested_extent_.width || extent.height != requested_extent_.height) recreate_swapchain(extent);
    const std::optional<AcquiredFrame> frame = swapchain_.begin_frame();
    if (!frame) {
      recreate_swapchain(extent);
      return;
    }
    gpu_ = renderer_->timings(frame->slot);
    hud_.begin();
    draw_panel();
    BrushView brush;
    brush.visible = session_->tools->state().target.has_value();
    if (brush.visible) {
      const granular::Vec3 t = *session_->tools->state().target;
      brush.center = glm::vec3(t.x, t.y, t.z);
      brush.radius = float(session_->tools->state().radius);
    }
    renderer_->record(frame->commands, frame->slot, swapchain_.target(), frame->image_index, VK_IMAGE_LAYOUT_UNDEFINED,
                      camera_, brush, [&](VkCommandBuffer commands) { hud_.record(commands); });
    if (!swapchain_.end_frame(*frame)) recreate_swapchain(window_.framebuffer_extent());
  }

 private:
  static ContextOptions context_options(const SandboxOptions& options, const GlfwWindow& window) {
    ContextOptions result;
    result.validation = options.validation;
    // CUDA interop when the world will run on the CUDA backend: same GPU, exportable memory.
    if (!options.no_interop && options.world.backend != "cpu") {
      if (const auto uuid = granular::cuda_device_uuid()) {
        result.external_memory = true;
        result.device_uuid = *uuid;
      }
    }
    return window.presenting(result);
  }

  granular::World& world() { return *session_->sandbox.world; }

  /// Writes the frame presented last to `path` as a PNG (waits for the device first).
  void write_last_frame(const std::string& path) {
    vkDeviceWaitIdle(context_.device());
    const RenderTarget& target = swapchain_.target();
    write_png(path, target.extent().width, target.extent().height,
              target.read_pixels(context_, swapchain_.last_presented(), VK_IMAGE_LAYOUT_PRESENT_SRC_KHR));
  }

  /// The screenshot key: the frame just presented to the next free granular-screenshot-N.png.
  void take_screenshot() {
    const std::string path = next_screenshot_path(options_.screenshot_dir).string();
    try {
      write_last_frame(path);
      report("screenshot: %s", path.c_str());
    } catch (const std::runtime_error& e) {
      report("screenshot: failed (%s)", e.what());
    }
  }

  /// Makes `section` the section plane of the frames from now on and prints it.
  void set_section(const SectionPlane& section) {
    inside_.section = section;
    renderer_->set_see_inside(inside_);
    report("section: %s", inside_.section.describe().c_str());
  }

  /// Replaces the world with the one `choice` names; throws granular::Error (the world stays) when it
  /// cannot be made.
  void load(const WorldChoice& choice) {
    SandboxWorld fresh = load_world(choice);
    vkDeviceWaitIdle(context_.device());
    loop_.reset();
    renderer_.reset();
    const int ticks = session_ ? session_->simulation->ticks_per_fixed_update() : options_.ticks_per_frame;
    const bool paused = session_ && session_->simulation->paused();
    const ToolState tool_state = session_ ? session_->tools->state() : ToolState{};
    const granular::Int3 old_size = session_ ? session_->sandbox.world->size() : granular::Int3{};  // {} at start
    session_.reset();
    auto session = std::make_unique<Session>();
    session->sandbox = std::move(fresh);
    if (context_.external_memory() && session->sandbox.world->backend() == granular::BackendKind::Cuda)
      session->shared = std::make_unique<SharedCells>(context_, *session->sandbox.world);
    session->tools = std::make_unique<ToolSubsystem>(*session->sandbox.world, session->sandbox.emitters);
    session->tools->state() = tool_state;
    session->tools->state().held = false;
    stroke_.reset();
    session->simulation = std::make_unique<granular::engine::GranularSubsystem>(*session->sandbox.world, ticks);
    session->simulation->set_paused(paused);
#ifdef GRANULAR_SANDBOX_BODIES
    // Bullet steps with the world, a tick at a time (BulletCoupling::step), in every fixed update.
    session->bodies = std::make_unique<SandboxBodies>(*session->sandbox.world);
    session->simulation->set_stepper([bodies = session->bodies.get()](int ticks) { bodies->step(ticks); });
#endif
    session->tools->set_running([simulation = session->simulation.get()] { return !simulation->paused(); });
    session->history = std::make_unique<granular::StrokeHistory>(*session->sandbox.world,
                                                                 std::uint64_t(options_.undo_mib) << 20);
    session_ = std::move(session);
    const std::vector<Tool> offered = left_button_tools(world().rules());
    if (std::find(offered.begin(), offered.end(), left_tool_) == offered.end()) left_tool_ = Tool::Dig;
    offered_materials_ = material_choices(world().rules().materials);
    ToolState& tools = session_->tools->state();
    if (std::none_of(offered_materials_.begin(), offered_materials_.end(), [&](const MaterialChoice& c) { return c.material == tools.material; }))
      tools.material = offered_materials_.front().material;
    world_choice_ = choice;
    world_choice_.scene = session_->sandbox.scene_name;
    world_choice_.size = session_->sandbox.n;
    renderer_ = std::make_unique<WorldRenderer>(context_, world(), swapchain_.target().compatible_pass(), kind_,
                                                session_->shared.get(), options_.detail);
    renderer_->set_see_inside(inside_);
    // Fixed updates at the rules' real-time rate for 5 mm cells (31 Hz with the motion model, 250 Hz
    // for one step per tick), so sand falls at the speed of real sand.
    granular::engine::FixedTimestepConfig timestep;
    timestep.tick_rate_hz = 1.0 / granular::tick_seconds(world().rules());
    // At most 2 fixed updates a frame: on a machine too slow for real time (lavapipe) the sand slows
    // down rather than every frame waiting for 8 catch-up steps, so the window stays responsive.
    timestep.max_ticks_per_frame = 2;
    loop_ = std::make_unique<granular::engine::EngineLoop>(clock_, timestep);
    loop_->add(*session_->tools);
    loop_->add(*session_->simulation);
    loop_->add(*this);
    counts_age_ = 1e9;
#ifdef GRANULAR_SANDBOX_BODIES
    if (!(old_size == world().size())) throw_choice_.half_size = default_half_size(world().size());
    sync_bodies();  // a loaded snapshot's bodies get their rigid bodies
#else
    (void)old_size;
#endif
  }

  /// Loads the world file `path` (a snapshot, or a .raw/.vox grid) and reports it; a file that
  /// cannot be loaded is reported and the world stays.
  void open_file(const std::string& path) {
    WorldChoice choice = world_choice_;
    choice.scene = path;
    choice.size = 0;
    const granular::Int3 before = world().size();
    try {
      load(choice);
    } catch (const granular::Error& e) {
      report("load failed: %s", e.what());
      return;
    }
    report("%s", loaded_line(world(), path).c_str());
    if (!(world().size() == before)) camera_ = frame_content(world(), aspect());
  }

  /// Writes the snapshot file and reports it; a failure is reported and changes nothing.
  void save() {
    try {
      report("%s", save_world(world(), snapshot_file_).c_str());
    } catch (const granular::Error& e) {
      report("save failed: %s", e.what());
    }
  }

  /// Undoes the last stroke (ending a held one first) and pauses, so that a redo finds the world
  /// as the undo left it.
  void undo() {
    if (stroke_) end_stroke();
    const auto move = session_->history->undo();
    if (move) session_->simulation->set_paused(true);
    report("%s", undo_line(move, world()).c_str());
    sync_bodies();
  }

  void redo() {
    if (stroke_) return;  // a stroke in progress is what redo would overwrite
    report("%s", redo_line(session_->history->redo(), world()).c_str());
    sync_bodies();
  }

  /// Brings Bullet's rigid bodies in line with the World's bodies after an undo, a redo or a load,
  /// and says what changed ("bodies: 0 (1 removed, 0 added)").
  void sync_bodies() {
#ifdef GRANULAR_SANDBOX_BODIES
    const BodiesSynced synced = session_->bodies->sync();
    if (synced.removed > 0 || synced.added > 0)
      report("bodies: %zu (%zu removed, %zu added)", session_->bodies->count(), synced.removed, synced.added);
#endif
  }

#ifdef GRANULAR_SANDBOX_BODIES
  /// Throws the HUD's body from just in front of the camera along the ray through the cursor, as one
  /// stroke of the history (Ctrl+Z takes it back).
  void throw_body() {
    SandboxBodies& bodies = *session_->bodies;
    if (bodies.count() >= kMaxSandboxBodies) {
      report("throw: refused: %zu bodies already, the sandbox's most (Ctrl+Z or R takes them away)", bodies.count());
      return;  // before the history's stroke: a refused throw is nothing to undo
    }
    const VkExtent2D extent = swapchain_.target().extent();
    const Ray ray =
        ray_through_pixel(camera_, float(input_.x()), float(input_.y()), float(extent.width), float(extent.height));
    const double cell = world().def().cell_metres;
    const double tick = granular::tick_seconds(world().rules(), cell);
    std::optional<granular::BodyDef> def;
    double speed = 0;
    try {
      speed = throw_speed(world().size(), cell);
      def = aim_throw(throw_choice_, {ray.origin.x, ray.origin.y, ray.origin.z},
                      {ray.direction.x, ray.direction.y, ray.direction.z}, world().size(), speed, cell, tick);
    } catch (const std::invalid_argument& e) {
      report("throw: refused: %s", e.what());
      return;
    }
    if (!def) {
      report("throw: refused: the ray through the cursor passes no point of the grid with room for a %s of half "
             "size %.0f",
             shape_name(throw_choice_.shape), throw_choice_.half_size);
      return;
    }
    if (stroke_) end_stroke();
    const std::uint64_t tick_at_start = world().tick();
    granular::BodyId id = 0;
    try {
      session_->history->begin_stroke();
      id = bodies.add(*def);
      session_->history->end_stroke();
    } catch (const granular::Error& e) {
      session_->history->end_stroke();
      report("throw: failed: %s", e.what());
      return;
    }
    const granular::Vec3 p = def->pose.position, v = def->pose.velocity;
    report("throw: body %u, a %s of half size %.0f cells and %.0f kg/m^3 (%s), from (%.1f, %.1f, %.1f) at %.2f m/s = "
           "(%.2f, %.2f, %.2f) cells/tick at tick %llu (ticks of %.2f ms, cells of %.1f mm); %zu bodies%s",
           unsigned(id), shape_name(def->shape), throw_choice_.half_size, def->density,
           density_effect(def->density).c_str(), p.x, p.y, p.z, speed, v.x, v.y, v.z,
           static_cast<unsigned long long>(tick_at_start), tick * 1e3, cell * 1e3, bodies.count(),
           session_->simulation->paused() ? " (paused: it flies when the simulation runs)" : "");
  }
#endif

  void recreate_swapchain(VkExtent2D extent) {
    if (extent.width == 0 || extent.height == 0) return;
    requested_extent_ = extent;
    swapchain_.recreate(extent);
    renderer_->set_target_pass(swapchain_.target().compatible_pass());
    hud_.set_min_image_count(swapchain_.min_image_count());
  }

  /// The user's choice of renderer: it ends the automatic one.
  void set_renderer(RendererKind kind) {
    automatic_renderer_.stop();
    try {
      renderer_->set_kind(kind);
    } catch (const VulkanError& e) {
      report("renderer: %s unavailable here (%s); still %s", to_string(kind), e.what(), to_string(kind_));
      return;
    }
    kind_ = kind;
    report("renderer: %s", to_string(kind));
  }

  float aspect() const {
    const VkExtent2D extent = swapchain_.target().extent();
    return extent.height ? float(extent.width) / float(extent.height) : 1.0f;
  }

  /// What each command of the controls table does here; every row's commands have one (the
  /// constructor checks).
  void bind_controls() {
    controls_.handle(Command::UseLeftTool, [this](const Activation&) { start_stroke(GLFW_MOUSE_BUTTON_LEFT, left_tool_); });
    controls_.handle(Command::UseRightTool, [this](const Activation&) {
      const MaterialUse use = choice_of(offered_materials_, session_->tools->state().material).use;
      start_stroke(GLFW_MOUSE_BUTTON_RIGHT, use == MaterialUse::Pour ? Tool::Pour : Tool::Place);
    });
    controls_.handle(Command::BrushRadius, [this](const Activation& a) {
      ToolState& tool = session_->tools->state();
      tool.radius = std::clamp(tool.radius + a.steps, 1.0, 64.0);
      report("brush radius: %.0f", tool.radius);
    });
    controls_.handle(Command::Orbit, [this](const Activation& a) { camera_.orbit(float(a.dx), float(a.dy)); });
    controls_.handle(Command::Pan, [this](const Activation& a) { camera_.pan(float(a.dx), float(a.dy)); });
    controls_.handle(Command::Zoom, [this](const Activation& a) {
      camera_.zoom(float(std::pow(a.argument < 0 ? 0.4 : 2.5, a.seconds)));
    });
    controls_.handle(Command::WheelZoom, [this](const Activation& a) { camera_.zoom(float(std::pow(0.9, a.steps))); });
    controls_.handle(Command::Fly, [this](const Activation& a) { fly(FlyDirection(a.argument), a.seconds); });
    controls_.handle(Command::FrameContent, [this](const Activation&) {
      camera_ = frame_content(world(), aspect());
      report("camera: framing the content");
    });
    controls_.handle(Command::CycleLeftTool, [this](const Activation&) {
      left_tool_ = next_left_tool(left_tool_, world().rules());
      report("left button: %s", left_button_description(left_tool_, world().rules()).c_str());
    });
    controls_.handle(Command::ChooseMaterial, [this](const Activation& a) {
      if (const auto choice = choice_of_key(offered_materials_, a.argument)) choose(session_->tools->state(), *choice);
    });
#ifdef GRANULAR_SANDBOX_BODIES
    controls_.handle(Command::ThrowBody, [this](const Activation&) { throw_body(); });
#endif
    controls_.handle(Command::PauseResume, [this](const Activation&) {
      session_->simulation->set_paused(!session_->simulation->paused());
      report("%s", session_->simulation->paused() ? "paused" : "running");
    });
    controls_.handle(Command::Step, [this](const Activation&) {
      if (!session_->simulation->paused()) return;
      session_->simulation->request_step(session_->simulation->ticks_per_fixed_update());
      report("step");
    });
    controls_.handle(Command::ChangeTicks, [this](const Activation& a) { change_ticks(a.argument); });
    controls_.handle(Command::NextRenderer, [this](const Activation&) { set_renderer(RendererKind((int(kind_) + 1) % 3)); });
    controls_.handle(Command::CycleSection, [this](const Activation&) { set_section(inside_.section.cycled()); });
    controls_.handle(Command::MoveSection, [this](const Activation& a) { set_section(inside_.section.moved(a.argument)); });
    controls_.handle(Command::XRay, [this](const Activation&) {
      inside_.xray = !inside_.xray;
      renderer_->set_see_inside(inside_);
      report("x-ray: %s", inside_.xray ? "on" : "off");
    });
    controls_.handle(Command::Screenshot, [this](const Activation&) { screenshot_requested_ = true; });
    controls_.handle(Command::Reset, [this](const Activation&) { pending_load_ = true; });
    controls_.handle(Command::Undo, [this](const Activation&) { undo(); });
    controls_.handle(Command::Redo, [this](const Activation&) { redo(); });
    controls_.handle(Command::Save, [this](const Activation&) { save(); });
    controls_.handle(Command::Load, [this](const Activation&) { pending_file_ = snapshot_file_; });
    controls_.handle(Command::OpenDropped, [this](const Activation& a) {
      if (is_world_file(std::string(a.path))) pending_file_ = a.path;  // the last file dropped wins
      else report("drop: %s is not a world file (.gsnap, .raw or .vox)", std::string(a.path).c_str());
    });
    controls_.handle(Command::Quit, [this](const Activation&) { glfwSetWindowShouldClose(window_.handle(), GLFW_TRUE); });
    if (const std::vector<std::string> rows = controls_.unhandled(); !rows.empty())
      throw std::logic_error("controls: no handler for the row '" + rows.front() + "' of the controls table");
  }

  /// Which inputs this frame the HUD takes, and which button holds a stroke.
  InputClaims claims() const {
    // Dear ImGui decides whether it wants the mouse when the HUD is drawn, after this frame's input: a
    // click right after the cursor moved onto the HUD would reach the tools too, so the HUD's last
    // rectangle claims the mouse as well.
    const bool over_hud = input_.x() >= hud_min_.x && input_.x() < hud_max_.x && input_.y() >= hud_min_.y &&
                          input_.y() < hud_max_.y;
    return InputClaims{hud_.wants_keyboard(), hud_.wants_mouse() || over_hud, stroke_ ? stroke_->button : -1};
  }

  /// This frame's key presses, typed characters, button presses and releases and dropped files, in
  /// order, through the controls table: each one acts once, however short.
  void handle_events() {
    for (const InputEvent& event : input_.events()) {
      if (event.kind == InputEvent::Kind::ButtonRelease && stroke_ && stroke_->button == event.code) end_stroke();
      else controls_.dispatch(event, claims());
    }
  }

  /// Moves the camera towards `direction` for `seconds`, at its distance per second.
  void fly(FlyDirection direction, double seconds) {
    const float step = camera_.distance * float(seconds);
    switch (direction) {
      case FlyForward: camera_.fly(step, 0, 0); break;
      case FlyBack: camera_.fly(-step, 0, 0); break;
      case FlyRight: camera_.fly(0, step, 0); break;
      case FlyLeft: camera_.fly(0, -step, 0); break;
      case FlyUp: camera_.fly(0, 0, step); break;
      case FlyDown: camera_.fly(0, 0, -step); break;
    }
  }

  /// Makes `choice` the material of the right button.
  void choose(ToolState& tool, const MaterialChoice& choice) {
    tool.material = choice.material;
    report("material: %s (right button %ss it)", choice.name.c_str(), to_string(choice.use));
  }

  /// The table's name of `material`.
  const char* name_of(granular::Material material) const { return choice_of(offered_materials_, material).name.c_str(); }

  /// Starts a stroke of `tool` held by mouse button `button` (one stroke at a time).
  void start_stroke(int button, Tool tool) {
    if (stroke_) return;
    session_->tools->state().tool = tool;
    session_->tools->state().held = true;
    session_->history->begin_stroke();
    stroke_ = Stroke{button, session_->tools->cells_changed(), session_->tools->applications(), world().tick(),
                     world().hash()};
  }

  /// Releases the tool; a click that ended before any fixed update applied it applies it once.
  void end_stroke() {
    ToolSubsystem& tools = *session_->tools;
    tools.state().held = false;
    if (tools.applications() == stroke_->applications_at_start) tools.apply_once();
    session_->history->end_stroke();
    const long long cells = static_cast<long long>(tools.cells_changed() - stroke_->cells_at_start);
    // Where the stroke started and ended: an undo returns to the first, a redo to the second.
    const std::string span = "from tick " + std::to_string(stroke_->tick_at_start) + ", hash " +
                             granular::hex64(stroke_->hash_at_start) + ", to tick " + std::to_string(world().tick()) +
                             ", hash " + granular::hex64(world().hash());
    stroke_.reset();
    const char* material = name_of(tools.state().material);
    switch (tools.state().tool) {
      case Tool::Dig: report("dig: %lld cells removed (%s)", cells, span.c_str()); break;
      case Tool::Pour: report("pour: %lld %s cells added (%s)", cells, material, span.c_str()); break;
      case Tool::Place: report("place: %lld %s cells placed (%s)", cells, material, span.c_str()); break;
      case Tool::Erase: report("erase: %lld cells erased (%s)", cells, span.c_str()); break;
      case Tool::Shake: report("shake: %lld cells set moving (%s)", cells, span.c_str()); break;
    }
  }

  void change_ticks(int delta) {
    const int ticks = std::clamp(session_->simulation->ticks_per_fixed_update() + delta, 1, 64);
    session_->simulation->set_ticks_per_fixed_update(ticks);
    report("ticks per update: %d", ticks);
  }

  void pick() {
    ToolState& tool = session_->tools->state();
    tool.target.reset();
    tool.target_in_front.reset();
    if (hud_.wants_mouse()) return;
    const VkExtent2D extent = swapchain_.target().extent();
    const Ray ray = ray_through_pixel(camera_, float(input_.x()), float(input_.y()), float(extent.width), float(extent.height));
    const auto hit = pick_kept_cell(world(), inside_.section.cut(world().size(), camera_.eye()), ray.origin, ray.direction);
    if (!hit) return;
    tool.target = hit->point;
    const granular::Int3 front = hit->in_front();
    tool.target_in_front = granular::Vec3{front.x + 0.5, front.y + 0.5, front.z + 0.5};
  }

  void draw_panel() {
    counts_age_ += frame_seconds_;
    if (counts_age_ > 0.5) {
      counts_ = world().count();
      counts_age_ = 0;
    }
    const ToolState& tool = session_->tools->state();
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(440, 0), ImGuiCond_FirstUseEver);
    // No keyboard navigation in the HUD: Tab is the sandbox's key, and Dear ImGui would also take it
    // to focus the next widget (the ticks slider, which then holds the keyboard as a text field).
    ImGui::Begin("granular sandbox", nullptr, ImGuiWindowFlags_NoNavInputs);
    hud_min_ = ImGui::GetWindowPos();
    hud_max_ = ImVec2(hud_min_.x + ImGui::GetWindowSize().x, hud_min_.y + ImGui::GetWindowSize().y);
    ImGui::Text("%.1f FPS, frame %.2f ms", fps_, frame_seconds_ * 1e3);
    const int ticks = session_->simulation->ticks_per_fixed_update();
    ImGui::Text("simulation %.3f ms/tick (%d ticks per fixed update)", session_->simulation->last_step_seconds() * 1e3 / ticks, ticks);
    ImGui::Text("gpu: upload %.2f  build %.2f  draw %.2f ms", gpu_.upload_ms, gpu_.build_ms, gpu_.draw_ms);
    ImGui::Text("backend %s, cells %s", world().backend_description().c_str(),
                session_->shared ? "shared with CUDA" : "uploaded (changed bricks)");
    const granular::ActivityStats activity = world().activity();
    ImGui::Text("active bricks %llu / %llu, tick %llu", static_cast<unsigned long long>(activity.active_bricks),
                static_cast<unsigned long long>(activity.total_bricks), static_cast<unsigned long long>(world().tick()));
    ImGui::Separator();
    const MaterialChoice& chosen = choice_of(offered_materials_, tool.material);
    ImGui::Text("left button: %s (Tab cycles %s)", to_string(left_tool_), left_button_cycle(world().rules()).c_str());
    if (shake_level(world().rules()) == 0)
      ImGui::Text("no shake tool: rules '%s' have no motion model", world().rules().name.c_str());
    ImGui::Text("right button: %s %s, brush radius %.0f", to_string(chosen.use), chosen.name.c_str(), tool.radius);
    ImGui::Text("active tool: %s", tool.held ? to_string(tool.tool) : "none");
    ImGui::Text("section %s (V, comma, period), x-ray %s (B)", inside_.section.describe().c_str(), inside_.xray ? "on" : "off");
    ImGui::Text("%s (Ctrl+Z / Ctrl+Shift+Z)", history_line(*session_->history).c_str());
    ImGui::Text("snapshot file: %s (Ctrl+S / Ctrl+O)", snapshot_file_.c_str());
    if (const auto clicked = draw_material_panel(offered_materials_, tool.material, counts_))
      choose(session_->tools->state(), choice_of(offered_materials_, *clicked));
#ifdef GRANULAR_SANDBOX_BODIES
    draw_body_panel(throw_choice_, session_->bodies->count(),
                    world().rules().materials[granular::to_cell(world().def().body_material)]);
#endif
    int kind = int(kind_);
    ImGui::Text("renderer");
    for (RendererKind k : {RendererKind::Cubes, RendererKind::Marching, RendererKind::Raymarch}) {
      ImGui::SameLine();
      if (ImGui::RadioButton(to_string(k), kind == int(k))) set_renderer(k);
    }
    bool paused = session_->simulation->paused();
    if (ImGui::Checkbox("paused", &paused)) session_->simulation->set_paused(paused);
    ImGui::SameLine();
    if (ImGui::Button("step")) session_->simulation->request_step(session_->simulation->ticks_per_fixed_update());
    int ticks_value = ticks;
    if (ImGui::SliderInt("ticks/update", &ticks_value, 1, 64)) session_->simulation->set_ticks_per_fixed_update(ticks_value);
    const std::vector<std::string> scenes = granular::list_scenes();
    if (ImGui::BeginCombo("scene", session_->sandbox.scene_name.c_str())) {
      for (const std::string& name : scenes)
        if (ImGui::Selectable(name.c_str(), name == session_->sandbox.scene_name)) {
          world_choice_.scene = name;
          world_choice_.size = options_.world.size;
          pending_load_ = true;
        }
      ImGui::EndCombo();
    }
    ImGui::SameLine();
    if (ImGui::Button("reset")) pending_load_ = true;
    if (ImGui::CollapsingHeader("controls"))
      for (const Control& control : kControls) ImGui::BulletText("%s: %s", control.text.input, control.text.action);
    ImGui::End();
  }

  SandboxOptions options_;
  GlfwWindow window_;
  VulkanContext context_;
  Swapchain swapchain_;
  InputTracker input_;
  Hud hud_;
  ControlDispatch controls_;  ///< the controls table's commands and what they do here
  RendererChoice automatic_renderer_;  ///< measures the renderers while --renderer is auto
  RendererKind kind_;
  SeeInside inside_;  ///< the section plane (V, comma, period) and x-ray (B) of every frame
  VkExtent2D requested_extent_;
  granular::engine::SteadyClock clock_;
  std::unique_ptr<Session> session_;
  std::unique_ptr<WorldRenderer> renderer_;
  std::unique_ptr<granular::engine::EngineLoop> loop_;
  OrbitCamera camera_;
  WorldChoice world_choice_;  ///< the world loaded last: what R and the HUD's reset load again, a scene pick changes
  bool pending_load_ = false;
  bool screenshot_requested_ = false;  ///< P was pressed: write the frame once it is presented
  std::string snapshot_file_;  ///< the file of Ctrl+S and Ctrl+O (--save, else kDefaultSnapshotFile)
  std::string pending_file_;   ///< a world file to load after this frame (Ctrl+O, a drop); "" for none
  std::optional<Stroke> stroke_;
  Tool left_tool_ = Tool::Dig;  ///< the left button's tool, one of left_button_tools(world().rules())
  std::vector<MaterialChoice> offered_materials_;  ///< the materials of the world's table, on keys 1..7
#ifdef GRANULAR_SANDBOX_BODIES
  ThrowChoice throw_choice_;  ///< the body key T throws next (the HUD's bodies section)
#endif
  ImVec2 hud_min_{0, 0}, hud_max_{0, 0};  ///< the HUD window's rectangle when it was last drawn, in pixels
  double frame_seconds_ = 0;
  double fps_ = 0;
  double counts_age_ = 1e9;
  granular::MaterialCounts counts_{};
  GpuTimings gpu_;
};

}  // namespace

int run_windowed(const SandboxOptions& options) {
  SandboxApp app(options);
  return app.run();
}

}  // namespace viewer
