#version 460
// Marching cubes, before the build: one workgroup per listed brick reads the looks of the cells
// mc_build.comp's tile would hold (the brick and a border of 2, cells outside the grid void). A
// brick whose tile holds one look has no surface: its two draw commands are written empty here.
// Every other brick is appended to the mesh list, whose first three words are the build's
// indirect dispatch (bricks listed, 1, 1), so the build's costly workgroups run only where there
// is something to mesh.
#extension GL_EXT_shader_8bit_storage : require
#extension GL_EXT_shader_explicit_arithmetic_types_int8 : require
layout(local_size_x = 256) in;
#include "view.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Cells { uint8_t cells[]; };
layout(std430, set = 0, binding = 1) readonly buffer BrickList { uint brick_list[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Draws { uint draws[]; };
layout(std430, set = 0, binding = 8) buffer MeshList { uint mesh_list[]; };  // dispatch x, 1, 1, then bricks
#define MATERIALS_BINDING 5
#include "cells.glsl"
#include "materials.glsl"
#include "see_inside.glsl"
#include "marching_tile.glsl"

shared uint tile_looks;

void main() {
  uint brick = brick_list[gl_WorkGroupID.x];
  ivec3 origin = brick_origin(brick);
  if (gl_LocalInvocationIndex == 0u) tile_looks = 0u;
  barrier();
  uint looks = 0u;
  for (uint i = gl_LocalInvocationIndex; i < uint(kTile * kTile * kTile); i += 256u) {
    ivec3 t = ivec3(int(i % uint(kTile)), int((i / uint(kTile)) % uint(kTile)), int(i / uint(kTile * kTile)));
    looks |= 1u << seen_look(cell_at(origin + t - 2));
  }
  atomicOr(tile_looks, looks);
  barrier();
  if (gl_LocalInvocationIndex != 0u) return;
  if (bitCount(tile_looks) > 1u) {
    mesh_list[3u + atomicAdd(mesh_list[0], 1u)] = brick;
    return;
  }
  uint grid_bricks = uint(pc.bricks.x * pc.bricks.y * pc.bricks.z);
  draws[brick * 5u] = 0u;                   // the opaque command's index count
  draws[(grid_bricks + brick) * 5u] = 0u;   // the translucent one's
}
