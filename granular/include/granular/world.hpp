#pragma once
/// @file world.hpp
/// The simulated world: a grid of cells, the transition table of its rule set, and the backend that
/// steps it. A game creates one from a WorldDef and calls step() once per fixed tick.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "granular/body.hpp"
#include "granular/bricks.hpp"
#include "granular/external_memory.hpp"
#include "granular/geometry.hpp"
#include "granular/grid.hpp"
#include "granular/material.hpp"
#include "granular/step_profile.hpp"
#include "granular/change_report.hpp"
#include "granular/world_def.hpp"
#include "granular/world_snapshot.hpp"

namespace granular {

class Backend;
class TaskSystem;
struct BodyRecord;
class Lut;
class RegionEdit;
struct RuleSet;

/// A block-cellular-automaton world of sand. Not thread-safe: call it from one thread. step() runs
/// on the backend: the CPU backend's parallel loops run on WorldDef::task_system when the game
/// passes one, else on the CPU backend's own pool of WorldDef::threads worker threads; the CUDA
/// backend steps on the GPU.
class World {
 public:
  /// Creates a world of `def.size` void cells. Throws InvalidArgument for a bad def, OutOfMemory
  /// when the grid does not fit, BackendError when the requested backend is unavailable.
  explicit World(const WorldDef& def = {});
  /// Creates a world whose size and cells are those of `initial` (def.size is ignored).
  World(const WorldDef& def, const Grid& initial);
  /// Creates the world of `snapshot`: its size, every cell byte, its tick, tool calls and seed
  /// (def.size and def.seed are ignored), so that it continues as the world it was captured from.
  /// def's rule set (def.rule_set, else the preset def.rules) must be the snapshot's: pass
  /// def.rules = snapshot.rules for a preset. Throws InvalidArgument naming both rule sets when the
  /// fingerprints differ, and for cells that rule set cannot hold (see restore()).
  World(const WorldDef& def, const WorldSnapshot& snapshot);
  ~World();
  /// Moves the world; every call on the moved-from one, but destruction and assignment, throws
  /// StateError.
  World(World&&) noexcept;
  /// Moves the world (see the move constructor).
  World& operator=(World&&) noexcept;
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  /// Advances `ticks` fixed ticks. ticks >= 0. A tick is one Margolus step (one partition of the
  /// 8-offset cycle) under a rule set without a motion model (paper, isotropic, d4), and
  /// MotionParams::substeps Margolus sub-steps under one: 24 for the default rules
  /// (inertial-24-flow, and every inertial-24 preset), 16 for inertial.
  void step(int ticks = 1);

  /// Ticks done since creation (the position in the offset cycle is tick() % 8), or since the tick
  /// a snapshot or an undo put back.
  std::uint64_t tick() const { return tick_; }
  /// Calls of dig, shake, pour and paint since creation (each counts one, whatever it changes), or
  /// since the count a snapshot or an undo put back: pour salts its choice of cells with it.
  std::uint64_t tool_calls() const { return tool_calls_; }
  /// Grid extent.
  Int3 size() const { return size_; }
  /// The definition this world was made from (size updated to the actual grid).
  const WorldDef& def() const { return def_; }
  /// The backend actually stepping the world.
  BackendKind backend() const;
  /// The backend's name with details (e.g. "cpu (2 threads)").
  std::string backend_description() const;
  /// The rule set.
  const RuleSet& rules() const;
  /// The transition table in use.
  const Lut& lut() const;
  /// One-line notices from creation a user should see (backend fallback, table cache problems).
  const std::vector<std::string>& notices() const { return notices_; }
  /// Seconds spent obtaining the transition table at creation, and whether it came from the cache.
  double lut_seconds() const { return lut_seconds_; }
  /// True when the transition table was loaded from the on-disk cache (or shared in-process).
  bool lut_from_cache() const { return lut_from_cache_; }

  /// Removes every mobile cell (a granular, liquid or gas material of the rule set's table: static
  /// ones stay) whose cell centre lies in `sphere`.
  /// Throws InvalidArgument for a non-finite centre, radius <= 0, or a sphere that misses the grid.
  ChangeReport dig(const Sphere& sphere);
  /// Sets every granular and liquid cell whose centre lies in `sphere` moving at motion level `level`
  /// (1 .. MotionParams::max_level()), as if thrown: it rolls and topples on, and grains of two
  /// densities pass each other while one of them moves, so shaking a mixed bed again and again sorts
  /// the heavier grain below. Changes no material (ChangeReport::cells_shaken counts the cells).
  /// Throws InvalidArgument for a rule set without a motion model, a level out of range, or a sphere
  /// as dig refuses.
  ChangeReport shake(const Sphere& sphere, int level);
  /// Turns up to `amount` void cells inside the sphere (centre, radius) into `material`, chosen
  /// pseudo-randomly (deterministic for the world's seed and tick). Throws InvalidArgument for
  /// void or an invalid material, amount < 0, or a region missing the grid.
  ChangeReport pour(Vec3 center, double radius, Material material, std::int64_t amount);
  /// Sets every cell of `box` to `material` (solid included). Throws InvalidArgument when the
  /// box is empty or misses the grid.
  ChangeReport paint(const Box& box, Material material);
  /// Sets every cell whose centre lies in `sphere` to `material` (the brush form of paint).
  ChangeReport paint(const Sphere& sphere, Material material);

  /// Adds a rigid body (body.hpp; docs/design/bodies.md) and returns its handle. From the next tick
  /// on, each tick starts by writing every body into the grid at its pose as cells of
  /// WorldDef::body_material: the cells it left become void, and the grains, liquid and gas in its new
  /// cells are pushed out to free cells near it, every material conserved. Its pose then moves by its
  /// velocity. Throws InvalidArgument naming the field for a shape, size, density or pose out of
  /// range (sizes 0 < s <= kMaxBodyHalfSize, density 0 < d <= 1e5 kg/m^3, finite poses, speeds up
  /// to kMaxBodySpeed and spins up to kMaxBodySpin), for a body_material that is not static in the
  /// rule set, and past kMaxBodies bodies; StateError on a DistributedWorld's slab.
  BodyId add_body(const BodyDef& def);
  /// Removes a body: its cells become void at once. Throws InvalidArgument for an unknown id.
  void remove_body(BodyId id);
  /// Sets where a body is written at the next tick and how it moves after (the game's or its physics
  /// engine's pose each tick). Throws InvalidArgument as add_body does for a pose, or an unknown id.
  void set_body_pose(BodyId id, const BodyPose& pose);
  /// Where a body will be written at the next tick. Throws InvalidArgument for an unknown id.
  BodyPose body_pose(BodyId id) const;
  /// What a body is: the BodyDef it was added with, its pose the one body_pose() gives (how a physics
  /// engine adapter builds its own body for a World body). Throws InvalidArgument for an unknown id.
  BodyDef body_def(BodyId id) const;
  /// The grid indices (x fastest, ascending) of the cells a body holds now, valid until the next
  /// call that changes bodies or steps (how an engine adapter tells a body's cells from the body
  /// material's other cells). Throws InvalidArgument for an unknown id.
  std::span<const std::uint64_t> body_cells(BodyId id) const;
  /// What the sand did with a body and to it at the start of the last tick (tick 0 and no cells
  /// before its first). Throws InvalidArgument for an unknown id.
  const BodySand& body_sand(BodyId id) const;
  /// The bodies' handles, in the order they were added.
  std::vector<BodyId> body_ids() const;
  /// Every body as it is now: its handle, definition, pose and the cells it holds (what capture()
  /// and an undo keep).
  BodyStates body_states() const;
  /// Replaces every body with those of `states`, whose cells the grid must hold as body_material now
  /// (as after restore_bricks put back the cells of the moment body_states() gave them): how an undo
  /// puts bodies back. The cells are not written; each body's report is empty until the next tick.
  /// The next add_body gives states.next_id, as it did then: a handle taken later than `states` may
  /// name another body after it (body_ids() lists the bodies now). Throws InvalidArgument naming the body and the field for a definition add_body
  /// refuses, a zero, repeated or not-yet-given (>= next_id) handle, more than kMaxBodies bodies,
  /// cells out of the grid, not ascending, held by two bodies or not holding body_material; the
  /// world is unchanged then.
  void restore_bodies(const BodyStates& states);

  /// Cells per material.
  MaterialCounts count() const;
  /// 64-bit hash of the grid's cell bytes, grains' motion state included, and under
  /// MotionParams::momentum of the liquids' velocities while one is not 0 (identical across backends
  /// and thread counts).
  std::uint64_t hash() const;
  /// Copies the materials of the cells of `box` (which must lie inside the grid) into a vector, x
  /// fastest (the motion state of grains is internal, motion.hpp).
  std::vector<std::uint8_t> read_region(const Box& box) const;
  /// Copies the materials of the cells of `box` into `out` (size box.volume()), as the other
  /// read_region.
  void read_region(const Box& box, std::span<std::uint8_t> out) const;
  /// Copies the whole grid's materials into a Grid, without the grains' motion state (a World made
  /// from it starts its grains at rest); capture() gives the whole state, motion included.
  Grid read_grid() const;
  /// Deprecated name of read_grid(), which copies the cells into a Grid (a WorldSnapshot is
  /// capture()'s).
  [[deprecated("use read_grid(); capture() gives the WorldSnapshot")]] Grid snapshot() const { return read_grid(); }
  /// Replaces every cell with those of `grid`, which must have this world's size (a grain whose
  /// material is unchanged keeps its motion state).
  void load(const Grid& grid);

  /// The world's whole state: every cell byte (motion state included), the liquids' velocities under
  /// MotionParams::momentum, the tick, the seed, the tool calls, the rule set's name and fingerprint,
  /// and the bodies (body_states). A world made from it (World(def, snapshot), or restore()) continues
  /// bit-identically: the same hash() after every later tick and tool.
  WorldSnapshot capture() const;
  /// Puts back the state `snapshot` holds: every cell byte, the tick, the tool calls and the bodies
  /// (its bodies replace this world's, as restore_bodies does). Throws InvalidArgument naming the
  /// field and both values for a snapshot of another size, seed or rule set (fingerprint), for a
  /// cell byte the rule set cannot hold (a motion state on a cell that is not granular or liquid, or
  /// under rules without a motion model, or a level above MotionParams::max_level()), and for bodies
  /// restore_bodies refuses; the world is unchanged then.
  /// Every brick wakes, as after load().
  void restore(const WorldSnapshot& snapshot);

  /// Copies the cell bytes (motion state included) of the bricks `bricks` (bricks.hpp indices)
  /// into `out`: brick after brick in the list's order, each brick's cells (brick_box) x fastest.
  /// `out` holds brick_cells(size(), bricks) bytes.
  void read_bricks(std::span<const std::uint32_t> bricks, std::span<std::uint8_t> out) const;
  /// Writes cell bytes laid out as read_bricks gives them into `bricks` and sets the tick and the
  /// tool calls: how an undo puts a past state back. The bytes are checked as restore() checks a
  /// snapshot's (InvalidArgument naming the brick and the cell; the world is unchanged then). Every
  /// brick wakes; bricks_changed_since lists the written ones.
  void restore_bricks(std::span<const std::uint32_t> bricks, std::span<const std::uint8_t> bytes, std::uint64_t tick,
                      std::uint64_t tool_calls);
  /// Keeps a copy of every cell as it is now, the checkpoint, where the backend keeps its cells (host
  /// memory on the CPU, device memory on CUDA), replacing an earlier one. Throws OutOfMemory when it
  /// does not fit, BackendError when the backend keeps no checkpoint (Backend::take_checkpoint).
  void take_checkpoint();
  /// As read_bricks, from the cells as they were at the last take_checkpoint(). Throws StateError
  /// when there is no checkpoint.
  void read_checkpoint_bricks(std::span<const std::uint32_t> bricks, std::span<std::uint8_t> out) const;
  /// Frees the checkpoint, if any.
  void drop_checkpoint();
  /// Bytes the checkpoint holds; 0 when there is none.
  std::uint64_t checkpoint_bytes() const;
  /// Which take_checkpoint() the checkpoint is from, counting this world's calls from 1; 0 when
  /// there is none. A StrokeHistory compares it with its own to notice a checkpoint replaced under it.
  std::uint64_t checkpoint_id() const { return checkpoint_id_; }

  /// A counter that grows with every call that changes cells (step, tools, load, restore and
  /// restore_bricks) or bodies (add_body, remove_body, set_body_pose, restore_bodies). Pass a value read earlier to bricks_changed_since() to learn what changed
  /// after it.
  std::uint64_t change_version() const;
  /// Indices (x fastest, see brick_box) of the bricks whose cells changed after change_version()
  /// returned `version`. Never misses a changed brick. Exact with sparse stepping and for tools
  /// (with a motion model, a brick where only a grain's motion state changed counts as changed);
  /// with dense stepping (WorldDef::sparse = false) a step lists every brick.
  std::vector<std::uint32_t> bricks_changed_since(std::uint64_t version) const;
  /// Bricks per axis (see bricks.hpp).
  Int3 brick_counts() const { return granular::brick_counts(size_); }
  /// How much of the grid the last step() call stepped: its last tick, and sums over its ticks.
  ActivityStats activity() const;
  /// Where the last step() call's time went, phase by phase (host wall time).
  const StepProfile& profile() const { return profile_; }

  /// Bytes a buffer shared with share_cells() must hold (the cells, x fastest, padded to whole
  /// 8-byte words); 0 when the backend cannot share its cells (the CPU backend).
  std::uint64_t shared_cell_bytes() const;
  /// Moves the cells into memory exported by a graphics API (CUDA backend only) and steps them
  /// there in place from now on, so a renderer reads them with no copy. Throws BackendError for
  /// the CPU backend or a failed import, InvalidArgument when the memory is too small; the world is
  /// unchanged then and `memory.fd` stays the caller's.
  void share_cells(const ExternalCellMemory& memory);
  /// Orders writes of the shared cells with a renderer: after this, every call that writes cells
  /// (step, tools, load) first waits on the device until `cells_released` reaches the value of the
  /// last hand_off_cells(), then writes, then signals `cells_ready` with a new, larger value; step()
  /// returns without waiting for the device. Requires share_cells(). Both semaphores must start at 0.
  void attach_timelines(const ExternalTimeline& cells_ready, const ExternalTimeline& cells_released);
  /// Called by the renderer once per frame before it reads the shared cells: the values to wait for
  /// and to signal (CellsHandoff). The signal must be submitted before the next call that writes.
  CellsHandoff hand_off_cells();

 private:
  // A DistributedWorld's slab is a World whose tools take the whole world's shapes and change its
  // owned layers only (slab_tools_), whose pour chooses among the whole world's cells (pour_keys)
  // and which counts the tool calls that miss its slab (tool_calls_).
  friend class DistributedWorld;
  // Where a slab lies in the whole world.
  struct SlabTools {
    Int3 origin;  // the grid's cell (0, 0, 0) in the whole world (WorldDef::domain_origin)
    Int3 whole;   // the whole world's extent
    Box owned;    // the cells the slab's tools change, in the grid's coordinates
  };
  // The extent of the space tools' shapes are in: the grid's, or the whole world's for a slab.
  Int3 tool_space() const { return slab_tools_ ? slab_tools_->whole : size_; }
  // The grid's box of a tool's `region` in tool_space(): a slab's owned part of it (StateError when
  // it holds none).
  Box tool_box(const Box& region) const;
  // The keys of the void cells pour(sphere, ..., amount) would fill, at most `amount` of the
  // smallest (pour_key), in no particular order; changes nothing.
  std::vector<std::uint64_t> pour_keys(const Sphere& sphere, std::size_t amount);
  // Creates the backend for `initial` under `rules` (null: def_.rule_set, else the preset def_.rules).
  void init(const Grid& initial, std::shared_ptr<const RuleSet> rules = nullptr);
  // The backend; throws StateError on a moved-from World.
  Backend& live() const;
  // The factory of the backend to create: def_.backend_factory, or the one `wanted` stands for
  // here (adding a notice when auto falls back to the CPU). Throws BackendError when cuda is
  // wanted and not linked or not usable.
  BackendFactory choose_backend(BackendKind wanted);
  // The cell bytes of `region` as the backend holds them (a material in the low bits, a grain's
  // motion state above, motion.hpp), read in one backend call.
  std::vector<std::uint8_t> read_cells(const Box& region) const;
  // A buffer for the cells of `region`; OutOfMemory naming the region when it cannot be allocated.
  std::vector<std::uint8_t> cell_buffer(const Box& region) const;
  // Writes every cell (whole bytes, x fastest), marks `changed` bricks changed and wakes every brick.
  void write_grid(std::span<const std::uint8_t> cells, std::span<const std::uint32_t> changed);
  // The scratch of the tools and load (the region being edited, pour's choice), reused from call to
  // call.
  struct Scratch;
  // Starts the edit of `region` (scratch_): its cell bytes as the backend holds them (a material
  // in the low bits, a grain's motion state above, motion.hpp), read in one backend call.
  RegionEdit& begin_edit(const Box& region);
  // Writes the edited region with one backend write that also wakes the bricks holding a cell the
  // edit set (marked for bricks_changed_since); writes nothing when it set none. A cell whose
  // material stays keeps its byte, motion state included, so a tool or load changes nothing it
  // does not change in materials (a sleeping brick stays exact).
  void write_edit();
  // A tool's write_edit: the edit's report, with its region and clipping; counts the tool call.
  ChangeReport finish_tool(bool clipped);
  void mark_bricks(std::span<const std::uint32_t> bricks) const;
  // Throws InvalidArgument (starting with `what`) for a brick index past the grid's, or a buffer of
  // `bytes` bytes that is not the bricks' cells.
  void check_bricks(std::span<const std::uint32_t> bricks, std::size_t bytes, const char* what) const;
  // read_bricks through `read(box, out)`: the backend's cells or its checkpoint.
  template <class Read>
  void gather_bricks(std::span<const std::uint32_t> bricks, std::span<std::uint8_t> out, const char* what,
                     Read&& read) const;
  void take_step_changes() const;
  // Writes every body into the grid at its pose (stamp_body), and fills what its BodySand says of that.
  void stamp_bodies();
  // Steps the cells one tick, and fills each body's BodySand forces from its region as the stamps
  // left it: at once where the backend steps on a device, the forces first where the step needs the
  // host's threads.
  void step_sensing_bodies();
  // Moves every body's pose on by its velocity: after a tick.
  void advance_bodies();
  // Turns the cells of `owned` (grid indices) that still hold WorldDef::body_material void, and
  // clears it.
  void release_body_cells(std::vector<std::uint64_t>& owned);
  // Throws InvalidArgument, starting with `who`, when body_material is not static in the rules.
  void check_body_material(const std::string& who) const;
  // A body of handle `id` and definition `def`, at def.pose, holding no cell yet.
  BodyRecord body_record(BodyId id, const BodyDef& def) const;
  // Bodies changed: change_version() grows, so that a StrokeHistory sees it.
  void note_body_change();
  // Reads the cell bytes of a box of the grid, x fastest.
  using CellReader = std::function<void(const Box&, std::span<std::uint8_t>)>;
  // Throws what restore_bodies throws for `states`, starting with `who`, reading the grid's cells
  // through `read`.
  void check_body_states(const BodyStates& states, const std::string& who, const CellReader& read) const;
  // Replaces the bodies with `states` (checked), holding their cells, with empty reports.
  void put_bodies(const BodyStates& states);
  // The threads the bodies are written into the grid on: WorldDef::task_system, else the backend's
  // (Backend::host_tasks), else a pool of WorldDef::threads started at the first need.
  TaskSystem& body_tasks();
  // Memory for the cells of `boxes`, one after the other: the backend's transfer buffer where it has
  // one (Backend::transfer_buffer), else `own`, sized; OutOfMemory naming them when it cannot be had.
  std::span<std::uint8_t> boxes_buffer(std::span<const Box> boxes, std::vector<std::uint8_t>& own);
  // The bodies (world_bodies.cpp).
  struct Bodies;

  WorldDef def_;
  Int3 size_{};
  std::uint64_t tick_ = 0;
  std::uint64_t tool_calls_ = 0;
  std::uint64_t checkpoint_id_ = 0;      ///< checkpoint_id()
  std::uint64_t checkpoints_taken_ = 0;  ///< take_checkpoint() calls so far
  std::shared_ptr<const RuleSet> rules_;
  std::uint64_t rule_fingerprint_ = 0;  ///< rule_fingerprint(*rules_)
  std::shared_ptr<const Lut> lut_;
  std::unique_ptr<Backend> backend_;
  std::unique_ptr<Scratch> scratch_;
  std::unique_ptr<Bodies> bodies_;  ///< null until the first add_body
  std::vector<std::string> notices_;
  std::optional<SlabTools> slab_tools_;  ///< set for a DistributedWorld's slab
  double lut_seconds_ = 0;
  bool lut_from_cache_ = false;
  // Change versions are brought up to date lazily (take_step_changes), so that step() costs no
  // read-back of the backend's changed-brick flags unless somebody asks.
  mutable std::uint64_t change_version_ = 0;
  mutable std::vector<std::uint64_t> brick_version_;  ///< per brick: change_version_ when it last changed
  mutable std::vector<std::uint8_t> changed_flags_;   ///< scratch: per brick, changed by steps
  mutable bool step_changes_pending_ = false;         ///< steps ran since the flags were last taken
  StepProfile profile_{};  ///< the last step() call's
  mutable ActivityStats activity_{};
  mutable bool activity_pending_ = false;  ///< a step ran since activity_ was read from the backend
};

}  // namespace granular
