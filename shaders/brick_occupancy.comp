#version 460
// Ray march, empty-space skipping: for each listed brick, writes 1 when it holds a non-void cell,
// else 0, so raymarch.comp can cross empty bricks in one step.
#extension GL_EXT_shader_8bit_storage : require
#extension GL_EXT_shader_explicit_arithmetic_types_int8 : require
layout(local_size_x = 256) in;
#include "view.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Cells { uint8_t cells[]; };
layout(std430, set = 0, binding = 2) readonly buffer BrickList { uint brick_list[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Occupancy { uint occupancy[]; };
#include "cells.glsl"

shared uint any_filled;

void main() {
  uint brick = brick_list[gl_WorkGroupID.x];
  if (gl_LocalInvocationIndex == 0u) any_filled = 0u;
  barrier();
  ivec3 origin = brick_origin(brick);
  uint filled = 0u;
  for (uint i = gl_LocalInvocationIndex; i < kBrickCells; i += 256u) {
    ivec3 p = origin + ivec3(int(i & 15u), int((i >> 4) & 15u), int(i >> 8));
    if (inside_grid(p) && material_of(cells[cell_index(p)]) != 0u) filled = 1u;
  }
  if (filled != 0u) atomicOr(any_filled, 1u);
  barrier();
  if (gl_LocalInvocationIndex == 0u) occupancy[brick] = any_filled;
}
