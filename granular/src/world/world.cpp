#include "granular/world.hpp"

#include <algorithm>
#include <map>
#include <mutex>
#include <new>

#include "world/world_body_set.hpp"
#include "granular/extend/backend.hpp"
#include "granular/extend/backend_factory.hpp"
#include "granular/extend/backend_registry.hpp"
#include "granular/bricks.hpp"
#include "granular/errors.hpp"
#include "granular/extend/hex.hpp"
#include "granular/extend/lut.hpp"
#include "granular/motion.hpp"
#include "granular/rule_presets.hpp"
#include "granular/rule_set.hpp"
#include "granular/world_snapshot.hpp"
#include "world/cell_checks.hpp"
#include "world/region_edit.hpp"
#include "world/tool_region.hpp"
#include "world/world_def_validation.hpp"
#include "world/world_scratch.hpp"
#include "util/stopwatch.hpp"

namespace granular {

const char* backend_name(BackendKind kind) noexcept {
  switch (kind) {
    case BackendKind::Auto: return "auto";
    case BackendKind::Cpu: return "cpu";
    case BackendKind::Cuda: return "cuda";
  }
  return "unknown";
}

namespace {

/// Clears the motion state (motion.hpp) of cell bytes read from a backend: readers get materials.
void strip_motion(std::span<std::uint8_t> cells) {
  for (auto& c : cells) c &= kMaterialMask;
}

/// Tables are 64 MiB: worlds of one process share them while any is alive.
std::shared_ptr<const Lut> shared_lut(const RuleSet& rules, const WorldDef& def, int threads, double& seconds,
                                      bool& from_cache, std::string& notice) {
  static std::mutex mutex;
  static std::map<std::uint64_t, std::weak_ptr<const Lut>> live;
  const std::uint64_t fingerprint = rule_fingerprint(rules);
  std::lock_guard lock(mutex);
  if (auto lut = live[fingerprint].lock()) {
    seconds = 0;
    from_cache = true;
    return lut;
  }
  LutCacheOptions options;
  options.enabled = def.use_lut_cache;
  options.directory = def.lut_cache_dir;
  options.threads = threads;
  LutObtained got = obtain_lut(rules, options);
  seconds = got.seconds;
  from_cache = got.from_cache;
  notice = got.notice;
  live[fingerprint] = got.lut;
  return got.lut;
}

/// Throws unless `box` is non-empty and lies inside a grid of `size`.
void check_inside(const Box& box, Int3 size, const char* what) {
  if (box.empty() || !(intersect(box, Box{{0, 0, 0}, size}) == box))
    throw InvalidArgument(std::string(what) + ": box " + box_string(box) + " is empty or not inside the " +
                          to_string(size) + " grid");
}

/// Throws InvalidArgument naming both names and fingerprints unless `rules`, whose fingerprint is
/// `fingerprint`, is the rule set the snapshot was taken under; `what` starts the message.
void check_snapshot_rules(const WorldSnapshot& snapshot, const RuleSet& rules, std::uint64_t fingerprint,
                          const std::string& what) {
  if (fingerprint == snapshot.rule_fingerprint) return;
  throw InvalidArgument(what + ": the snapshot was taken under rules '" + snapshot.rules + "' (fingerprint " +
                        hex64(snapshot.rule_fingerprint) + ") but the world's rules are '" + rules.name +
                        "' (fingerprint " + hex64(fingerprint) + ")" +
                        (snapshot.rules == rules.name ? "; the rule set of that name has changed since" : ""));
}

/// Host memory a world needs beside its cells: the transition table (64 MiB) and the backend's
/// scratch, with room to spare.
constexpr double kWorldExtraBytes = 128.0 * 1024 * 1024;

}  // namespace


namespace {

/// Reads boxes of the cells of `snapshot` (its grid's bytes, x fastest).
std::function<void(const Box&, std::span<std::uint8_t>)> snapshot_cells(const WorldSnapshot& snapshot) {
  return [&snapshot](const Box& box, std::span<std::uint8_t> out) {
    const Int3 n = snapshot.size;
    std::size_t at = 0;
    const std::size_t w = std::size_t(box.max.x - box.min.x);
    for (int z = box.min.z; z < box.max.z; ++z)
      for (int y = box.min.y; y < box.max.y; ++y, at += w)
        std::copy_n(snapshot.cells.data() + std::size_t(box.min.x) + std::size_t(n.x) * (std::size_t(y) + std::size_t(n.y) * std::size_t(z)), w,
                    out.data() + at);
  };
}

}  // namespace

World::World(const WorldDef& def) : def_(def) {
  // The initial grid and the backend's copy of it.
  check_grid_size(def.size, "WorldDef::size", 2.0, kWorldExtraBytes);
  init(Grid(def.size));
}

World::World(const WorldDef& def, const Grid& initial) : def_(def) {
  if (initial.cell_count() == 0) throw InvalidArgument("World: the initial grid is empty (0 cells)");
  check_grid_size(initial.size(), "World: the backend's copy of the initial grid", 1.0, kWorldExtraBytes);
  check_cells(initial.cells(), initial.size(), "World: initial grid");
  init(initial);
}

World::World(const WorldDef& def, const WorldSnapshot& snapshot) : def_(def) {
  check_grid_extents(snapshot.size, "World: WorldSnapshot::size");
  const std::uint64_t cells = std::uint64_t(snapshot.size.x) * std::uint64_t(snapshot.size.y) * std::uint64_t(snapshot.size.z);
  if (snapshot.cells.size() != cells)
    throw InvalidArgument("World: WorldSnapshot::cells holds " + std::to_string(snapshot.cells.size()) +
                          " bytes; its " + to_string(snapshot.size) + " grid has " + std::to_string(cells) + " cells");
  const std::shared_ptr<const RuleSet> rules = def_.rule_set ? def_.rule_set : make_rule_set(def_.rules);
  check_snapshot_rules(snapshot, *rules, rule_fingerprint(*rules), "World");
  check_cell_bytes(snapshot.cells, *rules, "World: snapshot", [&](std::size_t i) { return cell_text(i, snapshot.size); });
  check_side_bytes(snapshot.side, snapshot.cells, snapshot.size, *rules, "World");
  check_face_plane(snapshot.faces, snapshot.size, *rules, "World");
  // The initial grid and the backend's copy of it.
  check_grid_size(snapshot.size, "World: the snapshot's grid", 2.0, kWorldExtraBytes);
  def_.seed = snapshot.seed;
  Grid initial(snapshot.size);
  std::copy(snapshot.cells.begin(), snapshot.cells.end(), initial.cells().begin());
  init(initial, rules);
  check_body_states(snapshot.bodies, "World: snapshot", snapshot_cells(snapshot));
  put_bodies(snapshot.bodies);
  live().write_side(snapshot.side);
  live().write_faces(snapshot.faces);
  tick_ = snapshot.tick;
  tool_calls_ = snapshot.tool_calls;
}

World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

void World::init(const Grid& initial, std::shared_ptr<const RuleSet> rules) {
  const int threads = validate_world_def(def_, initial.size());
  size_ = initial.size();
  def_.size = size_;
  scratch_ = std::make_unique<Scratch>();
  const Int3 bricks = granular::brick_counts(size_);
  brick_version_.assign(std::size_t(bricks.x) * std::size_t(bricks.y) * std::size_t(bricks.z), 0);
  changed_flags_.assign(brick_version_.size(), 0);
  activity_.total_bricks = brick_version_.size();
  rules_ = rules ? std::move(rules) : def_.rule_set ? def_.rule_set : make_rule_set(def_.rules);
  validate_rule_set(*rules_);
  rule_fingerprint_ = rule_fingerprint(*rules_);
  const BackendFactory factory = choose_backend(def_.backend);
  // The table (64 MiB), the backend's cells and its scratch: an allocation that fails is an
  // OutOfMemory naming the grid, not a bare std::bad_alloc.
  try {
    std::string notice;
    lut_ = shared_lut(*rules_, def_, threads, lut_seconds_, lut_from_cache_, notice);
    if (!notice.empty()) notices_.push_back(notice);
    backend_ = factory(BackendCreateInfo{.initial = initial,
                                         .lut = lut_,
                                         .rules = rules_,
                                         .seed = def_.seed,
                                         .sparse = def_.sparse,
                                         .threads = threads,
                                         .task_system = def_.task_system,
                                         .cuda = def_.cuda,
                                         .domain_origin = def_.domain_origin});
  } catch (const std::bad_alloc&) {
    throw OutOfMemory("World: out of host memory creating the backend of the " + to_string(size_) + " grid (" +
                      std::to_string(initial.cell_count() >> 20) +
                      " MiB of cells, plus a 64 MiB transition table); use a smaller grid");
  }
  if (!backend_) throw BackendError("WorldDef::backend_factory returned no backend (a null pointer)");
}

BackendFactory World::choose_backend(BackendKind wanted) {
  if (def_.backend_factory) return def_.backend_factory;
  if (wanted == BackendKind::Cpu) return make_cpu_backend;
  const std::optional<BackendProvider> cuda = registered_backend(BackendKind::Cuda);
  if (!cuda) {
    if (wanted == BackendKind::Cuda)
      throw BackendError("WorldDef::backend = cuda, but this program links no CUDA backend (link granular::granular "
                         "from a build with CUDA, not granular::core alone); use cpu or auto");
    notices_.push_back("backend auto: no CUDA backend linked into this program; using the CPU");
    return make_cpu_backend;
  }
  const std::string why = cuda->unusable_reason();
  if (why.empty()) return cuda->create;
  if (wanted == BackendKind::Cuda)
    throw BackendError("WorldDef::backend = cuda, but no CUDA device is usable: " + why + "; use cpu or auto");
  notices_.push_back("backend auto: no usable CUDA device (" + why + "); using the CPU");
  return make_cpu_backend;
}

void World::step(int ticks) {
  live();
  if (ticks < 0) throw InvalidArgument("World::step: ticks = " + std::to_string(ticks) + " must be >= 0");
  if (ticks == 0) return;
  if (std::uint64_t(ticks) > std::numeric_limits<std::uint64_t>::max() - tick_)
    throw StateError("World::step: ticks = " + std::to_string(ticks) + " from tick " + std::to_string(tick_) +
                     " would wrap the 64-bit tick counter");
  profile_ = StepProfile{};
  profile_.ticks = std::uint64_t(ticks);
  Stopwatch whole, watch;
  if (bodies_ && !bodies_->list.empty()) {
    for (int t = 0; t < ticks; ++t) {
      stamp_bodies();         // times its own phases
      step_sensing_bodies();  // likewise
      ++tick_;
      advance_bodies();
    }
  } else {
    live().step(tick_, ticks);
    profile_.step = watch.lap();
    tick_ += std::uint64_t(ticks);
  }
  profile_.total = whole.lap();
  activity_pending_ = true;
  step_changes_pending_ = true;
}

ActivityStats World::activity() const {
  live();
  // Read lazily: with a renderer's timelines attached the CUDA backend returns from step() before
  // the device has finished, and only this waits for the activity counters.
  if (activity_pending_) {
    activity_ = live().last_activity();
    activity_pending_ = false;
  }
  return activity_;
}

void World::take_step_changes() const {
  live();
  if (!step_changes_pending_) return;
  step_changes_pending_ = false;
  std::fill(changed_flags_.begin(), changed_flags_.end(), std::uint8_t(0));
  live().take_changed_bricks(changed_flags_);
  std::vector<std::uint32_t> changed;
  for (std::uint32_t i = 0; i < changed_flags_.size(); ++i)
    if (changed_flags_[i]) changed.push_back(i);
  mark_bricks(changed);
}

std::uint64_t World::change_version() const {
  take_step_changes();
  return change_version_;
}

void World::mark_bricks(std::span<const std::uint32_t> bricks) const {
  // Changes of steps not taken yet (take_step_changes) get their version when somebody next asks
  // for one, after these: every version a caller holds was read after taking them, so
  // bricks_changed_since lists the same bricks either way, and a tool costs no read of the
  // backend's changed-brick flags.
  if (bricks.empty()) return;
  ++change_version_;
  for (const std::uint32_t b : bricks) brick_version_[b] = change_version_;
}

std::uint64_t World::shared_cell_bytes() const { return live().shared_cell_bytes(); }

void World::share_cells(const ExternalCellMemory& memory) {
  const std::uint64_t needed = live().shared_cell_bytes();
  if (needed > 0 && (memory.offset > memory.allocation_size || memory.allocation_size - memory.offset < needed))
    throw InvalidArgument("World::share_cells: the shared buffer holds " +
                          std::to_string(memory.allocation_size - std::min(memory.offset, memory.allocation_size)) +
                          " bytes after offset " + std::to_string(memory.offset) + "; the " + to_string(size_) +
                          " grid needs " + std::to_string(needed) + " (World::shared_cell_bytes)");
  if (needed > 0 && memory.fd < 0)
    throw InvalidArgument("World::share_cells: fd " + std::to_string(memory.fd) + " is not a file descriptor");
  live().share_cells(memory);
}

void World::attach_timelines(const ExternalTimeline& cells_ready, const ExternalTimeline& cells_released) {
  live().attach_timelines(cells_ready, cells_released);
}

CellsHandoff World::hand_off_cells() { return live().hand_off_cells(); }

std::vector<std::uint32_t> World::bricks_changed_since(std::uint64_t version) const {
  take_step_changes();
  std::vector<std::uint32_t> changed;
  for (std::size_t i = 0; i < brick_version_.size(); ++i)
    if (brick_version_[i] > version) changed.push_back(std::uint32_t(i));
  return changed;
}

BackendKind World::backend() const { return live().kind(); }
std::string World::backend_description() const { return live().description(); }
const RuleSet& World::rules() const {
  live();
  return *rules_;
}
const Lut& World::lut() const {
  live();
  return *lut_;
}

Backend& World::live() const {
  if (!backend_)
    throw StateError("World: this world was moved from (std::move); call it through the World it was moved into");
  return *backend_;
}
MaterialCounts World::count() const { return live().count(); }
std::uint64_t World::hash() const { return live().hash(); }

std::vector<std::uint8_t> World::read_region(const Box& box) const {
  check_inside(box, size_, "World::read_region");
  std::vector<std::uint8_t> out(std::size_t(box.volume()));
  read_region(box, out);
  return out;
}

void World::read_region(const Box& box, std::span<std::uint8_t> out) const {
  check_inside(box, size_, "World::read_region");
  if (out.size() != std::size_t(box.volume()))
    throw InvalidArgument("World::read_region: output holds " + std::to_string(out.size()) + " bytes; the box has " +
                          std::to_string(box.volume()) + " cells");
  live().read(box, out);
  strip_motion(out);
}

Grid World::read_grid() const {
  Grid g(size_);
  live().read(g.bounds(), g.cells());
  strip_motion(g.cells());
  return g;
}

void World::load(const Grid& grid) {
  if (!(grid.size() == size_))
    throw InvalidArgument("World::load: grid is " + to_string(grid.size()) + " but the world is " + to_string(size_));
  check_cells(grid.cells(), grid.size(), "World::load");
  begin_edit(grid.bounds()).put_materials(grid.cells());
  write_edit();
}

std::vector<std::uint8_t> World::read_cells(const Box& region) const {
  std::vector<std::uint8_t> cells = cell_buffer(region);
  live().read(region, cells);
  return cells;
}

std::vector<std::uint8_t> World::cell_buffer(const Box& region) const {
  try {
    return std::vector<std::uint8_t>(std::size_t(region.volume()));
  } catch (const std::bad_alloc&) {
    throw OutOfMemory("World: could not allocate " + std::to_string(region.volume()) + " bytes for the cells of " +
                      box_string(region) + " of the " + to_string(size_) + " grid");
  }
}

WorldSnapshot World::capture() const {
  WorldSnapshot s;
  s.size = size_;
  s.cells = read_cells(Box{{0, 0, 0}, size_});
  s.side = live().read_side();
  s.faces = live().read_faces();
  s.tick = tick_;
  s.seed = def_.seed;
  s.tool_calls = tool_calls_;
  s.rules = rules().name;
  s.rule_fingerprint = rule_fingerprint_;
  s.bodies = body_states();
  return s;
}

void World::restore(const WorldSnapshot& snapshot) {
  live();
  if (!(snapshot.size == size_))
    throw InvalidArgument("World::restore: the snapshot's grid is " + to_string(snapshot.size) + " but the world's is " +
                          to_string(size_));
  if (snapshot.cells.size() != std::size_t(Box{{0, 0, 0}, size_}.volume()))
    throw InvalidArgument("World::restore: WorldSnapshot::cells holds " + std::to_string(snapshot.cells.size()) +
                          " bytes; the " + to_string(size_) + " grid has " +
                          std::to_string(Box{{0, 0, 0}, size_}.volume()) + " cells");
  if (snapshot.seed != def_.seed)
    throw InvalidArgument("World::restore: the snapshot's seed is " + std::to_string(snapshot.seed) +
                          " but this world's (WorldDef::seed) is " + std::to_string(def_.seed) +
                          "; a snapshot continues only under its own seed");
  check_snapshot_rules(snapshot, *rules_, rule_fingerprint_, "World::restore");
  check_cell_bytes(snapshot.cells, *rules_, "World::restore: snapshot", [&](std::size_t i) { return cell_text(i, size_); });
  check_side_bytes(snapshot.side, snapshot.cells, size_, *rules_, "World::restore");
  check_face_plane(snapshot.faces, size_, *rules_, "World::restore");
  check_body_states(snapshot.bodies, "World::restore: snapshot", snapshot_cells(snapshot));
  write_grid(snapshot.cells, all_bricks(brick_counts()));
  put_bodies(snapshot.bodies);
  live().write_side(snapshot.side);
  live().write_faces(snapshot.faces);
  tick_ = snapshot.tick;
  tool_calls_ = snapshot.tool_calls;
}

void World::write_grid(std::span<const std::uint8_t> cells, std::span<const std::uint32_t> changed) {
  mark_bricks(changed);
  live().write(Box{{0, 0, 0}, size_}, cells, all_bricks(brick_counts()));
}

RegionEdit& World::begin_edit(const Box& region) {
  Backend& backend = live();
  RegionEdit& edit = scratch_->edit;
  edit.begin(region, size_, slab_tools_ ? slab_tools_->origin : Int3{});
  backend.read(region, edit.cells());
  return edit;
}

void World::write_edit() {
  RegionEdit& edit = scratch_->edit;
  const std::span<const std::uint32_t> bricks = edit.bricks();
  if (!bricks.empty()) {
    mark_bricks(bricks);
    live().write(edit.region(), edit.cells(), bricks);
  }
  edit.trim();
}

}  // namespace granular
