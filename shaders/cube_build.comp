#version 460
// Instanced cubes, build pass: for each brick of the list, writes one instance per non-void cell
// with a face showing (materials.glsl's face_shows: towards void, a translucent neighbour in front
// of a denser look, or another translucent material; under x-ray also towards a static material:
// see_inside.glsl's seen_face_shows) into the brick's slot (4096 instances):
// opaque instances from the slot's start, translucent ones (liquid, gas) from its end. Then it writes the brick's two indirect draw
// commands: draws[brick] for the opaque instances, draws[bricks in the grid + brick] for the
// translucent ones. Instance: bits 0-11 cell in brick, 12-14 material, 16-21 showing faces.
#extension GL_EXT_shader_8bit_storage : require
#extension GL_EXT_shader_explicit_arithmetic_types_int8 : require
layout(local_size_x = 256) in;
#include "view.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Cells { uint8_t cells[]; };
layout(std430, set = 0, binding = 1) readonly buffer BrickList { uint brick_list[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Instances { uint instances[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Draws { uint draws[]; };
#define MATERIALS_BINDING 4
#include "cells.glsl"
#include "materials.glsl"
#include "see_inside.glsl"

shared uint opaque_count;
shared uint translucent_count;

bool shows_towards(uint material, ivec3 neighbour) { return seen_face_shows(material, cell_at(neighbour)); }

void main() {
  uint brick = brick_list[gl_WorkGroupID.x];
  if (gl_LocalInvocationIndex == 0u) {
    opaque_count = 0u;
    translucent_count = 0u;
  }
  barrier();
  ivec3 origin = brick_origin(brick);
  for (uint i = gl_LocalInvocationIndex; i < kBrickCells; i += 256u) {
    ivec3 local = ivec3(int(i & 15u), int((i >> 4) & 15u), int(i >> 8));
    ivec3 p = origin + local;
    if (!inside_grid(p)) continue;
    uint material = material_of(cells[cell_index(p)]);
    uint look = look_of(material);
    if (look == kLookVoid) continue;
    uint faces = (shows_towards(material, p + ivec3(-1, 0, 0)) ? 1u : 0u) | (shows_towards(material, p + ivec3(1, 0, 0)) ? 2u : 0u) |
                 (shows_towards(material, p + ivec3(0, -1, 0)) ? 4u : 0u) | (shows_towards(material, p + ivec3(0, 1, 0)) ? 8u : 0u) |
                 (shows_towards(material, p + ivec3(0, 0, -1)) ? 16u : 0u) | (shows_towards(material, p + ivec3(0, 0, 1)) ? 32u : 0u);
    if (faces == 0u) continue;
    uint slot = is_translucent(look) ? kBrickCells - 1u - atomicAdd(translucent_count, 1u) : atomicAdd(opaque_count, 1u);
    instances[brick * kBrickCells + slot] = i | (material << 12) | (faces << 16);
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    uint grid_bricks = uint(pc.bricks.x * pc.bricks.y * pc.bricks.z);
    uint opaque = brick * 4u, translucent = (grid_bricks + brick) * 4u;
    draws[opaque + 0u] = 18u;  // three camera-facing faces (cube.vert)
    draws[opaque + 1u] = opaque_count;
    draws[opaque + 2u] = 0u;
    draws[opaque + 3u] = brick * kBrickCells;
    draws[translucent + 0u] = 18u;
    draws[translucent + 1u] = translucent_count;
    draws[translucent + 2u] = 0u;
    draws[translucent + 3u] = brick * kBrickCells + kBrickCells - translucent_count;
  }
}
