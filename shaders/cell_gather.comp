#version 460
// Copies the listed bricks' cells from another grid of the same layout (the cells shared with
// CUDA) into the cell buffer, so a frame copies only what changed.
#extension GL_EXT_shader_8bit_storage : require
#extension GL_EXT_shader_explicit_arithmetic_types_int8 : require
layout(local_size_x = 256) in;
#include "view.glsl"
layout(std430, set = 0, binding = 0) buffer Cells { uint8_t cells[]; };
layout(std430, set = 0, binding = 1) readonly buffer BrickList { uint brick_list[]; };
layout(std430, set = 0, binding = 2) readonly buffer Source { uint8_t source_cells[]; };
#include "cells.glsl"

void main() {
  ivec3 origin = brick_origin(brick_list[gl_WorkGroupID.x]);
  for (uint i = gl_LocalInvocationIndex; i < kBrickCells; i += 256u) {
    ivec3 p = origin + ivec3(int(i & 15u), int((i >> 4) & 15u), int(i >> 8));
    if (inside_grid(p)) {
      uint index = cell_index(p);
      cells[index] = source_cells[index];
    }
  }
}
