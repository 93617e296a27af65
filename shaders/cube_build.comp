#version 460
// Instanced cubes, build pass: for each brick of the list, writes one instance per non-void cell
// with a void face neighbour into the brick's slot (4096 instances), and the brick's indirect
// draw command. Instance: bits 0-11 cell in brick, 12-14 material, 16-21 exposed faces.
#extension GL_EXT_shader_8bit_storage : require
#extension GL_EXT_shader_explicit_arithmetic_types_int8 : require
layout(local_size_x = 256) in;
#include "view.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Cells { uint8_t cells[]; };
layout(std430, set = 0, binding = 1) readonly buffer BrickList { uint brick_list[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Instances { uint instances[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Draws { uint draws[]; };
#include "cells.glsl"

shared uint instance_count;

void main() {
  uint brick = brick_list[gl_WorkGroupID.x];
  if (gl_LocalInvocationIndex == 0u) instance_count = 0u;
  barrier();
  ivec3 origin = brick_origin(brick);
  for (uint i = gl_LocalInvocationIndex; i < kBrickCells; i += 256u) {
    ivec3 local = ivec3(int(i & 15u), int((i >> 4) & 15u), int(i >> 8));
    ivec3 p = origin + local;
    if (!inside_grid(p)) continue;
    uint material = material_of(cells[cell_index(p)]);
    if (material == 0u) continue;
    uint faces = (cell_at(p + ivec3(-1, 0, 0)) == 0u ? 1u : 0u) | (cell_at(p + ivec3(1, 0, 0)) == 0u ? 2u : 0u) |
                 (cell_at(p + ivec3(0, -1, 0)) == 0u ? 4u : 0u) | (cell_at(p + ivec3(0, 1, 0)) == 0u ? 8u : 0u) |
                 (cell_at(p + ivec3(0, 0, -1)) == 0u ? 16u : 0u) | (cell_at(p + ivec3(0, 0, 1)) == 0u ? 32u : 0u);
    if (faces == 0u) continue;
    uint slot = atomicAdd(instance_count, 1u);
    instances[brick * kBrickCells + slot] = i | (material << 12) | (faces << 16);
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    draws[brick * 4u + 0u] = 18u;  // three camera-facing faces (cube.vert)
    draws[brick * 4u + 1u] = instance_count;
    draws[brick * 4u + 2u] = 0u;
    draws[brick * 4u + 3u] = brick * kBrickCells;
  }
}
