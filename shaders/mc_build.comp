#version 460
// Marching cubes, build pass (pc.bricks.w: a brick slot's triangles, and its vertices): one
// workgroup per brick of the mesh list (mc_classify.comp: the listed bricks with more than one look
// around them). The brick's cells and a border are loaded into shared memory (packed 4 cells a
// word, each byte its material and look). Each look present (opaque, liquid, gas: materials.glsl;
// under x-ray the static materials' look apart, see_inside.glsl) is a layer of its own: a marching
// cube (cube c spans the lattice points c..c+1, lattice point q lies between cells q-1 and q, and
// its density is the fraction of the 8 cells around it of the layer's look; a layer's densities at
// the lattice points -2..18 are counted once into shared memory before its cubes read them) emits
// the triangles of its case into the brick's slot. The triangles share their vertices: each lattice
// edge the surface crosses is one vertex of the brick's vertex slot, with its normal from the
// density gradient and the material most frequent among the layer's cells around the edge, and a
// triangle is three indices into the slot. The opaque layers' triangles (x-ray's static layer
// included) come first, then the translucent layers'; the first and last bricks along an axis also
// mesh the cubes just outside the grid, so the surfaces close at the grid's faces. A brick at level
// 1 (brick_levels, viewer/src/brick_detail.hpp) meshes a cube per 2x2x2 cells over the even lattice
// points, with the same densities there; a level-0 brick's face toward it takes the mean of the
// even points beside each odd one (match_coarse_faces), so both cross the face alike, and the
// coarse brick's opaque layers mesh one cube more into the finer one, which covers what is left
// between the two meshes. Then the brick's two indexed indirect draw commands are written:
// draws[brick] for the opaque triangles, draws[bricks in the grid + brick] for the translucent
// ones.
#extension GL_EXT_shader_8bit_storage : require
#extension GL_EXT_shader_explicit_arithmetic_types_int8 : require
// Invocations of a workgroup: 256, or what the renderer specialises (64 on a CPU device, where
// fewer invocations meet at each barrier: MarchingCubesRenderer).
layout(constant_id = 0) const uint kGroupSize = 256u;
layout(local_size_x_id = 0) in;
#include "view.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Cells { uint8_t cells[]; };
// The same cells four to a word (CellBuffer pads them to whole words): the tile load reads words.
layout(std430, set = 0, binding = 0) readonly buffer CellWords { uint cell_words[]; };
// A vertex slot holds, between the two halves of a layer's vertex pass, the work item of each
// vertex (its owner point and axis) before the vertex itself.
layout(std430, set = 0, binding = 2) buffer Vertices { uvec2 vertices[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Draws { uint draws[]; };
layout(std430, set = 0, binding = 4) readonly buffer Cases { uint cases[]; };  // 256 x (count, 15 edges)
layout(std430, set = 0, binding = 6) readonly buffer BrickLevels { uint8_t brick_levels[]; };  // 0 or 1 a brick
layout(std430, set = 0, binding = 7) writeonly buffer Indices { uint indices[]; };  // 3 a triangle, into the brick's vertex slot
layout(std430, set = 0, binding = 8) readonly buffer MeshList { uint mesh_list[]; };  // mc_classify.comp: dispatch, then bricks
#define MATERIALS_BINDING 5
#include "cells.glsl"
#include "materials.glsl"
#include "marching_iso.glsl"
#include "see_inside.glsl"
#include "marching_tile.glsl"

const uint kTileCells = uint(kTile * kTile * kTile);
const float kPositionScale = 50.0;  // fixed point: (local + 2) * 50 fits 10 bits for local in [-2, 18]

shared uint tile[(kTileCells + 3u) / 4u];
shared uint layer_density[(kTileCells + 3u) / 4u];  // per lattice point: 4 x the layer's cells around it (count_layer)
const int kFaceSide = 19;  // lattice points -1..17 along each axis of a brick's face
const int kEdgeOwners = 19 * 19 * 19;  // lattice points a layer's edges start from, at most (cubes -1..16 and one past)
// Scratch, one use at a time: the layer's tile rows (count_layer), match_coarse_faces' means of a
// face, then each edge owner's vertices (16 bits a point: its first vertex << 3 | the axes of its
// edges the surface crosses; edge_vertex).
shared uint scratch[(kEdgeOwners + 1) / 2];
shared uint triangle_count;
shared uint vertex_count;
shared uint tile_looks;  // bit l: some cell of the tile has look l
shared uint material_looks;  // bits 3m..3m+2: the seen look of material m (see_inside.glsl)

uint tile_index(ivec3 t) { return uint(t.x + kTile * (t.y + kTile * t.z)); }

// A tile byte: bits 0-2 the cell's material, bits 3-5 its seen look (see_inside.glsl).
uint tile_byte(ivec3 local) {
  uint i = tile_index(local + 2);
  return (tile[i >> 2] >> ((i & 3u) * 8u)) & 255u;
}

const int kCoarsePoints = 11;  // the even lattice points -2, 0, .., 18 along an axis

const uint kTileRows = uint(kTile * kTile);

// The layer's cells in tile row (y, z) (tile coordinates, 0..20): bit x set where cell x has the
// layer's look. count_layer writes them into scratch.
uint layer_row(int y, int z) { return scratch[uint(y + kTile * z)]; }

// The cells of the layer among the 8 around lattice point q (cells q - 1 .. q, clamped to the
// tile), from the layer's rows.
uint cells_around(ivec3 q) {
  ivec3 hi = q + 2, lo = max(hi - 1, ivec3(0));
  uint sum = 0u;
  for (int c = 0; c < 4; ++c) {
    uint row = layer_row((c & 1) == 0 ? lo.y : hi.y, (c & 2) == 0 ? lo.z : hi.z);
    sum += ((row >> lo.x) & 1u) + ((row >> hi.x) & 1u);
  }
  return sum;
}

// Counts the cells of layer `look` around the lattice points the brick's level reads into
// layer_density, four times over (so that a mean of two or four counts is a whole number): at
// level 0 every point -2..18 (local), a byte each; at level 1 the even ones, a word each. Every
// invocation calls it.
void count_layer(uint look, uint level) {
  barrier();  // the previous layer's cubes have read its densities and its edges' vertices
  for (uint r = gl_LocalInvocationIndex; r < kTileRows; r += kGroupSize) {
    uint first = r * uint(kTile), row = 0u;
    for (uint x = 0u; x < uint(kTile); ++x) {
      uint i = first + x;
      if (((tile[i >> 2] >> ((i & 3u) * 8u + 3u)) & 7u) == look) row |= 1u << x;
    }
    scratch[r] = row;
  }
  barrier();
  if (level == 0u) {
    for (uint w = gl_LocalInvocationIndex; w < (kTileCells + 3u) / 4u; w += kGroupSize) {
      uint word = 0u;
      for (uint b = 0u; b < 4u; ++b) {
        uint i = w * 4u + b;
        if (i >= kTileCells) break;
        ivec3 q = ivec3(int(i % uint(kTile)), int((i / uint(kTile)) % uint(kTile)), int(i / uint(kTile * kTile))) - 2;
        word |= (cells_around(q) * 4u) << (b * 8u);
      }
      layer_density[w] = word;
    }
  } else {
    for (uint i = gl_LocalInvocationIndex; i < uint(kCoarsePoints * kCoarsePoints * kCoarsePoints); i += kGroupSize) {
      ivec3 p = ivec3(int(i % uint(kCoarsePoints)), int((i / uint(kCoarsePoints)) % uint(kCoarsePoints)), int(i / uint(kCoarsePoints * kCoarsePoints)));
      layer_density[i] = cells_around(p * 2 - 2) * 4u;
    }
  }
  barrier();
}

// The counted layer's value at lattice point q of a level-0 brick (local, -2..18): 4 x its cells around.
uint fine_count(ivec3 q) {
  uint i = tile_index(q + 2);
  return (layer_density[i >> 2] >> ((i & 3u) * 8u)) & 255u;
}

// Density of the counted layer at lattice point q (local, -2..18; even at level 1): the fraction
// of the 8 cells around it of its look.
float density(ivec3 q, uint level) {
  if (level != 0u) return float(layer_density[uint((q.x + 2) / 2 + kCoarsePoints * ((q.y + 2) / 2 + kCoarsePoints * ((q.z + 2) / 2)))]) / 32.0;
  return float(fine_count(q)) / 32.0;
}

// The level of the brick `offset` bricks from brick `at` (bricks), or `fallback` outside the grid.
uint level_of(ivec3 at, ivec3 offset, uint fallback) {
  ivec3 b = at + offset;
  if (any(lessThan(b, ivec3(0))) || any(greaterThanEqual(b, pc.bricks.xyz))) return fallback;
  return uint(brick_levels[b.x + pc.bricks.x * (b.y + pc.bricks.y * b.z)]);
}

// On each face a level-0 brick shares with a coarse neighbour, the densities of the lattice points
// between the even ones become the mean of the even points beside them on the face (2, or 4 where
// both coordinates are odd): the brick's surface then crosses the face where the neighbour's
// coarse cubes cross it. Every invocation calls it, after count_layer.
void match_coarse_faces(ivec3 at) {
  for (int a = 0; a < 3; ++a) {
    ivec3 d = ivec3(0);
    d[a] = 1;
    for (int side = 0; side < 2; ++side) {
      if (level_of(at, side == 0 ? -d : d, 0u) == 0u) continue;
      ivec3 u = ivec3(0), v = ivec3(0);
      u[(a + 1) % 3] = 1;
      v[(a + 2) % 3] = 1;
      // The means first (they read only even points, which keep their counts), then the writes.
      for (uint i = gl_LocalInvocationIndex; i < uint(kFaceSide * kFaceSide); i += kGroupSize) {
        int iu = int(i % uint(kFaceSide)) - 1, iv = int(i / uint(kFaceSide)) - 1;
        ivec3 q = d * (side * kBrickSize) + u * iu + v * iv;
        ivec3 du = (iu & 1) != 0 ? u : ivec3(0), dv = (iv & 1) != 0 ? v : ivec3(0);
        // Where one coordinate is odd the four are two pairs of the same point; where none is, q four times.
        scratch[i] = (fine_count(q - du - dv) + fine_count(q + du - dv) + fine_count(q - du + dv) + fine_count(q + du + dv)) / 4u;
      }
      barrier();
      for (uint i = gl_LocalInvocationIndex; i < uint(kFaceSide * kFaceSide); i += kGroupSize) {
        int iu = int(i % uint(kFaceSide)) - 1, iv = int(i / uint(kFaceSide)) - 1;
        if (((iu | iv) & 1) == 0) continue;
        uint index = tile_index(d * (side * kBrickSize) + u * iu + v * iv + 2);
        uint shift = (index & 3u) * 8u;
        atomicAnd(layer_density[index >> 2], ~(255u << shift));
        atomicOr(layer_density[index >> 2], scratch[i] << shift);
      }
      barrier();
    }
  }
}

// The density gradient at lattice point q, by central differences over the level's point spacing
// (one-sided at the counted points' edge).
vec3 gradient(ivec3 q, uint level) {
  int step = 1 << level;
  vec3 g;
  for (int a = 0; a < 3; ++a) {
    ivec3 d = ivec3(0);
    d[a] = step;
    ivec3 hi = clamp(q + d, ivec3(-2), ivec3(18)), lo = clamp(q - d, ivec3(-2), ivec3(18));
    g[a] = (density(hi, level) - density(lo, level)) / float(max(hi[a] - lo[a], 1));
  }
  return g;
}

// The material of layer `look` most frequent among the cells around the lattice edge from point
// `from` to from + step along `axis`: cells from - 1 .. from + step along the axis and from - 1 ..
// from across it, the cells its two ends' densities count (ties: the higher state).
uint layer_material(ivec3 from, int axis, int step, uint look) {
  // A byte of counts per material, materials 0-3 in `low` and 4-7 in `high` (at most 16 cells).
  uint low = 0u, high = 0u;
  ivec3 size = ivec3(2);
  size[axis] = step + 2;
  for (int c = 0; c < size.x * size.y * size.z; ++c) {
    ivec3 cell = from - 1 + ivec3(c % size.x, (c / size.x) % size.y, c / (size.x * size.y));
    uint b = tile_byte(clamp(cell, ivec3(-2), ivec3(kTile - 3)));
    if ((b >> 3) != look) continue;
    uint one = 1u << ((b & 3u) * 8u);
    if ((b & 4u) == 0u) low += one; else high += one;
  }
  uint best = 0u, best_count = low & 255u;
  for (uint m = 1u; m < 8u; ++m) {
    uint count = ((m < 4u ? low : high) >> ((m & 3u) * 8u)) & 255u;
    if (count >= best_count) {
      best = m;
      best_count = count;
    }
  }
  return best;
}

uint octahedral(vec3 n) {
  n /= abs(n.x) + abs(n.y) + abs(n.z) + 1e-6;
  vec2 e = n.z >= 0.0 ? n.xy : (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
  uvec2 q = uvec2(clamp(e * 0.5 + 0.5, 0.0, 1.0) * 16383.0 + 0.5);
  return q.x | (q.y << 14);
}

// The brick-slot vertex of the edge from owner point `owner` (index into scratch) along `axis`, or
// -1 when the surface does not cross it or its vertex found no room.
int edge_vertex(uint owner, uint axis) {
  uint entry = (scratch[owner >> 1] >> ((owner & 1u) * 16u)) & 65535u;
  if ((entry & (1u << axis)) == 0u) return -1;
  return int((entry >> 3) + bitCount(entry & ((1u << axis) - 1u)));
}

// The brick-slot vertex of edge k of the case `mask` of the cube at `cube` (counted from the
// layer's first cube), the owners spanning `owners` points along each axis; -1 when it has none.
int case_edge_vertex(uint mask, uint k, ivec3 cube, ivec3 owners) {
  uint edge = cases[mask * 16u + 1u + k];
  uint axis = edge >> 2;
  uint rest = edge & 3u;
  // The edge's low corner has bit `axis` clear; the other two bits enumerate the edge within its axis.
  uint low = (axis == 0u) ? (rest << 1) : (axis == 1u ? ((rest & 1u) | ((rest >> 1) << 2)) : rest);
  ivec3 owner = cube + ivec3(int(low & 1u), int((low >> 1) & 1u), int((low >> 2) & 1u));
  return edge_vertex(uint(owner.x + owners.x * (owner.y + owners.y * owner.z)), axis);
}

// Meshes layer `look` of the tile at `level`: appends its vertices and triangles to the brick's
// slots. Every invocation calls it.
void mesh_layer(uint brick, ivec3 origin, uint look, uint max_triangles, uint level) {
  count_layer(look, level);
  ivec3 at = origin / kBrickSize;
  if (level == 0u) match_coarse_faces(at);
  int step = 1 << level;
  // Cubes this brick meshes, in units of `step` cells: its own, plus index -1 / one past its own
  // along an axis at the grid's faces and, for the opaque layers of a coarse brick, toward each
  // finer neighbour.
  ivec3 first_cube = ivec3(equal(origin, ivec3(0))) * -1;
  bvec3 last_brick = greaterThanEqual(origin + kBrickSize, pc.grid.xyz);
  ivec3 end_cube = mix(ivec3(kBrickSize / step), (pc.grid.xyz - origin + step) / step, last_brick);
  if (level != 0u && look == kLookOpaque) {
    for (int a = 0; a < 3; ++a) {
      ivec3 d = ivec3(0);
      d[a] = 1;
      if (level_of(at, -d, level) < level) first_cube[a] = -1;
      if (level_of(at, d, level) < level) end_cube[a] = kBrickSize / step + 1;
    }
  }
  // The vertices: each lattice point first_cube..end_cube owns the edges from it toward +x, +y, +z
  // that lie in the meshed cubes. First each owner finds the edges the surface crosses and takes
  // their vertices, leaving a work item in each; then each vertex is computed from its item, so
  // that the costly part runs on every invocation alike.
  ivec3 owners = end_cube - first_cube + 1;
  uint owner_total = uint(owners.x * owners.y * owners.z);
  uint max_vertices = max_triangles;  // a slot holds as many vertices as triangles (mostly half are used)
  uint slot = brick * max_vertices;
  uint layer_first_vertex = min(vertex_count, max_vertices);
  for (uint w = gl_LocalInvocationIndex; w < (owner_total + 1u) / 2u; w += kGroupSize) scratch[w] = 0u;
  barrier();
  const uint kNoItem = 0xffffffffu;
  for (uint i = gl_LocalInvocationIndex; i < owner_total; i += kGroupSize) {
    ivec3 c = first_cube + ivec3(int(i % uint(owners.x)), int((i / uint(owners.x)) % uint(owners.y)), int(i / uint(owners.x * owners.y)));
    bool inside = density(c * step, level) > kIso;
    uint crossed = 0u;
    for (int a = 0; a < 3; ++a) {
      ivec3 e = ivec3(0);
      e[a] = 1;
      if (c[a] < end_cube[a] && (density((c + e) * step, level) > kIso) != inside) crossed |= 1u << a;
    }
    if (crossed == 0u) continue;
    uint count = bitCount(crossed);
    uint first = atomicAdd(vertex_count, count);
    bool fits = first + count <= max_vertices;  // else the triangles using these are dropped
    uint k = 0u;
    for (uint a = 0u; a < 3u; ++a) {
      if ((crossed & (1u << a)) == 0u) continue;
      if (first + k < max_vertices) vertices[slot + first + k] = uvec2(fits ? i : kNoItem, a);
      ++k;
    }
    if (fits) atomicOr(scratch[i >> 1], ((first << 3) | crossed) << ((i & 1u) * 16u));
  }
  memoryBarrierBuffer();
  barrier();
  uint layer_end_vertex = min(vertex_count, max_vertices);
  for (uint v = layer_first_vertex + gl_LocalInvocationIndex; v < layer_end_vertex; v += kGroupSize) {
    uvec2 item = vertices[slot + v];
    if (item.x == kNoItem) continue;
    uint i = item.x;
    int a = int(item.y);
    ivec3 from = (first_cube + ivec3(int(i % uint(owners.x)), int((i / uint(owners.x)) % uint(owners.y)), int(i / uint(owners.x * owners.y)))) * step;
    ivec3 e = ivec3(0);
    e[a] = step;
    float d0 = density(from, level), d1 = density(from + e, level);
    float t = clamp((kIso - d0) / (d1 - d0), 0.0, 1.0);
    vec3 position = mix(vec3(from), vec3(from + e), t);
    vec3 normal = -mix(gradient(from, level), gradient(from + e, level), t);
    if (dot(normal, normal) < 1e-8) normal = vec3(0.0, 0.0, 1.0);
    uvec3 fixed_position = uvec3((position + 2.0) * kPositionScale + 0.5);
    uint material = layer_material(from, a, step, look);
    vertices[slot + v] =
        uvec2(fixed_position.x | (fixed_position.y << 10) | (fixed_position.z << 20), octahedral(normalize(normal)) | (material << 28));
  }
  // The triangles: each cube's case names its edges; an edge's vertex is its owner's.
  ivec3 span = end_cube - first_cube;
  uint cube_total = uint(span.x * span.y * span.z);
  for (uint i = gl_LocalInvocationIndex; i < cube_total; i += kGroupSize) {
    ivec3 c = first_cube + ivec3(int(i % uint(span.x)), int((i / uint(span.x)) % uint(span.y)), int(i / uint(span.x * span.y)));
    uint mask = 0u;
    for (int corner = 0; corner < 8; ++corner)
      if (density((c + ivec3(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1)) * step, level) > kIso) mask |= 1u << corner;
    if (mask == 0u || mask == 255u) continue;
    uint edge_count = cases[mask * 16u];
    uint first = atomicAdd(triangle_count, edge_count / 3u);
    for (uint k = 0u; k < edge_count; k += 3u) {
      uint triangle = first + k / 3u;
      if (triangle >= max_triangles) break;
      int a = case_edge_vertex(mask, k, c - first_cube, owners);
      int b = case_edge_vertex(mask, k + 1u, c - first_cube, owners);
      int v = case_edge_vertex(mask, k + 2u, c - first_cube, owners);
      // A triangle with a vertex that found no room is drawn as nothing (all three indices 0).
      bool whole = min(a, min(b, v)) >= 0;
      uint at = (brick * max_triangles + triangle) * 3u;
      indices[at] = whole ? uint(a) : 0u;
      indices[at + 1u] = whole ? uint(b) : 0u;
      indices[at + 2u] = whole ? uint(v) : 0u;
    }
  }
  barrier();  // the next layer reuses scratch
}

bool layer_has_surface(uint look) { return (tile_looks & (1u << look)) != 0u && (tile_looks & ~(1u << look)) != 0u; }

// VkDrawIndexedIndirectCommand `command`: `index_count` indices from `first_index`, into the brick's vertex slot.
void write_draw(uint command, uint first_index, uint index_count, uint first_vertex, uint brick) {
  draws[command * 5u + 0u] = index_count;
  draws[command * 5u + 1u] = 1u;
  draws[command * 5u + 2u] = first_index;
  draws[command * 5u + 3u] = first_vertex;
  draws[command * 5u + 4u] = brick;
}

const uint kWordsPerRow = 7u;  // words of the cell buffer that can hold a tile row's 21 cells

// The word of the cell buffer that tile-load task `task` reads (task / 7: the tile row, task % 7:
// the word among those holding the row's cells inside the grid), or 0xffffffff when there is none.
uint tile_row_word(ivec3 origin, uint task) {
  uint row = task / kWordsPerRow;
  if (row >= kTileRows) return 0xffffffffu;
  ivec3 first = origin + ivec3(-2, int(row % uint(kTile)) - 2, int(row / uint(kTile)) - 2);
  if (first.y < 0 || first.z < 0 || first.y >= pc.grid.y || first.z >= pc.grid.z) return 0xffffffffu;
  int lo = max(first.x, 0), hi = min(first.x + kTile - 1, pc.grid.x - 1);
  if (lo > hi) return 0xffffffffu;
  uint row_base = cell_index(ivec3(0, first.y, first.z));
  uint word = ((row_base + uint(lo)) >> 2) + task % kWordsPerRow;
  return word > ((row_base + uint(hi)) >> 2) ? 0xffffffffu : word;
}

void main() {
  uint max_triangles = uint(pc.bricks.w);  // the brick's slot size (MarchingCubesRenderer)
  uint grid_bricks = uint(pc.bricks.x * pc.bricks.y * pc.bricks.z);
  uint brick = mesh_list[3u + gl_WorkGroupID.x];
  ivec3 origin = brick_origin(brick);
  uint level = uint(brick_levels[brick]);
  uint slot_start = brick * max_triangles * 3u;
  if (gl_LocalInvocationIndex == 0u) {
    triangle_count = 0u;
    vertex_count = 0u;
    tile_looks = 0u;
    uint table = 0u;
    for (uint m = 0u; m < 8u; ++m) table |= seen_look(m) << (3u * m);
    material_looks = table;
  }
  barrier();
  // The tile, row by row: each row of 21 cells is read as the (at most 7) words of the cell
  // buffer that hold its cells inside the grid; cells outside the grid stay void.
  for (uint w = gl_LocalInvocationIndex; w < (kTileCells + 3u) / 4u; w += kGroupSize) tile[w] = 0u;
  barrier();
  uint seen = material_looks;
  uint looks = 0u;
  if (gl_LocalInvocationIndex == 0u &&
      (any(lessThan(origin - 2, ivec3(0))) || any(greaterThan(origin + kTile - 3, pc.grid.xyz - 1))))
    looks |= 1u << (seen & 7u);  // void's look, for the cells outside the grid
  const uint kTasks = (kTileRows * kWordsPerRow + kGroupSize - 1u) / kGroupSize;  // tasks an invocation takes
  // All of an invocation's words are read before any is used, so their reads overlap.
  uint loaded[kTasks];
  for (uint k = 0u; k < kTasks; ++k) {
    uint task = gl_LocalInvocationIndex + kGroupSize * k;
    uint word = tile_row_word(origin, task);
    loaded[k] = word != 0xffffffffu ? cell_words[word] : 0u;
  }
  for (uint k = 0u; k < kTasks; ++k) {
    uint task = gl_LocalInvocationIndex + kGroupSize * k;
    uint word = tile_row_word(origin, task);
    if (word == 0xffffffffu) continue;
    uint row = task / kWordsPerRow;
    ivec3 first = origin + ivec3(-2, int(row % uint(kTile)) - 2, int(row / uint(kTile)) - 2);  // the row's first cell
    int lo = max(first.x, 0), hi = min(first.x + kTile - 1, pc.grid.x - 1);  // its cells inside the grid
    uint row_base = cell_index(ivec3(0, first.y, first.z));
    uint bits = loaded[k];
    // The word's cells of the row go to consecutive tile bytes: at most two tile words.
    uint first_tile_word = 0xffffffffu, low_part = 0u, high_part = 0u;
    for (uint j = 0u; j < 4u; ++j) {
      int x = int(word * 4u + j - row_base);
      if (x < lo || x > hi) continue;
      uint material = (bits >> (8u * j)) & 7u;
      uint look = (seen >> (3u * material)) & 7u;
      looks |= 1u << look;
      uint t = row * uint(kTile) + uint(x - first.x);
      if (first_tile_word == 0xffffffffu) first_tile_word = t >> 2;
      uint byte = (material | (look << 3)) << ((t & 3u) * 8u);
      if ((t >> 2) == first_tile_word) low_part |= byte; else high_part |= byte;
    }
    if (first_tile_word == 0xffffffffu) continue;
    atomicOr(tile[first_tile_word], low_part);
    if (high_part != 0u) atomicOr(tile[first_tile_word + 1u], high_part);
  }
  atomicOr(tile_looks, looks);
  barrier();
  // A layer's surface lies where its look meets another; a tile of one look holds none (most bricks).
  if (layer_has_surface(kLookOpaque)) mesh_layer(brick, origin, kLookOpaque, max_triangles, level);
  if (layer_has_surface(kLookXray)) mesh_layer(brick, origin, kLookXray, max_triangles, level);
  barrier();
  uint opaque_triangles = min(triangle_count, max_triangles);
  barrier();  // every invocation has read the opaque count before the translucent layers add to it
  if (layer_has_surface(kLookLiquid)) mesh_layer(brick, origin, kLookLiquid, max_triangles, level);
  if (layer_has_surface(kLookGas)) mesh_layer(brick, origin, kLookGas, max_triangles, level);
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    uint total = min(triangle_count, max_triangles);
    write_draw(brick, slot_start, opaque_triangles * 3u, brick * max_triangles, brick);
    write_draw(grid_bricks + brick, slot_start + opaque_triangles * 3u, (total - opaque_triangles) * 3u, brick * max_triangles, brick);
  }
}
