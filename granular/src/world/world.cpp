#include "granular/world.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <new>
#include <tuple>

#include "granular/extend/backend.hpp"
#include "granular/extend/backend_factory.hpp"
#include "granular/extend/backend_registry.hpp"
#include "granular/errors.hpp"
#include "granular/extend/hex.hpp"
#include "granular/extend/lut.hpp"
#include "granular/motion.hpp"
#include "granular/rule_presets.hpp"
#include "granular/rule_set.hpp"
#include "granular/task_system.hpp"
#include "granular/extend/threads.hpp"
#include "granular/world_snapshot.hpp"
#include "world/pour_choice.hpp"
#include "world/region_edit.hpp"
#include "world/sphere_runs.hpp"
#include "step/step_materials.hpp"
#include "world/tool_region.hpp"

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

/// "cell (x, y, z)" of cell `i` (x fastest) of a grid of `size`.
std::string cell_text(std::size_t i, Int3 size) {
  const std::size_t x = i % std::size_t(size.x), y = (i / std::size_t(size.x)) % std::size_t(size.y),
                    z = i / (std::size_t(size.x) * std::size_t(size.y));
  return "cell (" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) + ")";
}

void check_cells(std::span<const std::uint8_t> cells, Int3 size, const char* what) {
  for (std::size_t i = 0; i < cells.size(); ++i)
    if (!is_valid_material_value(cells[i]))
      throw InvalidArgument(std::string(what) + ": " + cell_text(i, size) + " holds " + std::to_string(unsigned(cells[i])) +
                            ", not a valid state (0..7)");
}

/// For each of the 256 cell bytes, what keeps a world under `rules` from holding it ("" when
/// nothing): the motion state (bits 3..7) belongs to granular and liquid cells under a motion model,
/// at a level up to MotionParams::max_level(), and to wakes under MotionParams::columns.
std::array<std::string, 256> cell_byte_problems(const RuleSet& rules) {
  const StepMaterials mats = step_materials(rules.materials);
  std::array<std::string, 256> problems;
  for (unsigned b = 0; b < 256; ++b) {
    const std::uint8_t m = cell_material(std::uint8_t(b));
    if ((b >> kMotionShift) == 0) continue;
    if (rules.motion.columns && is_wake(std::uint8_t(b)) && cell_motion(std::uint8_t(b)) <= rules.motion.max_level())
      continue;
    if (!rules.motion.enabled())
      problems[b] = "a motion state, but rules '" + rules.name + "' have no motion model";
    else if (!mats.is_faller(m))
      problems[b] = "a motion state on " + rules.materials[m].name + ", which is neither granular nor liquid";
    else if (cell_motion(std::uint8_t(b)) > rules.motion.max_level())
      problems[b] = "motion level " + std::to_string(cell_motion(std::uint8_t(b))) + ", above the rules' highest, " +
                    std::to_string(rules.motion.max_level());
  }
  return problems;
}

/// Throws InvalidArgument starting with `what` when one of `cells` is a byte a world under `rules`
/// cannot hold (cell_byte_problems), naming the byte and, through where(i), cell i.
template <class Where>
void check_cell_bytes(std::span<const std::uint8_t> cells, const RuleSet& rules, const std::string& what,
                      Where&& where) {
  const std::array<std::string, 256> problems = cell_byte_problems(rules);
  std::array<bool, 256> bad{};
  for (unsigned b = 0; b < 256; ++b) bad[b] = !problems[b].empty();
  const auto first = std::find_if(cells.begin(), cells.end(), [&](std::uint8_t c) { return bad[c]; });
  if (first == cells.end()) return;
  const auto i = std::size_t(first - cells.begin());
  throw InvalidArgument(what + ": " + where(i) + " holds the byte " + std::to_string(unsigned(*first)) + ": " +
                        problems[*first]);
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

/// Every brick of a grid of `size`, ascending.
std::vector<std::uint32_t> all_bricks(Int3 size) {
  const Int3 n = granular::brick_counts(size);
  std::vector<std::uint32_t> bricks(std::size_t(n.x) * std::size_t(n.y) * std::size_t(n.z));
  for (std::size_t i = 0; i < bricks.size(); ++i) bricks[i] = std::uint32_t(i);
  return bricks;
}

/// Calls copy(box, offset) for each of `bricks` of a grid of `size`: its cells, and where they start
/// in the bricks' packed bytes (brick after brick, each x fastest).
template <class Copy>
void for_each_brick(Int3 size, std::span<const std::uint32_t> bricks, Copy&& copy) {
  std::size_t offset = 0;
  for (const std::uint32_t b : bricks) {
    const Box box = brick_box(size, b);
    copy(box, offset);
    offset += std::size_t(box.volume());
  }
}

/// Calls fn(grid index, packed offset, width) for every row of the cells of `bricks` of a grid of
/// `size`: where the row starts in the grid (x fastest) and in the bricks' packed bytes.
template <class Fn>
void for_each_brick_row(Int3 size, std::span<const std::uint32_t> bricks, Fn&& fn) {
  for_each_brick(size, bricks, [&](const Box& box, std::size_t offset) {
    const std::size_t w = std::size_t(box.max.x - box.min.x);
    for (int z = box.min.z; z < box.max.z; ++z)
      for (int y = box.min.y; y < box.max.y; ++y, offset += w)
        fn(std::size_t(box.min.x) + std::size_t(size.x) * (std::size_t(y) + std::size_t(size.y) * std::size_t(z)),
           offset, w);
  });
}

/// True when bricks holding `cells` cells move faster as one copy of a whole grid of `size` than
/// brick by brick (one backend call each): when they hold more than an eighth of it.
bool whole_grid_is_faster(Int3 size, std::uint64_t cells) {
  return cells * 8 > std::uint64_t(size.x) * std::uint64_t(size.y) * std::uint64_t(size.z);
}

}  // namespace

namespace {

/// Host memory a world needs beside its cells: the transition table (64 MiB) and the backend's
/// scratch, with room to spare.
constexpr double kWorldExtraBytes = 128.0 * 1024 * 1024;

}  // namespace

struct World::Scratch {
  RegionEdit edit;  ///< the region a tool or load edits
  PourChoice pour;  ///< pour's choice of cells
};

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
  // The initial grid and the backend's copy of it.
  check_grid_size(snapshot.size, "World: the snapshot's grid", 2.0, kWorldExtraBytes);
  def_.seed = snapshot.seed;
  Grid initial(snapshot.size);
  std::copy(snapshot.cells.begin(), snapshot.cells.end(), initial.cells().begin());
  init(initial, rules);
  tick_ = snapshot.tick;
  tool_calls_ = snapshot.tool_calls;
}

World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

void World::init(const Grid& initial, std::shared_ptr<const RuleSet> rules) {
  int threads = resolve_threads(def_.threads, "WorldDef::threads");
  if (def_.task_system) {
    threads = def_.task_system->thread_count();
    if (threads < 1 || threads > max_threads())
      throw InvalidArgument("WorldDef::task_system->thread_count() = " + std::to_string(threads) + "; use 1.." +
                            std::to_string(max_threads()) + " (4 times the hardware threads)");
  }
  if (def_.backend != BackendKind::Auto && def_.backend != BackendKind::Cpu && def_.backend != BackendKind::Cuda)
    throw InvalidArgument("WorldDef::backend = " + std::to_string(int(def_.backend)) +
                          " is not a BackendKind; use Auto, Cpu or Cuda");
  for (const auto& [field, value] : {std::pair{"dense_fraction", def_.cuda.dense_fraction},
                                     std::pair{"motion_dense_fraction", def_.cuda.motion_dense_fraction}})
    if (!(value >= 0.0 && value <= 1.0))
      throw InvalidArgument(std::string("WorldDef::cuda.") + field + " = " + std::to_string(value) +
                            "; use a fraction of the bricks in 0..1 (0: always dense-recording, 1: never)");
  size_ = initial.size();
  def_.size = size_;
  for (const auto& [axis, origin, extent] : {std::tuple{"x", def_.domain_origin.x, size_.x},
                                            std::tuple{"y", def_.domain_origin.y, size_.y},
                                            std::tuple{"z", def_.domain_origin.z, size_.z}})
    if (origin < 0 || origin % 2 != 0 || origin > kMaxGridExtent - extent)
      throw InvalidArgument(std::string("WorldDef::domain_origin.") + axis + " = " + std::to_string(origin) +
                            "; use an even coordinate in 0.." + std::to_string(kMaxGridExtent - extent) +
                            " (the grid must lie inside a " + std::to_string(kMaxGridExtent) +
                            "-cell world, on the block partition's parity)");
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
  live().step(tick_, ticks);
  tick_ += std::uint64_t(ticks);
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

Grid World::snapshot() const {
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
  s.tick = tick_;
  s.seed = def_.seed;
  s.tool_calls = tool_calls_;
  s.rules = rules().name;
  s.rule_fingerprint = rule_fingerprint_;
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
  write_grid(snapshot.cells, all_bricks(size_));
  tick_ = snapshot.tick;
  tool_calls_ = snapshot.tool_calls;
}

void World::write_grid(std::span<const std::uint8_t> cells, std::span<const std::uint32_t> changed) {
  mark_bricks(changed);
  live().write(Box{{0, 0, 0}, size_}, cells, all_bricks(size_));
}

void World::read_bricks(std::span<const std::uint32_t> bricks, std::span<std::uint8_t> out) const {
  gather_bricks(bricks, out, "World::read_bricks", [this](const Box& box, std::span<std::uint8_t> cells) {
    live().read(box, cells);
  });
}

void World::read_checkpoint_bricks(std::span<const std::uint32_t> bricks, std::span<std::uint8_t> out) const {
  if (live().checkpoint_bytes() == 0)
    throw StateError("World::read_checkpoint_bricks: there is no checkpoint (take_checkpoint)");
  gather_bricks(bricks, out, "World::read_checkpoint_bricks", [this](const Box& box, std::span<std::uint8_t> cells) {
    live().read_checkpoint(box, cells);
  });
}

void World::take_checkpoint() { live().take_checkpoint(); }
void World::drop_checkpoint() { live().drop_checkpoint(); }
std::uint64_t World::checkpoint_bytes() const { return live().checkpoint_bytes(); }

void World::check_bricks(std::span<const std::uint32_t> bricks, std::size_t bytes, const char* what) const {
  const std::size_t total = brick_version_.size();
  for (const std::uint32_t b : bricks)
    if (b >= total)
      throw InvalidArgument(std::string(what) + ": brick " + std::to_string(b) + " is not one of the " +
                            std::to_string(total) + " bricks of the " + to_string(size_) + " grid");
  const std::uint64_t cells = brick_cells(size_, bricks);
  if (bytes != cells)
    throw InvalidArgument(std::string(what) + ": the buffer holds " + std::to_string(bytes) + " bytes; the " +
                          std::to_string(bricks.size()) + " bricks hold " + std::to_string(cells) + " cells");
}

template <class Read>
void World::gather_bricks(std::span<const std::uint32_t> bricks, std::span<std::uint8_t> out, const char* what,
                          Read&& read) const {
  check_bricks(bricks, out.size(), what);
  if (!whole_grid_is_faster(size_, out.size())) {
    for_each_brick(size_, bricks, [&](const Box& box, std::size_t offset) {
      read(box, out.subspan(offset, std::size_t(box.volume())));
    });
    return;
  }
  std::vector<std::uint8_t> whole = cell_buffer(Box{{0, 0, 0}, size_});
  read(Box{{0, 0, 0}, size_}, whole);
  for_each_brick_row(size_, bricks, [&](std::size_t cell, std::size_t offset, std::size_t w) {
    std::copy_n(whole.data() + cell, w, out.data() + offset);
  });
}

void World::restore_bricks(std::span<const std::uint32_t> bricks, std::span<const std::uint8_t> bytes,
                           std::uint64_t tick, std::uint64_t tool_calls) {
  check_bricks(bricks, bytes.size(), "World::restore_bricks");
  check_cell_bytes(bytes, *rules_, "World::restore_bricks", [&](std::size_t i) {
    std::size_t brick = 0;
    for (std::size_t cells = 0; brick < bricks.size(); ++brick) {
      const auto volume = std::size_t(brick_box(size_, bricks[brick]).volume());
      if (i < cells + volume) return "byte " + std::to_string(i) + " (brick " + std::to_string(bricks[brick]) + ")";
      cells += volume;
    }
    return "byte " + std::to_string(i);
  });
  // A rewound tick moves the 8-tick activity cycle against the cells: every brick wakes, as after
  // load(), so that sparse stepping stays exact whatever it held.
  if (whole_grid_is_faster(size_, bytes.size())) {
    std::vector<std::uint8_t> whole = read_cells(Box{{0, 0, 0}, size_});
    for_each_brick_row(size_, bricks, [&](std::size_t cell, std::size_t offset, std::size_t w) {
      std::copy_n(bytes.data() + offset, w, whole.data() + cell);
    });
    write_grid(whole, bricks);
  } else if (bricks.empty()) {
    // Nothing to write: brick 0 gets its own bytes back, a write that wakes every brick.
    const std::vector<std::uint8_t> own = read_cells(brick_box(size_, 0));
    live().write(brick_box(size_, 0), own, all_bricks(size_));
  } else {
    mark_bricks(bricks);
    const std::vector<std::uint32_t> every = all_bricks(size_);
    bool woken = false;
    for_each_brick(size_, bricks, [&](const Box& box, std::size_t offset) {
      live().write(box, bytes.subspan(offset, std::size_t(box.volume())),
                   woken ? std::span<const std::uint32_t>() : std::span<const std::uint32_t>(every));
      woken = true;
    });
  }
  tick_ = tick;
  tool_calls_ = tool_calls;
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

ChangeReport World::finish_tool(bool clipped) {
  write_edit();
  ChangeReport report = scratch_->edit.report();
  report.region = scratch_->edit.region();
  report.clipped = clipped;
  ++tool_calls_;
  return report;
}

Box World::tool_box(const Box& region) const {
  if (!slab_tools_) return region;
  const Int3 o = slab_tools_->origin;
  const Box in = intersect(Box{{region.min.x - o.x, region.min.y - o.y, region.min.z - o.z},
                               {region.max.x - o.x, region.max.y - o.y, region.max.z - o.z}},
                           slab_tools_->owned);
  if (in.empty())
    throw StateError("World: a tool's region " + box_string(region) + " misses the cells this slab owns, " +
                     box_string(slab_tools_->owned) + " from " + to_string(o));
  return in;
}

std::vector<std::uint64_t> World::pour_keys(const Sphere& sphere, std::size_t amount) {
  bool clipped = false;
  const Box region = tool_box(sphere_region(sphere, tool_space(), "pour", clipped));
  RegionEdit& edit = begin_edit(region);
  std::vector<std::uint64_t> keys;
  for (const PourCandidate& c :
       scratch_->pour.choose(edit, sphere, pour_salt(def_.seed, tick_, tool_calls_), amount))
    keys.push_back(c.key);
  edit.trim();
  scratch_->pour.trim();
  return keys;
}

ChangeReport World::dig(const Sphere& sphere) {
  bool clipped = false;
  const Box region = tool_box(sphere_region(sphere, tool_space(), "dig", clipped));
  const MaterialTable& table = rules().materials;
  MaterialMap to{};
  for (std::size_t m = 0; m < to.size(); ++m)
    to[m] = table[m].behaviour == Behaviour::Static ? std::uint8_t(m) : to_cell(Material::Void);
  begin_edit(region).map_materials(sphere, to);
  return finish_tool(clipped);
}

ChangeReport World::shake(const Sphere& sphere, int level) {
  check_shake(rules(), level);
  bool clipped = false;
  const Box region = tool_box(sphere_region(sphere, tool_space(), "shake", clipped));
  const StepMaterials mats = step_materials(rules().materials);
  RegionEdit& edit = begin_edit(region);
  for_each_run_in_sphere(region, sphere, [&](int y, int z, int first, int last) {
    const RegionEdit::Row row = edit.row(y, z);
    for (int x = first; x < last; ++x) {
      const std::uint8_t cell = edit.byte(row.cell(x));
      if (!mats.is_faller(cell_material(cell))) continue;
      const auto shaken = std::uint8_t((cell & ~(kMotionLevelMask << kMotionShift)) | (level << kMotionShift));
      if (shaken != cell) edit.set_motion(row.cell(x), row.flag(x), shaken);
    }
  }, edit.origin());
  return finish_tool(clipped);
}

ChangeReport World::pour(Vec3 center, double radius, Material material, std::int64_t amount) {
  const Sphere sphere{center, radius};
  bool clipped = false;
  const Box region = tool_box(check_pour(sphere, material, amount, tool_space(), clipped));
  RegionEdit& edit = begin_edit(region);
  const std::uint64_t salt = pour_salt(def_.seed, tick_, tool_calls_);
  for (const PourCandidate& c : scratch_->pour.choose(edit, sphere, salt, std::size_t(amount))) {
    const Int3 g = unpack_position(c.position), o = edit.origin();
    const Int3 p{g.x - o.x, g.y - o.y, g.z - o.z};
    const RegionEdit::Row row = edit.row(p.y, p.z);
    edit.set_material(row.cell(p.x), row.flag(p.x), to_cell(material));
  }
  scratch_->pour.trim();
  return finish_tool(clipped);
}

ChangeReport World::paint(const Box& box, Material material) {
  bool clipped = false;
  const Box region = tool_box(check_paint_box(box, material, tool_space(), clipped));
  MaterialMap to{};
  to.fill(to_cell(material));
  begin_edit(region).map_materials(to);
  return finish_tool(clipped);
}

ChangeReport World::paint(const Sphere& sphere, Material material) {
  check_tool_material(material, "paint");
  bool clipped = false;
  const Box region = tool_box(sphere_region(sphere, tool_space(), "paint", clipped));
  MaterialMap to{};
  to.fill(to_cell(material));
  begin_edit(region).map_materials(sphere, to);
  return finish_tool(clipped);
}

}  // namespace granular
