#pragma once
/// @file shallow_water.hpp
/// MotionParams::shallow: after the last sub-step of every tick, the liquid moves as shallow water,
/// column against column, under open sky and through pipes under a static cover. Plain constexpr
/// integer code on flat arrays, one function per column or per face, that the CPU backend calls
/// over rows of columns and the CUDA kernels one thread a column or face (the plain loop of the
/// tests writes it again); nothing here depends on the order columns or faces are visited in.
///
/// A *column* of the grid has a *room* from a ground up to a ceiling and a *body* in it: the liquid
/// cells from the ground up, each at most kBodyGap void or gas cells above the one below it (the
/// ground for the first). Its depth is their count (the voids between them are not counted); a
/// liquid farther up is in flight, and the pass leaves it to the block step. The scan (ColumnScan)
/// takes the room under open sky: its ground is the cell over the highest cell that is neither
/// void, gas nor liquid, and it has no ceiling. When that room holds no liquid, it takes the
/// highest *covered* room instead, under a static cell (the ceiling) over a body, if there is one;
/// settle_column then gives a covered column back its dry room under open sky when liquid beside it
/// stands at or above that room's ground, so water runs over the top of a pipe. A covered column
/// more than half full is *pressurized*, a pipe.
/// Two neighbouring columns, along x and along y, share a *face*, which holds a velocity (kVelocity
/// units per cell a tick, a staggered grid) and a carried fraction of a cell (kVolume units per
/// cell). The faces are the *face plane*: 4 int32 per column, part of the world's state. A face
/// opens (opening) where the rooms of its columns overlap above the higher ground; one that does
/// not is a wall.
///
/// One tick is kIterations iterations (each 1 / kIterations tick) of:
///  1. surfaces (surface_of): ground + depth, plus the fractions the faces carry in, less those they
///     carry out, so the surfaces the faces see are level to a fraction of a cell;
///  2. heads (head_of, in a grid with a covered column only): a pipe's surface is its head instead:
///     liquid cannot gather in a full pipe, so its steady head falls from one end of the pipe to the
///     other in proportion to the resistance of the faces between (line_head, along x and along y,
///     the mean of the two);
///  3. faces (update_face): a face *passes* liquid when the surface of one of its columns stands
///     above the higher ground (under a cover, counting up to the opening's top only). One that
///     does not stops. Its velocity accelerates down the surface step (g = 2 cells a tick^2), takes
///     its upstream face's velocity at the rate the flow replaces its liquid (a momentum-conserving
///     upwind advection, so a front runs on over a dry bed), and loses some to bed friction: a part
///     proportional to the velocity (less on deep, fast water) and a fixed part that stops slow
///     flows and thin films (never past 0). Its volume is its velocity x the upwind depth x dt,
///     plus its fraction;
///  4. columns (limit_column): a column whose outflow over its four faces exceeds its depth scales
///     its outflows down to it;
///  5. faces (split_face): each face's volume to the nearest whole cell is to move (a half towards
///     none), the rest, at most half a cell, is carried;
///  6. moves, in four phases of disjoint column pairs (even x faces, odd x, even y, odd y;
///     move_face): a move swaps the top of the donor's body with the void or gas just over the
///     receiver's body (or its ground), so every move is a permutation of the grid and every
///     material is conserved exactly; the receiver's body takes in the liquid in flight the move
///     brought within kBodyGap. A move that finds no liquid or no room stops the face, except into
///     a full pipe: that face keeps half its velocity and moves again once the pipe has passed
///     liquid on (a pipe's donor gives the cell under its ceiling, and the room left is filled from
///     upstream).
/// A pool comes to rest: once no face's velocity, rounded, carries anything and every fraction is
/// held, an iteration changes nothing; the backends end the tick's iterations there, and skip a
/// pass that changed nothing while no cell changes (sparse stepping).
/// docs/design/shallow-water.md gives the reasons and the figures.

#include <cstdint>

#include "granular/geometry.hpp"
#include "granular/motion.hpp"
#include "step/step_materials.hpp"

namespace granular::shallow {

/// Iterations of the pass per tick.
inline constexpr int kIterations = 32;
/// Velocity units per cell a tick.
inline constexpr std::int64_t kVelocity = 1 << 16;
/// Volume (and surface) units per cell.
inline constexpr std::int64_t kVolume = 32768;
/// A velocity times a depth (kVolume units) over kTransport is the volume one iteration carries.
inline constexpr std::int64_t kTransport = kVelocity * kIterations;
/// Velocity units a cell of surface step adds in one iteration: g dt = 2 cells a tick^2 x 1/32 tick.
inline constexpr std::int64_t kGravity = kVelocity * 2 / kIterations;
/// The largest speed a face takes (velocity units, 2^14 cells a tick): far above any flow of a
/// grid, so that no product overflows.
inline constexpr std::int32_t kMaxSpeed = 1 << 30;
/// The proportional friction: 1/kFrictionDivisor of the velocity an iteration, divided by depth /
/// kFrictionDepth (cells) beyond that depth for a flow of kSlowFlow or faster (a slow flow in deep
/// water keeps the whole friction, so a deep pool's last waves die out).
inline constexpr std::int64_t kFrictionDivisor = 256, kFrictionDepth = 16, kSlowFlow = kVelocity / 2;
/// The fixed friction: kCoulomb / depth^2 (depth in cells) velocity units an iteration, at least 1:
/// it stops a thin film, and holds a surface step of at most 1 / depth^2 cell a face at rest.
inline constexpr std::int64_t kCoulomb = 4096;

/// The faces of the plane: 0 the x face of a column (to its +x neighbour), 1 its y face.
inline constexpr int kAxes = 2;

/// A column's ceiling when its body lies under open sky (Column::ceiling).
inline constexpr std::int32_t kOpenSky = 2147483647;

/// A column of the grid as the pass sees it.
struct Column {
  std::int32_t ground = 0;           ///< the cell over the highest cell under the body that is neither
                                     ///< void, gas nor liquid
  std::int32_t depth = 0;            ///< liquid cells above the ground
  std::int32_t top = -1;             ///< the highest of them (ground - 1 when there is none)
  std::int32_t ceiling = kOpenSky;   ///< the static cell over a covered body; kOpenSky under open sky
  std::int32_t sky = 0;              ///< the ground under open sky (the body's ground unless covered)
  std::int32_t sky_top = -1;         ///< the highest liquid of the body under open sky (sky - 1: none)

  /// True when a static cell covers the body.
  constexpr bool covered() const { return ceiling != kOpenSky; }
  /// True when the body is covered and more than half fills the room under its cover: a pipe under
  /// pressure, whose surface is the head its pipe's ends give (head_of), not its cells.
  constexpr bool pressurized() const { return covered() && 2 * depth > ceiling - ground; }
  /// The cell over the body's room: its ceiling, or `nz` under open sky.
  constexpr std::int32_t room_end(int nz) const { return ceiling < nz ? ceiling : nz; }
};

/// The most void or gas cells between two liquid cells of a column's body (shallow::Column): a
/// liquid farther above the body is in flight, the block step's, and the pass leaves it.
inline constexpr int kBodyGap = 2;

/// One column's scan, bottom up: visit z = 0, 1, ... in order, then take result().
struct ColumnScan {
  Column column;        ///< the body over the last cell visited that is neither void, gas nor liquid
  Column covered;       ///< the highest body visited with a static cell over it (depth 0: none)
  bool closed = false;  ///< a liquid more than kBodyGap above the body ended it (until the next ground)

  /// Visits `cell`, the column's cell at z.
  constexpr void visit(int z, std::uint8_t cell, const StepMaterials& m) {
    const std::uint32_t material = cell & kMaterialMask;
    if (m.is_liquid(material)) {
      if (closed) return;
      if (z - column.top - 1 > kBodyGap) {
        closed = true;
        return;
      }
      ++column.depth;
      column.top = z;
    } else if (!m.is_void(material) && !m.is_gas(material)) {
      if (column.depth > 0 && !m.is_faller(material)) covered = Column{column.ground, column.depth, column.top, z};
      column = Column{z + 1, 0, z, kOpenSky};
      closed = false;
    }
  }
  /// The column the scan found: its body under open sky, or, when that holds no liquid, its highest
  /// covered body, if it has one (settle_column may still uncover it); sky and sky_top say what lies
  /// under open sky either way.
  constexpr Column result() const {
    Column r = column.depth == 0 && covered.depth > 0 ? covered : column;
    r.sky = column.ground;
    r.sky_top = column.top;
    return r;
  }
};

/// After the scan, for column (x, y) of `columns` (nx x ny): a covered column beside liquid under
/// open sky that stands at or above its own ground under open sky takes that ground instead (dry),
/// so water runs over the top of a pipe rather than stopping at its edge. It writes its own column's
/// body and reads only the neighbours' sky and sky_top, which it does not write.
constexpr void settle_column(Column* columns, int nx, int ny, int x, int y) {
  Column& col = columns[std::int64_t(x) + std::int64_t(nx) * y];
  if (!col.covered()) return;
  const int dx[4] = {-1, 1, 0, 0}, dy[4] = {0, 0, -1, 1};
  for (int k = 0; k < 4; ++k) {
    const int u = x + dx[k], v = y + dy[k];
    if (u < 0 || u >= nx || v < 0 || v >= ny) continue;
    const Column& n = columns[std::int64_t(u) + std::int64_t(nx) * v];
    if (n.sky_top >= n.sky && n.sky_top >= col.sky) {
      col = Column{col.sky, 0, col.sky - 1, kOpenSky, col.sky, col.sky_top};
      return;
    }
  }
}

/// The pass's arrays for a grid of nx x ny columns (index x + nx y), where the backend keeps them.
/// `u` and `fraction` are the face plane (the world's state); the rest is scratch.
struct Plane {
  int nx = 0, ny = 0, nz = 0;            ///< the grid's extent
  Column* columns = nullptr;             ///< per column
  std::int64_t* surface = nullptr;       ///< per column: surface_of, in kVolume units
  std::int64_t* limit = nullptr;         ///< per column, 2 values: depth and outflow (kVolume units),
                                         ///< when the outflow exceeds the depth; else 0 and 0
  std::int32_t* u[kAxes] = {};           ///< per face: velocity (kVelocity units, + along the axis)
  std::int32_t* fraction[kAxes] = {};    ///< per face: carried volume (kVolume units, |f| < kVolume)
  std::int32_t* next_u[kAxes] = {};      ///< per face: the velocity update_face computed
  std::int64_t* volume[kAxes] = {};      ///< per face: the volume update_face computed
  std::int32_t* cells[kAxes] = {};       ///< per face: the whole cells split_face leaves to move

  /// Index of column (x, y).
  constexpr std::int64_t at(int x, int y) const { return std::int64_t(x) + std::int64_t(nx) * y; }
  /// Index step from a column to its neighbour along `axis`.
  constexpr std::int64_t stride(int axis) const { return axis == 0 ? 1 : nx; }
  /// True when column (x, y) has a neighbour at +1 along `axis` (so its face there is not a wall).
  constexpr bool has_next(int x, int y, int axis) const { return axis == 0 ? x + 1 < nx : y + 1 < ny; }
  /// True when column (x, y) has a neighbour at -1 along `axis`.
  constexpr bool has_previous(int x, int y, int axis) const { return axis == 0 ? x > 0 : y > 0; }
};

/// The flat buffers a backend keeps a Plane in, for a grid of C = nx ny columns: `columns` and
/// `surface` C each, `limit` 2 C, `faces` the face plane (4 C: the x velocities, the y velocities,
/// the x fractions, the y fractions), `next_u`, `volume` and `cells` 2 C each (x faces, then y).
struct PlaneBuffers {
  Column* columns;       ///< C columns
  std::int64_t* surface; ///< C surfaces
  std::int64_t* limit;   ///< 2 C limits
  std::int32_t* faces;   ///< the face plane, 4 C values
  std::int32_t* next_u;  ///< 2 C velocities
  std::int64_t* volume;  ///< 2 C volumes
  std::int32_t* cells;   ///< 2 C whole cells
};

/// The Plane of a grid of `size` over the buffers `b`.
constexpr Plane plane_over(Int3 size, const PlaneBuffers& b) {
  Plane p;
  p.nx = size.x;
  p.ny = size.y;
  p.nz = size.z;
  p.columns = b.columns;
  p.surface = b.surface;
  p.limit = b.limit;
  const std::int64_t columns = std::int64_t(size.x) * std::int64_t(size.y);
  for (int a = 0; a < kAxes; ++a) {
    p.u[a] = b.faces + a * columns;
    p.fraction[a] = b.faces + (2 + a) * columns;
    p.next_u[a] = b.next_u + a * columns;
    p.volume[a] = b.volume + a * columns;
    p.cells[a] = b.cells + a * columns;
  }
  return p;
}

/// Step 1 for column (x, y): its surface with the faces' carried fractions.
constexpr void surface_of(const Plane& p, int x, int y) {
  const std::int64_t c = p.at(x, y);
  const Column& col = p.columns[c];
  std::int64_t s = (std::int64_t(col.ground) + col.depth) * kVolume;
  for (int axis = 0; axis < kAxes; ++axis) {
    s -= p.fraction[axis][c];
    if (p.has_previous(x, y, axis)) s += p.fraction[axis][c - p.stride(axis)];
  }
  p.surface[c] = s;
}

/// Resistance units of a face whose opening is one cell high (line_head).
inline constexpr std::int64_t kResistance = 1 << 16;
/// The most faces a pressurized column looks along a line for an end of its pipe (line_head).
inline constexpr int kPipeReach = 512;
/// The surface of a pressurized column none of whose lines reaches an end of its pipe: the faces
/// beside it stop.
inline constexpr std::int64_t kNoHead = -(std::int64_t(1) << 62);

/// The opening (cells) between columns `a` and `b`: the height their rooms share above the higher
/// ground; 0 when they share none, so the face between them is a wall.
constexpr std::int64_t opening(const Column& a, const Column& b, int nz) {
  const std::int32_t low = a.ground > b.ground ? a.ground : b.ground;
  const std::int32_t ea = a.room_end(nz), eb = b.room_end(nz);
  const std::int32_t high = ea < eb ? ea : eb;
  return high > low ? high - low : 0;
}

/// One end of a pipe along a line: whether the line reaches one, its surface, and the resistance
/// of the faces between (the sum over them of kResistance / opening).
struct PipeEnd {
  bool found = false;           ///< the line reaches a column that is not pressurized
  std::int64_t surface = 0;     ///< that column's surface
  std::int64_t resistance = 0;  ///< of the faces from the pressurized column to it
};

/// The end of the pipe of column (x, y) along `axis` in direction `dir` (+1 or -1): the first column
/// that is not pressurized, across faces that open, within kPipeReach faces.
constexpr PipeEnd pipe_end(const Plane& p, int x, int y, int axis, int dir) {
  std::int64_t c = p.at(x, y);
  int along = axis == 0 ? x : y;
  const int length = axis == 0 ? p.nx : p.ny;
  const std::int64_t step = dir * p.stride(axis);
  std::int64_t resistance = 0;
  for (int k = 0; k < kPipeReach; ++k) {
    along += dir;
    if (along < 0 || along >= length) return PipeEnd{};
    const std::int64_t d = c + step;
    const std::int64_t open = opening(p.columns[c], p.columns[d], p.nz);
    if (open == 0) return PipeEnd{};
    resistance += kResistance / open;
    if (!p.columns[d].pressurized()) return PipeEnd{true, p.surface[d], resistance};
    c = d;
  }
  return PipeEnd{};
}

/// The head of column (x, y) along `axis`: between the two ends of its pipe on that line, in
/// proportion to the resistance to each (so a uniform pipe's head falls linearly from one end to
/// the other); the one end's surface when the line reaches only one (a dead end holds its head);
/// kNoHead when it reaches none.
constexpr std::int64_t line_head(const Plane& p, int x, int y, int axis) {
  const PipeEnd a = pipe_end(p, x, y, axis, -1), b = pipe_end(p, x, y, axis, 1);
  if (a.found && b.found) return a.surface + (b.surface - a.surface) * a.resistance / (a.resistance + b.resistance);
  if (a.found) return a.surface;
  if (b.found) return b.surface;
  return kNoHead;
}

/// Step 2 for column (x, y), in a grid with a covered column: a pipe's (a pressurized column's)
/// surface is its head, the steady head of its pipe (liquid cannot gather in a full pipe, so what
/// flows in flows out): along x and along y the line_head, and the mean of the two when both reach
/// an end; kNoHead when neither does. It reads the surfaces of columns that are not pipes only,
/// which surface_of wrote and this step does not write.
constexpr void head_of(const Plane& p, int x, int y) {
  const std::int64_t c = p.at(x, y);
  if (!p.columns[c].pressurized()) return;
  const std::int64_t hx = line_head(p, x, y, 0), hy = line_head(p, x, y, 1);
  p.surface[c] = hx == kNoHead ? hy : hy == kNoHead ? hx : (hx + hy) / 2;
}

/// The depths (kVolume units) of the two columns of face `c` along `axis` above their higher ground.
struct FaceDepths {
  std::int64_t first = 0, second = 0;  ///< the column at c, the one at c + stride
  /// True when the face passes liquid: one of them holds some.
  constexpr bool wet() const { return first > 0 || second > 0; }
  /// The depth upwind of a velocity `u` (the deeper side at rest), never below 0.
  constexpr std::int64_t upwind(std::int32_t u) const {
    const std::int64_t d = u > 0 ? first : u < 0 ? second : (first > second ? first : second);
    return d > 0 ? d : 0;
  }
};

/// The depths of face `c` along `axis` (its next column must exist).
/// Under a cover, a depth counts up to the opening's top only (a pipe passes its height, whatever its
/// head), and a face that does not open, or beside a column without a head, has none.
constexpr FaceDepths depths_of(const Plane& p, std::int64_t c, int axis) {
  const std::int64_t n = c + p.stride(axis);
  const Column &a = p.columns[c], &b = p.columns[n];
  const std::int32_t g = a.ground > b.ground ? a.ground : b.ground;
  const std::int64_t floor = std::int64_t(g) * kVolume;
  if (!a.covered() && !b.covered()) return FaceDepths{p.surface[c] - floor, p.surface[n] - floor};
  const std::int64_t open = opening(a, b, p.nz);
  const std::int64_t lc = p.surface[c], ln = p.surface[n];
  if (open == 0 || lc == kNoHead || ln == kNoHead) return FaceDepths{};
  const std::int64_t roof = floor + open * kVolume;
  return FaceDepths{(lc < roof ? lc : roof) - floor, (ln < roof ? ln : roof) - floor};
}

/// The absolute value of `v`.
constexpr std::int64_t magnitude(std::int64_t v) { return v < 0 ? -v : v; }

/// Step 3 for the face of column (x, y) along `axis`: its next velocity and the volume it carries
/// this iteration, from the surfaces and the current velocities. A wall (no next column) keeps 0.
constexpr void update_face(const Plane& p, int x, int y, int axis) {
  const std::int64_t c = p.at(x, y);
  if (!p.has_next(x, y, axis)) {
    p.next_u[axis][c] = 0;
    p.volume[axis][c] = 0;
    return;
  }
  const std::int64_t s = p.stride(axis), n = c + s;
  const std::int32_t u0 = p.u[axis][c];
  const std::int32_t f = p.fraction[axis][c];
  const FaceDepths d = depths_of(p, c, axis);
  const std::int64_t step = p.surface[c] - p.surface[n];
  // A face that passes no liquid stops and drops its fraction.
  if (!d.wet()) {
    p.next_u[axis][c] = 0;
    p.volume[axis][c] = 0;
    return;
  }
  std::int64_t u = u0 + kGravity * step / kVolume;
  // Upwind advection: the upstream face's velocity, at the rate its flow replaces this face's liquid.
  const std::int64_t h = d.upwind(std::int32_t(u > 0 ? 1 : u < 0 ? -1 : 0));
  const bool forward = u > 0;
  const bool has_upstream =
      forward ? p.has_previous(x, y, axis) : p.has_next(axis == 0 ? x + 1 : x, axis == 0 ? y : y + 1, axis);
  if (u != 0 && h > 0 && has_upstream) {
    const std::int64_t up = forward ? c - s : n;
    const std::int32_t wu = p.u[axis][up];
    if ((wu > 0) == forward && wu != 0) {
      const std::int64_t hu = depths_of(p, up, axis).upwind(wu);
      const std::int64_t num = magnitude(wu) * hu, den = kTransport * h;
      u += num >= den ? std::int64_t(wu) - u : (std::int64_t(wu) - u) * num / den;
    }
  }
  // Friction: proportional (less on deep water), then fixed, never past 0.
  const std::int64_t cells = h / kVolume > 1 ? h / kVolume : 1;
  const std::int64_t damped = magnitude(u) < kSlowFlow || cells < kFrictionDepth ? kFrictionDepth : cells;
  u -= u * kFrictionDepth / (kFrictionDivisor * damped);
  const std::int64_t coulomb = kCoulomb / (cells * cells) > 1 ? kCoulomb / (cells * cells) : 1;
  u = magnitude(u) <= coulomb ? 0 : (u > 0 ? u - coulomb : u + coulomb);
  if (u > kMaxSpeed) u = kMaxSpeed;
  if (u < -kMaxSpeed) u = -kMaxSpeed;
  const std::int32_t next = std::int32_t(u);
  p.next_u[axis][c] = next;
  p.volume[axis][c] = f + std::int64_t(next) * d.upwind(next) / kTransport;
}

/// The outflow of column (x, y) this iteration: the volumes its faces carry out of it.
constexpr std::int64_t outflow_of(const Plane& p, int x, int y) {
  const std::int64_t c = p.at(x, y);
  std::int64_t out = 0;
  for (int axis = 0; axis < kAxes; ++axis) {
    if (p.volume[axis][c] > 0) out += p.volume[axis][c];
    if (p.has_previous(x, y, axis) && p.volume[axis][c - p.stride(axis)] < 0) out -= p.volume[axis][c - p.stride(axis)];
  }
  return out;
}

/// Step 4 for column (x, y): when its outflow exceeds its depth, the scale (depth, outflow) its
/// outflows take; else (0, 0).
constexpr void limit_column(const Plane& p, int x, int y) {
  const std::int64_t c = p.at(x, y);
  const std::int64_t depth = std::int64_t(p.columns[c].depth) * kVolume;
  const std::int64_t out = outflow_of(p, x, y);
  p.limit[2 * c] = out > depth ? depth : 0;
  p.limit[2 * c + 1] = out > depth ? out : 0;
}

/// Step 5 for the face of column (x, y) along `axis`: its donor's limit applied, its whole cells to
/// move and its carried fraction; its velocity takes the value update_face computed.
constexpr void split_face(const Plane& p, int x, int y, int axis) {
  const std::int64_t c = p.at(x, y);
  std::int64_t v = p.volume[axis][c];
  const std::int64_t donor = v > 0 ? c : c + p.stride(axis);
  if (v != 0 && p.limit[2 * donor + 1] != 0) v = v * p.limit[2 * donor] / p.limit[2 * donor + 1];
  // Whole cells to the nearest, a half towards none: the carried fraction stays within half a cell
  // (so the cells stand within half a cell a face of the surfaces the pass sees), and a face at rest
  // with half a cell keeps it instead of passing a cell to and fro.
  const std::int64_t whole = (v + (v >= 0 ? kVolume / 2 - 1 : 1 - kVolume / 2)) / kVolume;
  p.cells[axis][c] = std::int32_t(whole);
  p.fraction[axis][c] = std::int32_t(v - whole * kVolume);
  p.u[axis][c] = p.next_u[axis][c];
}

/// The face moves of phase `phase` (0..3): axis phase / 2, faces of columns whose coordinate along
/// the axis has the parity phase % 2, so no two faces of a phase share a column.
constexpr int phase_axis(int phase) { return phase / 2; }
/// True when the face of column (x, y) along phase_axis(phase) moves in `phase`.
constexpr bool in_phase(int x, int y, int phase) { return ((phase_axis(phase) == 0 ? x : y) & 1) == phase % 2; }

/// Step 6 for the face of column (x, y) along `axis` (in its phase): moves its whole cells, one
/// swap at a time. `grid` gives `std::uint8_t get(std::int64_t column, int z)` and `void
/// set(std::int64_t column, int z, std::uint8_t byte)` (which notes the cell as changed). Both cells
/// keep their material only: the liquid lands at rest (its motion is the face's), and the void or
/// gas loses a wake (motion.hpp), which belongs where the grain that left it is. A rule set with the lever has no side plane (MotionParams::shallow),
/// so a cell byte is all a move carries. Returns the cells moved.
template <class Grid>
constexpr int move_face(const Plane& p, Grid& grid, int x, int y, int axis, const StepMaterials& m) {
  const std::int64_t c = p.at(x, y);
  const std::int32_t k = p.cells[axis][c];
  if (k == 0) return 0;
  const std::int64_t n = c + p.stride(axis);
  const std::int64_t from = k > 0 ? c : n, to = k > 0 ? n : c;
  int moved = 0;
  for (std::int32_t left = k > 0 ? k : -k; left > 0; --left) {
    Column& donor = p.columns[from];
    Column& receiver = p.columns[to];
    const int target = receiver.depth > 0 ? receiver.top + 1 : receiver.ground;
    if (donor.depth > 0 && target >= receiver.room_end(p.nz) && receiver.pressurized()) {
      // A full pipe: it takes liquid as fast as it passes liquid on, so the face keeps half its
      // velocity (a pipe blocked for good stops it within a few iterations) and moves again once the
      // pipe has room; what it could not move is dropped from its fraction.
      p.fraction[axis][c] = 0;
      p.u[axis][c] /= 2;
      break;
    }
    if (donor.depth == 0 || target >= receiver.room_end(p.nz)) {
      // No liquid left or no room: the face stops, and what it could not move is dropped from its
      // fraction (cells, not fractions, are the mass).
      p.u[axis][c] = 0;
      p.fraction[axis][c] = 0;
      break;
    }
    const int source = donor.top;
    const std::uint8_t liquid = grid.get(from, source), space = grid.get(to, target);
    grid.set(to, target, std::uint8_t(liquid & kMaterialMask));
    grid.set(from, source, std::uint8_t(space & kMaterialMask));
    ++moved;
    // The receiver's body grows by the cell, and by the liquid in flight within kBodyGap above it.
    receiver.top = target;
    ++receiver.depth;
    for (int z = target + 1; z < receiver.room_end(p.nz) && z - receiver.top - 1 <= kBodyGap; ++z)
      if (m.is_liquid(grid.get(to, z) & kMaterialMask)) {
        receiver.top = z;
        ++receiver.depth;
      }
    // The donor's top is the next cell of its body down.
    --donor.depth;
    int z = source - 1;
    if (donor.depth > 0)
      while (!m.is_liquid(grid.get(from, z) & kMaterialMask)) --z;
    donor.top = donor.depth > 0 ? z : donor.ground - 1;
  }
  p.cells[axis][c] = 0;
  return moved;
}

}  // namespace granular::shallow
