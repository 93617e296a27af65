#version 460
// Copies uploaded bricks (packed 16^3, x fastest) from the staging buffer into the linear cell grid.
#extension GL_EXT_shader_8bit_storage : require
#extension GL_EXT_shader_explicit_arithmetic_types_int8 : require
layout(local_size_x = 256) in;
#include "view.glsl"
layout(std430, set = 0, binding = 0) buffer Cells { uint8_t cells[]; };
layout(std430, set = 0, binding = 1) readonly buffer BrickList { uint brick_list[]; };
layout(std430, set = 0, binding = 2) readonly buffer Packed { uint8_t packed_cells[]; };
#include "cells.glsl"

void main() {
  uint slot = gl_WorkGroupID.x;
  ivec3 origin = brick_origin(brick_list[slot]);
  for (uint i = gl_LocalInvocationIndex; i < kBrickCells; i += 256u) {
    ivec3 p = origin + ivec3(int(i & 15u), int((i >> 4) & 15u), int(i >> 8));
    if (inside_grid(p)) cells[cell_index(p)] = packed_cells[slot * kBrickCells + i];
  }
}
