#version 460
// Marching cubes, build pass (pc.bricks.w: triangles per brick slot): one workgroup per listed
// brick. The brick's cells and a border are loaded into shared memory (packed 4 cells a word, each
// byte its material and look). Each look present (opaque, liquid, gas: materials.glsl; under x-ray
// the static materials' look apart, see_inside.glsl) is a layer of its own: a marching cube (cube c
// spans the lattice points c..c+1, lattice point q lies between cells q-1 and q, and its density is
// the fraction of the 8 cells around it of the layer's look; a layer's densities at the lattice
// points -2..18 are counted once into shared memory before its cubes read them) emits the triangles of its case into
// the brick's slot, with normals from the density gradient and the material most frequent among the
// layer's cells around it. The opaque layers' triangles (x-ray's static layer included) come first,
// then the translucent layers'; the first and last bricks along an axis also mesh the cubes just
// outside the grid, so the surfaces close at the grid's faces. Then the brick's two indirect draw
// commands are written: draws[brick] for the opaque triangles, draws[bricks in the grid + brick]
// for the translucent ones.
#extension GL_EXT_shader_8bit_storage : require
#extension GL_EXT_shader_explicit_arithmetic_types_int8 : require
layout(local_size_x = 256) in;
#include "view.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Cells { uint8_t cells[]; };
layout(std430, set = 0, binding = 1) readonly buffer BrickList { uint brick_list[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Vertices { uvec2 vertices[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Draws { uint draws[]; };
layout(std430, set = 0, binding = 4) readonly buffer Cases { uint cases[]; };  // 256 x (count, 15 edges)
#define MATERIALS_BINDING 5
#include "cells.glsl"
#include "materials.glsl"
#include "marching_iso.glsl"
#include "see_inside.glsl"

const int kTile = 21;  // cells -2..18 around the brick
const uint kTileCells = uint(kTile * kTile * kTile);
const float kPositionScale = 50.0;  // fixed point: (local + 1) * 50 fits 10 bits for local in [-1, 17]

shared uint tile[(kTileCells + 3u) / 4u];
shared uint layer_density[(kTileCells + 3u) / 4u];  // per lattice point -2..18: cells of the layer around it, 0..8
shared uint triangle_count;
shared uint tile_looks;  // bit l: some cell of the tile has look l

uint tile_index(ivec3 t) { return uint(t.x + kTile * (t.y + kTile * t.z)); }

// A tile byte: bits 0-2 the cell's material, bits 3-5 its seen look (see_inside.glsl).
uint tile_byte(ivec3 local) {
  uint i = tile_index(local + 2);
  return (tile[i >> 2] >> ((i & 3u) * 8u)) & 255u;
}

// Counts, for every lattice point q in -2..18 (local), the cells of layer `look` among the 8 around
// it (cells q - 1 .. q, clamped to the tile) into layer_density. Every invocation calls it.
void count_layer(uint look) {
  barrier();  // the previous layer's cubes have read its densities
  for (uint w = gl_LocalInvocationIndex; w < (kTileCells + 3u) / 4u; w += 256u) {
    uint word = 0u;
    for (uint b = 0u; b < 4u; ++b) {
      uint i = w * 4u + b;
      if (i >= kTileCells) break;
      ivec3 q = ivec3(int(i % uint(kTile)), int((i / uint(kTile)) % uint(kTile)), int(i / uint(kTile * kTile))) - 2;
      uint sum = 0u;
      for (int c = 0; c < 8; ++c)
        sum += (tile_byte(clamp(q - 1 + ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1), ivec3(-2), ivec3(kTile - 3))) >> 3) == look ? 1u : 0u;
      word |= sum << (b * 8u);
    }
    layer_density[w] = word;
  }
  barrier();
}

// Density of the counted layer at lattice point q (local, -2..18): the fraction of the 8 cells around it of its look.
float density(ivec3 q) {
  uint i = tile_index(q + 2);
  return float((layer_density[i >> 2] >> ((i & 3u) * 8u)) & 255u) * 0.125;
}

vec3 gradient(ivec3 q) {
  return vec3(density(q + ivec3(1, 0, 0)) - density(q - ivec3(1, 0, 0)), density(q + ivec3(0, 1, 0)) - density(q - ivec3(0, 1, 0)),
              density(q + ivec3(0, 0, 1)) - density(q - ivec3(0, 0, 1)));
}

// The material of layer `look` most frequent among the 27 cells around cube `local` (ties: the higher state).
uint layer_material(ivec3 local, uint look) {
  uint counts[8] = uint[8](0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
  for (int c = 0; c < 27; ++c) {
    uint b = tile_byte(local - 1 + ivec3(c % 3, (c / 3) % 3, c / 9));
    if ((b >> 3) == look) counts[b & 7u]++;
  }
  uint best = 0u;
  for (uint m = 1u; m < 8u; ++m)
    if (counts[m] >= counts[best]) best = m;
  return best;
}

uint octahedral(vec3 n) {
  n /= abs(n.x) + abs(n.y) + abs(n.z) + 1e-6;
  vec2 e = n.z >= 0.0 ? n.xy : (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
  uvec2 q = uvec2(clamp(e * 0.5 + 0.5, 0.0, 1.0) * 16383.0 + 0.5);
  return q.x | (q.y << 14);
}

// Meshes layer `look` of the tile: appends its triangles to the brick's slot. Every invocation calls it.
void mesh_layer(uint brick, ivec3 origin, uint look, uint max_triangles) {
  count_layer(look);
  // Cubes this brick meshes: its own, plus index -1 / index N along an axis at the grid's faces.
  ivec3 first_cube = ivec3(equal(origin, ivec3(0))) * -1;
  bvec3 last_brick = greaterThanEqual(origin + kBrickSize, pc.grid.xyz);
  ivec3 end_cube = mix(ivec3(kBrickSize), pc.grid.xyz + 1 - origin, last_brick);
  ivec3 span = end_cube - first_cube;
  uint cube_total = uint(span.x * span.y * span.z);
  for (uint i = gl_LocalInvocationIndex; i < cube_total; i += 256u) {
    ivec3 local = first_cube + ivec3(int(i % uint(span.x)), int((i / uint(span.x)) % uint(span.y)), int(i / uint(span.x * span.y)));
    float d[8];
    uint mask = 0u;
    for (int c = 0; c < 8; ++c) {
      d[c] = density(local + ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1));
      if (d[c] > kIso) mask |= 1u << c;
    }
    if (mask == 0u || mask == 255u) continue;
    uint edge_count = cases[mask * 16u];
    uint material = layer_material(local, look);
    uint first = atomicAdd(triangle_count, edge_count / 3u);
    for (uint k = 0u; k < edge_count; ++k) {
      uint triangle = first + k / 3u;
      if (triangle >= max_triangles) break;
      uint edge = cases[mask * 16u + 1u + k];
      uint axis = edge >> 2;
      uint rest = edge & 3u;
      // Corner a has bit `axis` clear; the other two bits enumerate the edge within its axis.
      uint low_bits = (axis == 0u) ? (rest << 1) : (axis == 1u ? ((rest & 1u) | ((rest >> 1) << 2)) : rest);
      uint corner_a = low_bits, corner_b = low_bits | (1u << axis);
      ivec3 pa = local + ivec3(int(corner_a & 1u), int((corner_a >> 1) & 1u), int((corner_a >> 2) & 1u));
      ivec3 pb = local + ivec3(int(corner_b & 1u), int((corner_b >> 1) & 1u), int((corner_b >> 2) & 1u));
      float t = clamp((kIso - d[corner_a]) / (d[corner_b] - d[corner_a]), 0.0, 1.0);
      vec3 position = mix(vec3(pa), vec3(pb), t);
      vec3 normal = -mix(gradient(pa), gradient(pb), t);
      if (dot(normal, normal) < 1e-8) normal = vec3(0.0, 0.0, 1.0);
      uvec3 fixed_position = uvec3((position + 1.0) * kPositionScale + 0.5);
      vertices[brick * max_triangles * 3u + first * 3u + k] =
          uvec2(fixed_position.x | (fixed_position.y << 10) | (fixed_position.z << 20), octahedral(normalize(normal)) | (material << 28));
    }
  }
}

bool layer_has_surface(uint look) { return (tile_looks & (1u << look)) != 0u && (tile_looks & ~(1u << look)) != 0u; }

void write_draw(uint command, uint first_vertex, uint vertex_count, uint brick) {
  draws[command * 4u + 0u] = vertex_count;
  draws[command * 4u + 1u] = 1u;
  draws[command * 4u + 2u] = first_vertex;
  draws[command * 4u + 3u] = brick;
}

void main() {
  uint max_triangles = uint(pc.bricks.w);  // the brick's slot size (MarchingCubesRenderer)
  uint grid_bricks = uint(pc.bricks.x * pc.bricks.y * pc.bricks.z);
  uint brick = brick_list[gl_WorkGroupID.x];
  ivec3 origin = brick_origin(brick);
  uint slot_start = brick * max_triangles * 3u;
  if (gl_LocalInvocationIndex == 0u) {
    triangle_count = 0u;
    tile_looks = 0u;
  }
  barrier();
  uint looks = 0u;
  for (uint w = gl_LocalInvocationIndex; w < (kTileCells + 3u) / 4u; w += 256u) {
    uint word = 0u;
    for (uint b = 0u; b < 4u; ++b) {
      uint i = w * 4u + b;
      if (i >= kTileCells) break;
      ivec3 t = ivec3(int(i % uint(kTile)), int((i / uint(kTile)) % uint(kTile)), int(i / uint(kTile * kTile)));
      uint material = cell_at(origin + t - 2);
      uint look = seen_look(material);
      looks |= 1u << look;
      word |= (material | (look << 3)) << (b * 8u);
    }
    tile[w] = word;
  }
  atomicOr(tile_looks, looks);
  barrier();
  // A layer's surface lies where its look meets another; a tile of one look holds none (most bricks).
  if (layer_has_surface(kLookOpaque)) mesh_layer(brick, origin, kLookOpaque, max_triangles);
  if (layer_has_surface(kLookXray)) mesh_layer(brick, origin, kLookXray, max_triangles);
  barrier();
  uint opaque_triangles = min(triangle_count, max_triangles);
  barrier();  // every invocation has read the opaque count before the translucent layers add to it
  if (layer_has_surface(kLookLiquid)) mesh_layer(brick, origin, kLookLiquid, max_triangles);
  if (layer_has_surface(kLookGas)) mesh_layer(brick, origin, kLookGas, max_triangles);
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    uint total = min(triangle_count, max_triangles);
    write_draw(brick, slot_start, opaque_triangles * 3u, brick);
    write_draw(grid_bricks + brick, slot_start + opaque_triangles * 3u, (total - opaque_triangles) * 3u, brick);
  }
}
