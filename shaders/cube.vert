#version 460
// Instanced cubes, draw pass: 18 vertices per instance, two triangles for each of the three faces
// that can face the camera (on each axis, the side towards the eye); faces not showing collapse to
// nothing. Per-vertex ambient occlusion from the three cells around each face corner (cells of the
// face's own see-through rank or above occlude; cells the section removed and static ones under
// x-ray do not). The opaque and
// the translucent pass draw the same way from their own instances (cube_build.comp); cells on the
// side the section removes collapse, and under x-ray the opaque pass leaves the static materials to
// the x-ray pass, which draws the opaque instances again, only those, translucent (see_inside.glsl).
#extension GL_EXT_shader_8bit_storage : require
#extension GL_EXT_shader_explicit_arithmetic_types_int8 : require
#include "view.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Cells { uint8_t cells[]; };
layout(std430, set = 0, binding = 2) readonly buffer Instances { uint instances[]; };
#define MATERIALS_BINDING 4
#include "cells.glsl"
#include "materials.glsl"
#include "see_inside.glsl"

layout(location = 0) out vec4 out_color;  // rgb: base colour; a: coverage (surface_alpha)
layout(location = 1) out vec3 out_normal;
layout(location = 2) out float out_occlusion;
layout(location = 3) out vec3 out_position;
layout(location = 4) flat out uint out_look;

const ivec2 kCorners[6] = ivec2[](ivec2(0, 0), ivec2(1, 0), ivec2(1, 1), ivec2(0, 0), ivec2(1, 1), ivec2(0, 1));

void main() {
  uint brick = uint(gl_InstanceIndex) / kBrickCells;
  uint instance = instances[gl_InstanceIndex];
  uint local = instance & 4095u;
  ivec3 p = brick_origin(brick) + ivec3(int(local & 15u), int((local >> 4) & 15u), int(local >> 8));
  int axis = gl_VertexIndex / 6;
  bool positive = pc.eye[axis] > float(p[axis]) + 0.5;
  uint face = uint(axis) * 2u + (positive ? 1u : 0u);
  uint material = (instance >> 12) & 7u;
  uint look = seen_look(material);
  out_look = kLookVoid;
  if ((instance & (1u << (16u + face))) == 0u || section_removes(p) || !drawn_in_pass(look)) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
  uint rank = see_through_rank(look_of(material));
  ivec3 n = ivec3(0);
  n[axis] = positive ? 1 : -1;
  int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
  ivec2 corner = kCorners[gl_VertexIndex % 6];
  if (!positive) corner = corner.yx;
  ivec3 offset = ivec3(0);
  offset[axis] = positive ? 1 : 0;
  offset[u_axis] = corner.x;
  offset[v_axis] = corner.y;
  ivec3 du = ivec3(0), dv = ivec3(0);
  du[u_axis] = corner.x == 1 ? 1 : -1;
  dv[v_axis] = corner.y == 1 ? 1 : -1;
  ivec3 front = p + n;
  uint side1 = see_through_rank(seen_look(visible_cell_at(front + du))) >= rank ? 1u : 0u;
  uint side2 = see_through_rank(seen_look(visible_cell_at(front + dv))) >= rank ? 1u : 0u;
  uint diagonal = see_through_rank(seen_look(visible_cell_at(front + du + dv))) >= rank ? 1u : 0u;
  float open = (side1 == 1u && side2 == 1u) ? 0.0 : float(3u - side1 - side2 - diagonal);
  vec3 position = vec3(p + offset);
  gl_Position = pc.matrix * vec4(position, 1.0);
  out_color = vec4(material_color(material, p), seen_alpha(look));
  out_normal = vec3(n);
  out_occlusion = 0.55 + 0.15 * open;
  out_position = position;
  out_look = look;
}
