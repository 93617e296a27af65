#pragma once
/// @file shallow_water.hpp
/// MotionParams::shallow: after the last sub-step of every tick, the liquid under open sky moves as
/// shallow water, column against column. Plain constexpr integer code on flat arrays, one function
/// per column or per face, that the CPU backend calls over rows of columns and the CUDA kernels one
/// thread a column or face (the plain loop of the tests writes it again); nothing here depends on the
/// order columns or faces are visited in.
///
/// A *column* of the grid has a ground (the cell over its highest cell that is neither void, gas
/// nor liquid) and a *body*: the liquid cells from the ground up, each at most kBodyGap void or gas
/// cells above the one below it (the ground for the first). Its depth is their count (the voids
/// between them are not counted); a liquid farther up is in flight, and the pass leaves it to the
/// block step.
/// Two neighbouring columns, along x and along y, share a *face*, which holds a velocity (kVelocity
/// units per cell a tick, a staggered grid) and a carried fraction of a cell (kVolume units per
/// cell). The faces are the *face plane*: 4 int32 per column, part of the world's state.
///
/// One tick is kIterations iterations (each 1 / kIterations tick) of:
///  1. surfaces (surface_of): ground + depth, plus the fractions the faces carry in, less those they
///     carry out, so the surfaces the faces see are level to a fraction of a cell;
///  2. faces (update_face): a face *passes* liquid when the surface of one of its columns stands
///     above the higher ground; one that does not stops. Its velocity accelerates down the surface
///     step (g = 2 cells a tick^2), takes its upstream face's velocity at the rate the flow replaces
///     its liquid (a momentum-conserving upwind advection, so a front runs on over a dry bed), and
///     loses some to bed friction: a part proportional to the velocity (less on deep water) and a
///     fixed part that stops slow flows and thin films (never past 0). Its volume is its velocity x
///     the upwind depth x dt, plus its fraction;
///  3. columns (limit_column): a column whose outflow over its four faces exceeds its depth scales
///     its outflows down to it;
///  4. faces (split_face): each face's volume to the nearest whole cell is to move (a half towards
///     none), the rest, at most half a cell, is carried;
///  5. moves, in four phases of disjoint column pairs (even x faces, odd x, even y, odd y;
///     move_face): a move swaps the top of the donor's body with the void or gas just over the
///     receiver's body (or its ground), so every move is a permutation of the grid and every
///     material is conserved exactly; the receiver's body takes in the liquid in flight the move
///     brought within kBodyGap. A move that finds no liquid or no room stops the face.
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
/// kFrictionDepth (cells) beyond that depth.
inline constexpr std::int64_t kFrictionDivisor = 256, kFrictionDepth = 16;
/// The fixed friction: kCoulomb / depth^2 (depth in cells) velocity units an iteration, at least 1:
/// it stops a thin film, and holds a surface step of at most 1 / depth^2 cell a face at rest.
inline constexpr std::int64_t kCoulomb = 4096;

/// The faces of the plane: 0 the x face of a column (to its +x neighbour), 1 its y face.
inline constexpr int kAxes = 2;

/// A column of the grid as the pass sees it.
struct Column {
  std::int32_t ground = 0;  ///< the cell over the highest cell that is neither void, gas nor liquid
  std::int32_t depth = 0;   ///< liquid cells above the ground
  std::int32_t top = -1;    ///< the highest of them (ground - 1 when there is none)
};

/// The most void or gas cells between two liquid cells of a column's body (shallow::Column): a
/// liquid farther above the body is in flight, the block step's, and the pass leaves it.
inline constexpr int kBodyGap = 2;

/// One column's scan, bottom up: visit z = 0, 1, ... in order.
struct ColumnScan {
  Column column;        ///< what the cells visited so far make
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
      column = Column{z + 1, 0, z};
      closed = false;
    }
  }
};

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
constexpr FaceDepths depths_of(const Plane& p, std::int64_t c, int axis) {
  const std::int64_t n = c + p.stride(axis);
  const std::int32_t g = p.columns[c].ground > p.columns[n].ground ? p.columns[c].ground : p.columns[n].ground;
  return FaceDepths{p.surface[c] - std::int64_t(g) * kVolume, p.surface[n] - std::int64_t(g) * kVolume};
}

/// The absolute value of `v`.
constexpr std::int64_t magnitude(std::int64_t v) { return v < 0 ? -v : v; }

/// Step 2 for the face of column (x, y) along `axis`: its next velocity and the volume it carries
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
  u -= u * kFrictionDepth / (kFrictionDivisor * (cells > kFrictionDepth ? cells : kFrictionDepth));
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

/// Step 3 for column (x, y): when its outflow exceeds its depth, the scale (depth, outflow) its
/// outflows take; else (0, 0).
constexpr void limit_column(const Plane& p, int x, int y) {
  const std::int64_t c = p.at(x, y);
  const std::int64_t depth = std::int64_t(p.columns[c].depth) * kVolume;
  const std::int64_t out = outflow_of(p, x, y);
  p.limit[2 * c] = out > depth ? depth : 0;
  p.limit[2 * c + 1] = out > depth ? out : 0;
}

/// Step 4 for the face of column (x, y) along `axis`: its donor's limit applied, its whole cells to
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

/// Step 5 for the face of column (x, y) along `axis` (in its phase): moves its whole cells, one
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
    if (donor.depth == 0 || target >= p.nz) {
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
    for (int z = target + 1; z < p.nz && z - receiver.top - 1 <= kBodyGap; ++z)
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
