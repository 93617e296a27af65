/// @file world_bodies.cpp
/// World's rigid bodies: adding, moving and removing them, and writing them into the grid at the
/// start of each tick (docs/design/bodies.md).

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "world/world_body_set.hpp"
#include "bodies/body_region.hpp"
#include "bodies/body_shape.hpp"
#include "granular/bricks.hpp"
#include "granular/errors.hpp"
#include "granular/extend/backend.hpp"
#include "granular/grid.hpp"
#include "granular/rule_set.hpp"
#include "granular/time_scale.hpp"
#include "step/brick_grid.hpp"
#include "granular/world.hpp"
#include "util/number_text.hpp"
#include "util/stopwatch.hpp"
#include "world/region_edit.hpp"
#include "world/world_scratch.hpp"
#include "cpu/thread_pool.hpp"
#include "granular/extend/threads.hpp"

namespace granular {

namespace {

constexpr double kMaxCoordinate = 1 << 23;  ///< cells: far past any grid, still exact in a double

/// The most cells of a body's region whose bytes it keeps, so that its next tick at rest needs no
/// read: a body of 64 cells across, with its reach.
constexpr std::size_t kMaxKeptRegion = std::size_t(1) << 18;

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
double length(const Vec3& v) { return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }

void check_pose(const BodyPose& p, const std::string& who) {
  if (!finite(p.position) || std::abs(p.position.x) > kMaxCoordinate || std::abs(p.position.y) > kMaxCoordinate ||
      std::abs(p.position.z) > kMaxCoordinate)
    throw InvalidArgument(who + ".position = " + vec_text(p.position) + "; use finite cells within +-" +
                          number_text(kMaxCoordinate));
  const Quat& q = p.orientation;
  const double norm = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  if (!std::isfinite(norm) || norm < 1e-6)
    throw InvalidArgument(who + ".orientation = (" + number_text(q.w) + ", " + number_text(q.x) + ", " +
                          number_text(q.y) + ", " + number_text(q.z) +
                          "); a rotation is a finite quaternion of non-zero length");
  if (!finite(p.velocity) || length(p.velocity) > kMaxBodySpeed)
    throw InvalidArgument(who + ".velocity = " + vec_text(p.velocity) + " cells per tick; its length must be at most " +
                          number_text(kMaxBodySpeed));
  if (!finite(p.angular_velocity) || length(p.angular_velocity) > kMaxBodySpin)
    throw InvalidArgument(who + ".angular_velocity = " + vec_text(p.angular_velocity) +
                          " radians per tick; its length must be at most " + number_text(kMaxBodySpin));
}

/// Throws InvalidArgument, starting with `who`, for a definition add_body refuses.
void check_def(const BodyDef& def, const std::string& who) {
  auto size = [&](double v, const char* field, bool zero_ok) {
    if (!(std::isfinite(v) && (zero_ok ? v >= 0 : v > 0) && v <= kMaxBodyHalfSize))
      throw InvalidArgument(who + ": BodyDef::" + field + " = " + number_text(v) + "; use " +
                            (zero_ok ? "0" : "a size above 0") + " .. " + number_text(kMaxBodyHalfSize) + " cells");
  };
  switch (def.shape) {
    case BodyShape::Box:
      size(def.half_extents.x, "half_extents.x", false);
      size(def.half_extents.y, "half_extents.y", false);
      size(def.half_extents.z, "half_extents.z", false);
      break;
    case BodyShape::Capsule:
      size(def.half_length, "half_length", true);
      [[fallthrough]];
    case BodyShape::Sphere:
      size(def.radius, "radius", false);
      break;
    default:
      throw InvalidArgument(who + ": BodyDef::shape = " + std::to_string(unsigned(def.shape)) +
                            " is not a BodyShape; use Box, Sphere or Capsule");
  }
  if (!(std::isfinite(def.density) && def.density > 0 && def.density <= 1e5))
    throw InvalidArgument(who + ": BodyDef::density = " + number_text(def.density) +
                          "; use kg/m^3 above 0 and at most 100000");
  check_pose(def.pose, who + ": BodyDef::pose");
}

/// `q` turned by the rotation vector `w` (radians), normalised.
Quat turned(const Quat& q, const Vec3& w) {
  const double angle = length(w);
  if (angle == 0) return q;
  const double s = std::sin(angle / 2) / angle, c = std::cos(angle / 2);
  const Quat d{c, w.x * s, w.y * s, w.z * s};
  Quat r{d.w * q.w - d.x * q.x - d.y * q.y - d.z * q.z, d.w * q.x + d.x * q.w + d.y * q.z - d.z * q.y,
         d.w * q.y - d.x * q.z + d.y * q.w + d.z * q.x, d.w * q.z + d.x * q.y - d.y * q.x + d.z * q.w};
  const double n = std::sqrt(r.w * r.w + r.x * r.x + r.y * r.y + r.z * r.z);
  return {r.w / n, r.x / n, r.y / n, r.z / n};
}

}  // namespace

BodyId World::add_body(const BodyDef& def) {
  live();
  if (slab_tools_) throw StateError("World::add_body: a DistributedWorld's slab holds no bodies");
  check_def(def, "World::add_body");
  check_body_material("World::add_body");
  if (!bodies_) bodies_ = std::make_unique<Bodies>();
  if (bodies_->list.size() >= kMaxBodies)
    throw InvalidArgument("World::add_body: the world holds " + std::to_string(bodies_->list.size()) +
                          " bodies, the most it takes (kMaxBodies)");
  bodies_->list.push_back(body_record(bodies_->next++, def));
  note_body_change();
  return bodies_->list.back().id;
}

void World::check_body_material(const std::string& who) const {
  const std::uint8_t m = to_cell(def_.body_material);
  if (rules_->materials[m].behaviour != Behaviour::Static)
    throw InvalidArgument(who + ": WorldDef::body_material = " + std::to_string(unsigned(m)) + " ('" +
                          rules_->materials[m].name + "') is " + behaviour_name(rules_->materials[m].behaviour) +
                          " in rule set '" + rules_->name + "'; a body's cells need a static material");
}

BodyRecord World::body_record(BodyId id, const BodyDef& def) const {
  BodyRecord body;
  body.id = id;
  body.def = def;
  body.pose = def.pose;
  const double volume = shape_volume(def) * def_.cell_metres * def_.cell_metres * def_.cell_metres;
  body.mass = def.density * volume;
  const double radius = std::cbrt(3 * volume / (4 * std::numbers::pi));
  body.moment = 0.4 * body.mass * radius * radius;
  body.sand.mass = body.mass;
  return body;
}

void World::note_body_change() { ++change_version_; }

namespace {

/// The body `id` of `all` (World::Bodies, or null before the first add_body); InvalidArgument naming
/// `who` when there is none.
template <class Bodies>
auto& find_body(Bodies* all, BodyId id, const char* who) {
  if (all) {
    const auto it = std::find_if(all->list.begin(), all->list.end(), [&](const BodyRecord& b) { return b.id == id; });
    if (it != all->list.end()) return *it;
  }
  throw InvalidArgument(std::string(who) + ": no body " + std::to_string(id) + " in this world");
}

}  // namespace

void World::remove_body(BodyId id) {
  live();
  BodyRecord& body = find_body(bodies_.get(), id, "World::remove_body");
  release_body_cells(body.owned);
  bodies_->list.erase(bodies_->list.begin() + (&body - bodies_->list.data()));
  note_body_change();
}

namespace {

/// The box of the cells `cells` (grid indices of a grid of `size`); empty for none.
Box bounds_of(const std::vector<std::uint64_t>& cells, Int3 size) {
  if (cells.empty()) return {};
  Box b{grid_cell(size, cells.front()), grid_cell(size, cells.front())};
  for_each_cell_at(cells, size, [&](Int3 c) {
    b.min = {std::min(b.min.x, c.x), std::min(b.min.y, c.y), std::min(b.min.z, c.z)};
    b.max = {std::max(b.max.x, c.x), std::max(b.max.y, c.y), std::max(b.max.z, c.z)};
  });
  b.max = {b.max.x + 1, b.max.y + 1, b.max.z + 1};
  return b;
}

/// `b` grown by `d` cells on every side.
Box grown(const Box& b, int d) {
  return {{b.min.x - d, b.min.y - d, b.min.z - d}, {b.max.x + d, b.max.y + d, b.max.z + d}};
}

/// The smallest box holding `a` and `b` (either may be empty).
Box joined(const Box& a, const Box& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  return {{std::min(a.min.x, b.min.x), std::min(a.min.y, b.min.y), std::min(a.min.z, b.min.z)},
          {std::max(a.max.x, b.max.x), std::max(a.max.y, b.max.y), std::max(a.max.z, b.max.z)}};
}

}  // namespace

void World::release_body_cells(std::vector<std::uint64_t>& owned) {
  if (owned.empty()) return;
  RegionEdit& edit = begin_edit(bounds_of(owned, size_));
  const std::uint8_t m = to_cell(def_.body_material);
  for (const std::uint64_t g : owned) {
    const Int3 c = grid_cell(size_, g);
    const RegionEdit::Row row = edit.row(c.y, c.z);
    if ((edit.byte(row.cell(c.x)) & kMaterialMask) == m) edit.put(row.cell(c.x), row.flag(c.x), 0);
  }
  write_edit();
  owned.clear();
}

void World::set_body_pose(BodyId id, const BodyPose& pose) {
  live();
  BodyRecord& body = find_body(bodies_.get(), id, "World::set_body_pose");
  check_pose(pose, "World::set_body_pose: pose");
  body.pose = pose;
  note_body_change();
}

BodyPose World::body_pose(BodyId id) const {
  live();
  return find_body(bodies_.get(), id, "World::body_pose").pose;
}

BodyDef World::body_def(BodyId id) const {
  live();
  const BodyRecord& body = find_body(bodies_.get(), id, "World::body_def");
  BodyDef def = body.def;
  def.pose = body.pose;
  return def;
}

std::span<const std::uint64_t> World::body_cells(BodyId id) const {
  live();
  return find_body(bodies_.get(), id, "World::body_cells").owned;
}

const BodySand& World::body_sand(BodyId id) const {
  live();
  return find_body(bodies_.get(), id, "World::body_sand").sand;
}

std::vector<BodyId> World::body_ids() const {
  live();
  std::vector<BodyId> ids;
  if (bodies_)
    for (const BodyRecord& b : bodies_->list) ids.push_back(b.id);
  return ids;
}

BodyStates World::body_states() const {
  live();
  BodyStates states;
  if (!bodies_) return states;
  states.next_id = bodies_->next;
  states.bodies.reserve(bodies_->list.size());
  for (const BodyRecord& b : bodies_->list) {
    BodyState& state = states.bodies.emplace_back();
    state.id = b.id;
    state.def = b.def;
    state.def.pose = b.pose;
    state.cells = b.owned;
  }
  return states;
}

void World::check_body_states(const BodyStates& states, const std::string& who, const CellReader& read) const {
  if (states.bodies.size() > kMaxBodies)
    throw InvalidArgument(who + ": " + std::to_string(states.bodies.size()) + " bodies; a world holds at most " +
                          std::to_string(kMaxBodies) + " (kMaxBodies)");
  if (states.next_id == 0) throw InvalidArgument(who + ": BodyStates::next_id = 0; handles start at 1");
  if (states.bodies.empty()) return;
  if (slab_tools_) throw StateError(who + ": a DistributedWorld's slab holds no bodies");
  check_body_material(who);
  const std::uint64_t total = std::uint64_t(size_.x) * std::uint64_t(size_.y) * std::uint64_t(size_.z);
  const std::uint8_t m = to_cell(def_.body_material);
  std::vector<std::pair<std::uint64_t, std::size_t>> held;  // (cell, body) of every cell, to find one held twice
  std::vector<std::uint8_t> bytes;
  for (std::size_t i = 0; i < states.bodies.size(); ++i) {
    const BodyState& b = states.bodies[i];
    const std::string body = who + ": bodies[" + std::to_string(i) + "] (body " + std::to_string(b.id) + ")";
    if (b.id == 0 || b.id >= states.next_id)
      throw InvalidArgument(body + ": the handle " + std::to_string(b.id) + " is not one of 1.." +
                            std::to_string(states.next_id - 1) + " (BodyStates::next_id = " +
                            std::to_string(states.next_id) + ")");
    check_def(b.def, body);
    for (std::size_t k = 0; k < b.cells.size(); ++k) {
      if (b.cells[k] >= total)
        throw InvalidArgument(body + ": cells[" + std::to_string(k) + "] = " + std::to_string(b.cells[k]) +
                              " is outside the " + to_string(size_) + " grid's " + std::to_string(total) + " cells");
      if (k > 0 && b.cells[k] <= b.cells[k - 1])
        throw InvalidArgument(body + ": cells[" + std::to_string(k) + "] = " + std::to_string(b.cells[k]) +
                              " does not follow cells[" + std::to_string(k - 1) + "] = " +
                              std::to_string(b.cells[k - 1]) + "; a body's cells are ascending grid indices");
      held.emplace_back(b.cells[k], i);
    }
    if (b.cells.empty()) continue;
    const Box box = bounds_of(b.cells, size_);
    bytes.resize(std::size_t(box.volume()));
    read(box, bytes);
    for (std::size_t k = 0; k < b.cells.size(); ++k) {
      const Int3 c = grid_cell(size_, b.cells[k]);
      const std::uint8_t cell = bytes[grid_index(Int3{box.max.x - box.min.x, box.max.y - box.min.y, box.max.z - box.min.z}, c.x - box.min.x, c.y - box.min.y, c.z - box.min.z)];
      if ((cell & kMaterialMask) != m)
        throw InvalidArgument(body + ": cells[" + std::to_string(k) + "], cell " + to_string(c) + ", holds material " +
                              std::to_string(unsigned(cell & kMaterialMask)) + ", not WorldDef::body_material " +
                              std::to_string(unsigned(m)) + ": the grid is not the one these bodies were taken with");
    }
  }
  std::vector<BodyId> ids;
  for (const BodyState& b : states.bodies) ids.push_back(b.id);
  std::sort(ids.begin(), ids.end());
  if (const auto twice = std::adjacent_find(ids.begin(), ids.end()); twice != ids.end())
    throw InvalidArgument(who + ": two bodies have the handle " + std::to_string(*twice));
  std::sort(held.begin(), held.end());
  for (std::size_t k = 1; k < held.size(); ++k)
    if (held[k].first == held[k - 1].first)
      throw InvalidArgument(who + ": cell " + to_string(grid_cell(size_, held[k].first)) + " is held by bodies[" +
                            std::to_string(held[k - 1].second) + "] and bodies[" + std::to_string(held[k].second) + "]");
}

void World::put_bodies(const BodyStates& states) {
  if (states.bodies.empty() && states.next_id == 1 && !bodies_) return;
  if (!bodies_) bodies_ = std::make_unique<Bodies>();
  bodies_->list.clear();
  for (const BodyState& b : states.bodies) {
    BodyRecord& body = bodies_->list.emplace_back(body_record(b.id, b.def));
    body.owned = b.cells;
  }
  bodies_->next = states.next_id;
  note_body_change();
}

void World::restore_bodies(const BodyStates& states) {
  live();
  check_body_states(states, "World::restore_bodies",
                    [this](const Box& box, std::span<std::uint8_t> out) { live().read(box, out); });
  put_bodies(states);
}

namespace {

/// Sets every body's `group` to the first body of its group: bodies whose regions overlap, directly
/// or through others (a sweep along x over the regions, joined by union-find). Returns the bodies
/// of each group, in the order added; bodies without a region are in none.
std::vector<std::vector<std::size_t>> group_bodies(std::vector<BodyStampWork>& work) {
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < work.size(); ++i) {
    work[i].group = i;
    if (!work[i].region.empty()) order.push_back(i);
  }
  auto root = [&](std::size_t i) {
    while (work[i].group != i) i = work[i].group = work[work[i].group].group;
    return i;
  };
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return work[a].region.min.x < work[b].region.min.x; });
  for (std::size_t k = 0; k < order.size(); ++k)
    for (std::size_t l = k + 1; l < order.size() && work[order[l]].region.min.x < work[order[k]].region.max.x; ++l)
      if (!intersect(work[order[k]].region, work[order[l]].region).empty()) {
        const std::size_t a = root(order[k]), b = root(order[l]);
        work[std::max(a, b)].group = std::min(a, b);
      }
  for (std::size_t i = 0; i < work.size(); ++i) work[i].group = root(i);
  std::vector<std::vector<std::size_t>> groups;
  std::vector<std::size_t> group_of(work.size(), 0);  // where a group's first body's group is in `groups`
  for (std::size_t i = 0; i < work.size(); ++i) {
    if (work[i].region.empty()) continue;
    if (work[i].group == i) {
      group_of[i] = groups.size();
      groups.emplace_back();
    }
    groups[group_of[work[i].group]].push_back(i);
  }
  return groups;
}

/// Copies the cells of `from`'s region that `to`'s region holds too into `to`: what an earlier body
/// of the group wrote, before a later one is stamped.
void copy_overlap(const RegionEdit& from, RegionEdit& to) {
  const Box o = intersect(from.region(), to.region());
  if (o.empty()) return;
  const std::size_t w = std::size_t(o.max.x - o.min.x);
  for (int z = o.min.z; z < o.max.z; ++z)
    for (int y = o.min.y; y < o.max.y; ++y)
      std::copy_n(from.cells().data() + from.row(y, z).cell(o.min.x), w,
                  to.cells().data() + to.row(y, z).cell(o.min.x));
}

/// Tasks for `items` items on `tasks`: one a thread, and no more than the items.
int tasks_for(const TaskSystem& tasks, std::size_t items) {
  return int(std::min<std::size_t>(items, std::size_t(std::max(1, tasks.thread_count()))));
}

/// Runs `count` tasks on `tasks`: task t calls first(t), then takes the items 0 .. items - 1 one at a
/// time, whichever task is free, calling fn(item, t). Which task takes an item depends on the times,
/// so what fn computes must not.
template <class First, class Fn>
void share_out(TaskSystem& tasks, int count, std::size_t items, First&& first, Fn&& fn) {
  std::atomic<std::size_t> next{0};
  tasks.run(count, [&](int task) {
    first(task);
    for (std::size_t item = next++; item < items; item = next++) fn(item, task);
  });
}

}  // namespace

std::span<std::uint8_t> World::boxes_buffer(std::span<const Box> boxes, std::vector<std::uint8_t>& own) {
  std::uint64_t cells = 0;
  for (const Box& box : boxes) cells += std::uint64_t(box.volume());
  if (const std::span<std::uint8_t> backend = live().transfer_buffer(cells); !backend.empty()) return backend;
  try {
    own.resize(std::size_t(cells));
  } catch (const std::bad_alloc&) {
    throw OutOfMemory("World: could not allocate " + std::to_string(cells) + " bytes for the regions of " +
                      std::to_string(boxes.size()) + " bodies");
  }
  return own;
}

TaskSystem& World::body_tasks() {
  Bodies& all = *bodies_;
  if (!all.tasks) {
    if (def_.task_system)
      all.tasks = def_.task_system;
    else if (TaskSystem* backend = live().host_tasks())
      all.tasks = std::shared_ptr<TaskSystem>(std::shared_ptr<TaskSystem>(), backend);
    else
      all.tasks = std::make_shared<ThreadPool>(resolve_threads(def_.threads, "WorldDef::threads"));
  }
  return *all.tasks;
}

void World::stamp_bodies() {
  Bodies& all = *bodies_;
  Stopwatch whole, watch;
  const std::uint8_t body_material = to_cell(def_.body_material);
  // True when no brick of `region` changed since `version` (brick_version_).
  auto unchanged = [&](const Box& region, std::uint64_t version) {
    const Int3 bricks = brick_counts();
    for (int z = brick_of(region.min.z); z <= brick_of(region.max.z - 1); ++z)
      for (int y = brick_of(region.min.y); y <= brick_of(region.max.y - 1); ++y)
        for (int x = brick_of(region.min.x); x <= brick_of(region.max.x - 1); ++x)
          if (brick_version_[brick_index(bricks, x, y, z)] > version) return false;
    return true;
  };
  const std::size_t n = all.list.size();
  all.work.resize(n);
  TaskSystem& tasks = body_tasks();
  // Each body's shape (its cells and their bounds), then its region: its old and new cells and the
  // reach of the pushes around them. A body that jumped farther than that leaves its old cells
  // first, so the region stays its size.
  auto region_of = [&](const BodyRecord& body, const BodyStampWork& work) {
    if (work.shape.empty() && body.owned.empty()) return Box{};  // wholly outside the grid
    return intersect(grown(joined(work.held, work.bounds), kBodyReach), Box{{0, 0, 0}, size_});
  };
  // A body at rest holds its whole shape in a region nothing changed since its last stamp. A group
  // of bodies whose regions overlap is stamped in the order the bodies were added, each seeing what
  // the ones before it wrote; a group whose bodies all rest would change nothing, and its reports
  // come from the bytes they kept. Groups touch disjoint cells, so they are stamped at once.
  auto rests = [&](const BodyRecord& body, const BodyStampWork& work) {
    return !work.region.empty() && work.shape == body.owned && work.region == body.region &&
           !body.region_bytes.empty() && unchanged(work.region, body.version);
  };
  std::vector<std::uint8_t> jumped(n, 0);
  auto shape = [&](std::size_t i) {
    BodyRecord& body = all.list[i];
    BodyStampWork& work = all.work[i];
    const PlacedShape placed(body.def, body.pose);
    placed.cells(size_, work.shape);
    work.bounds = work.shape.empty() ? Box{} : placed.bounds(size_);
    work.held = bounds_of(body.owned, size_);
    work.changes = 0;  // the cells its shape gains and loses, both lists ascending
    for (auto a = work.shape.begin(), b = body.owned.begin(); a != work.shape.end() || b != body.owned.end();) {
      const bool gained = b == body.owned.end() || (a != work.shape.end() && *a < *b);
      const bool lost = !gained && (a == work.shape.end() || *b < *a);
      work.changes += gained || lost;
      if (!lost) ++a;
      if (!gained) ++b;
    }
    jumped[i] = !work.held.empty() && !work.bounds.empty() &&
                intersect(grown(work.held, kBodyReach), grown(work.bounds, kBodyReach)).empty();
    work.region = jumped[i] ? Box{} : region_of(body, work);
    work.stamped = false;
    body.sand = BodySand{};
    body.sand.tick = tick_;
    body.sand.mass = body.mass;
  };
  // The shapes on the world's threads, a body at a time to whichever is free; one of them first
  // takes the bricks the last tick changed (from the device, on a GPU), for the rest check.
  share_out(
      tasks, tasks_for(tasks, n), n,
      [&](int task) {
        if (task == 0) take_step_changes();
      },
      [&](std::size_t i, int) { shape(i); });
  for (std::size_t i = 0; i < n; ++i)
    if (jumped[i]) {
      release_body_cells(all.list[i].owned);
      all.work[i].held = {};
      all.work[i].region = region_of(all.list[i], all.work[i]);
    }
  for (std::size_t i = 0; i < n; ++i) all.work[i].at_rest = rests(all.list[i], all.work[i]);
  const std::vector<std::vector<std::size_t>> groups = group_bodies(all.work);
  std::vector<std::uint8_t> group_moves(n, 0);  // per group's first body
  for (std::size_t i = 0; i < n; ++i)
    if (!all.work[i].region.empty() && !all.work[i].at_rest) group_moves[all.work[i].group] = 1;
  // The regions of the groups that move, in one read (one round trip on a GPU); the task that
  // stamps a body copies its region's bytes out of it.
  std::vector<std::size_t> moving;  // the bodies of those groups, in the order added
  std::vector<Box> boxes;
  std::vector<std::size_t> read_at(n, 0);  // per body of `moving`: where its bytes start in `packed`
  std::size_t bytes = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (!all.work[i].region.empty() && group_moves[all.work[i].group]) {
      moving.push_back(i);
      boxes.push_back(all.work[i].region);
      read_at[i] = bytes;
      bytes += std::size_t(all.work[i].region.volume());
    }
  const std::span<std::uint8_t> packed = boxes_buffer(boxes, all.packed);
  profile_.bodies_shapes += watch.lap();
  if (!boxes.empty()) live().read_boxes(boxes, packed);
  profile_.bodies_read += watch.lap();
  const int task_count = tasks_for(tasks, groups.size());
  all.stamp.resize(std::size_t(task_count));
  const MaterialTable& materials = rules_->materials;
  const std::uint64_t seed = def_.seed, tick = tick_;
  const Int3 grid = size_, origin = slab_tools_ ? slab_tools_->origin : Int3{};
  // The groups are taken one at a time by whichever task is free, the costliest first, so that a
  // few costly groups do not all fall to one thread. A body's cost is the cells its shape gains and
  // loses this tick at what a changed cell took in its last stamp that changed any (a body new to
  // the stamp first of all): what it pushes and fills grows with them, and what a cell costs
  // depends on what the body wades through. Groups touch disjoint cells and each task has its own
  // scratch: the cells do not depend on who takes what, nor on the times.
  std::vector<std::size_t> by_cost(groups.size());
  std::vector<double> cost(groups.size(), 0);
  for (std::size_t g = 0; g < groups.size(); ++g) {
    by_cost[g] = g;
    for (const std::size_t i : groups[g]) {
      const BodyStampWork& work = all.work[i];
      if (work.changes > 0)
        cost[g] += work.ms_per_change >= 0 ? double(work.changes) * work.ms_per_change
                                           : std::numeric_limits<double>::infinity();
    }
  }
  std::stable_sort(by_cost.begin(), by_cost.end(), [&](std::size_t a, std::size_t b) { return cost[a] > cost[b]; });
  share_out(
      tasks, task_count, groups.size(), [](int) {},
      [&](std::size_t taken, int task) {
        StampScratch& stamp = all.stamp[std::size_t(task)];
        const std::vector<std::size_t>& members = groups[by_cost[taken]];
        for (std::size_t k = 0; k < members.size(); ++k) {
          BodyRecord& body = all.list[members[k]];
          BodyStampWork& work = all.work[members[k]];
          work.stamped = group_moves[work.group] != 0;
          if (!work.stamped) continue;
          Stopwatch took;
          work.edit.begin(work.region, grid, origin);
          std::copy_n(packed.data() + read_at[members[k]], work.edit.cells().size(), work.edit.cells().data());
          for (std::size_t j = 0; j < k; ++j) copy_overlap(all.work[members[j]].edit, work.edit);
          const StampResult stamped =
              stamp_body(work.region, work.edit.cells(), grid, work.shape, body.owned, body_material, materials,
                         body.pose.velocity, mix64(seed ^ mix64(tick * 0x9E3779B97F4A7C15ull + body.id)), stamp);
          work.edit.flag_written(stamp.written);  // their bricks wake and count as changed
          body.sand.blocked = stamped.blocked;
          body.sand.displaced = stamped.displaced;
          const double took_ms = took.lap();
          if (work.changes > 0) work.ms_per_change = took_ms / double(work.changes);
        }
        // Every region of the group takes the cells its later bodies wrote, so that where regions
        // overlap they agree (the grid after the group), and can be written in any order.
        for (std::size_t k = members.size(); k-- > 0;) {
          if (!group_moves[all.work[members[k]].group]) continue;
          BodyStampWork& work = all.work[members[k]];
          for (std::size_t j = k + 1; j < members.size(); ++j) copy_overlap(all.work[members[j]].edit, work.edit);
          // The bytes it keeps for a tick at rest: its region as the group leaves it.
          BodyRecord& body = all.list[members[k]];
          body.region = work.region;
          if (work.edit.cells().size() <= kMaxKeptRegion)
            body.region_bytes.assign(work.edit.cells().begin(), work.edit.cells().end());
          else
            body.region_bytes.clear();
        }
      });
  profile_.bodies_stamp += watch.lap();
  // The regions the stamps wrote, in one write (one launch on a GPU), waking the bricks they wrote;
  // each region's bytes are copied into the write on the world's threads.
  boxes.clear();
  std::vector<std::size_t> written;  // the moving bodies whose stamp wrote a cell
  std::vector<std::size_t> write_at;  // per body of `written`: where its bytes start in `out`
  std::vector<std::uint32_t> woken;
  bytes = 0;
  for (const std::size_t i : moving) {
    const std::span<const std::uint32_t> bricks = all.work[i].edit.bricks();
    if (bricks.empty()) continue;
    written.push_back(i);
    boxes.push_back(all.work[i].region);
    write_at.push_back(bytes);
    woken.insert(woken.end(), bricks.begin(), bricks.end());
    bytes += all.work[i].edit.cells().size();
  }
  if (!boxes.empty()) {
    const std::span<std::uint8_t> out = boxes_buffer(boxes, all.packed);  // no larger than the read's
    share_out(
        tasks, tasks_for(tasks, written.size()), written.size(), [](int) {},
        [&](std::size_t k, int) {
          const RegionEdit& edit = all.work[written[k]].edit;
          std::copy_n(edit.cells().data(), edit.cells().size(), out.data() + write_at[k]);
        });
    std::sort(woken.begin(), woken.end());
    woken.erase(std::unique(woken.begin(), woken.end()), woken.end());
    mark_bricks(woken);
    live().write_boxes(boxes, out, woken);
  }
  for (const std::size_t i : moving) all.list[i].version = change_version_;
  profile_.bodies_write += watch.lap();
  profile_.bodies += whole.lap();
}

void World::step_sensing_bodies() {
  Bodies& all = *bodies_;
  const BodyScale scale{def_.cell_metres, tick_seconds(*rules_, def_.cell_metres), kStandardGravity};
  const MaterialTable& materials = rules_->materials;
  const std::size_t n = all.list.size();
  TaskSystem& tasks = body_tasks();
  const int task_count = tasks_for(tasks, n);
  all.forces.resize(std::size_t(task_count));
  // What the sand does to each body, from its region as its group's stamps left it (the grid the
  // step starts from): the bytes of its edit where its group was stamped, else those it kept.
  std::vector<double> sensed_ms(std::size_t(task_count), 0);  // per task
  auto sense = [&](std::size_t i, int task) {
    Stopwatch took;
    BodyRecord& body = all.list[i];
    const BodyStampWork& work = all.work[i];
    if (work.region.empty()) return;
    const std::span<const std::uint8_t> bytes =
        work.stamped ? std::span<const std::uint8_t>(work.edit.cells()) : body.region_bytes;
    sand_forces(work.region, bytes, size_, body.owned, materials, body.pose, body.mass, body.moment, scale, body.sand,
                all.forces[std::size_t(task)]);
    sensed_ms[std::size_t(task)] += took.lap();
  };
  Stopwatch watch;
  if (live().host_tasks() == nullptr) {
    // The backend steps on a device and the host only waits for it: the forces are found meanwhile,
    // on the world's threads, one of which steps first.
    share_out(
        tasks, task_count, n,
        [&](int task) {
          if (task == 0) live().step(tick_, 1);
        },
        sense);
    profile_.step += watch.lap();
    profile_.bodies_forces += *std::max_element(sensed_ms.begin(), sensed_ms.end());
  } else {
    // The step needs the host's threads.
    share_out(
        tasks, task_count, n, [](int) {}, sense);
    const double forces = watch.lap();
    profile_.bodies_forces += forces;
    profile_.bodies += forces;
    live().step(tick_, 1);
    profile_.step += watch.lap();
  }
  for (BodyStampWork& work : all.work)
    if (work.stamped) work.edit.trim();
}

void World::advance_bodies() {
  for (BodyRecord& body : bodies_->list) {
    const BodyPose& p = body.pose;
    body.pose.position = {p.position.x + p.velocity.x, p.position.y + p.velocity.y, p.position.z + p.velocity.z};
    body.pose.orientation = turned(p.orientation, p.angular_velocity);
  }
}

}  // namespace granular
