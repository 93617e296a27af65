#version 460
// The section's cap, shading: points of the plane (see_inside.glsl) covered by a kept cell's cut
// show its colour, lit as a face towards the removed side with nothing around it occluding (the ray
// march shades the cut the same way), where this draw's pass shows the cell's look; the rest is
// left open. What covers a point depends on the renderer:
// - cap_cut_faces_only() (instanced cubes): the kept cell just behind the plane, unless the cubes'
//   build listed its face at the plane (face_shows: the cell across the plane does not hide it);
// - otherwise (marching cubes, whose surfaces the plane clips): the cross-section of a look's
//   meshed surface, where the look's density at the plane's lattice points (mc_build.comp),
//   interpolated bilinearly between them, exceeds kIso; in the colour of the kept cell there when
//   it has the look, else of the look's most frequent material around the point.
#extension GL_EXT_shader_8bit_storage : require
#extension GL_EXT_shader_explicit_arithmetic_types_int8 : require
#include "view.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Cells { uint8_t cells[]; };
#define MATERIALS_BINDING 1
#include "cells.glsl"
#include "materials.glsl"
#include "marching_iso.glsl"
#include "see_inside.glsl"
#include "shading.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 0) out vec4 out_color;

// The 3 x 3 x 2 cells around the point: a, b the offsets -1..1 along the plane's two axes from the
// point's cell, layer 0 the kept cell, 1 the one across the plane.
uint around[18];

uint around_at(int a, int b, int layer) { return around[a + 3 * b + 9 * layer]; }

// The density of seen look `look` at lattice point (a, b) of the point's cell (0 or 1 on each axis).
float density(uint look, int a, int b) {
  uint count = 0u;
  for (int c = 0; c < 8; ++c) count += seen_look(around_at(a + (c & 1), b + ((c >> 1) & 1), c >> 2)) == look ? 1u : 0u;
  return float(count) * 0.125;
}

// The material of seen look `look` most frequent around the point (ties: the higher state).
uint most_frequent(uint look) {
  uint counts[8] = uint[8](0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
  for (int i = 0; i < 18; ++i)
    if (seen_look(around[i]) == look) counts[around[i] & 7u]++;
  uint best = 0u;
  for (uint m = 1u; m < 8u; ++m)
    if (counts[m] >= counts[best]) best = m;
  return best;
}

// The material whose meshed surface covers the point at `f` (0..1 across its cell) in this draw's
// pass, or void.
uint smooth_cover(vec2 f) {
  for (uint look = kLookOpaque; look <= kLookXray; ++look) {
    if (!drawn_in_pass(look)) continue;
    float d = mix(mix(density(look, 0, 0), density(look, 1, 0), f.x), mix(density(look, 0, 1), density(look, 1, 1), f.x), f.y);
    if (d > kIso) return seen_look(around_at(1, 1, 0)) == look ? around_at(1, 1, 0) : most_frequent(look);
  }
  return 0u;
}

void main() {
  int axis = section_axis();
  int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
  int plane = section_plane();
  bool keeps_high = section_keeps_high();
  ivec3 cell = min(ivec3(floor(in_position)), pc.grid.xyz - 1);
  cell[axis] = keeps_high ? plane : plane - 1;
  ivec3 across = cell;
  across[axis] = keeps_high ? plane - 1 : plane;
  uint material;
  if (cap_cut_faces_only()) {
    material = cell_at(cell);
    if (face_shows(material, cell_at(across))) discard;
  } else {
    for (int i = 0; i < 18; ++i) {
      ivec3 p = (i >= 9 ? across : cell);
      p[u_axis] += i % 3 - 1;
      p[v_axis] += (i / 3) % 3 - 1;
      around[i] = cell_at(p);
    }
    material = smooth_cover(vec2(in_position[u_axis] - float(cell[u_axis]), in_position[v_axis] - float(cell[v_axis])));
  }
  uint look = seen_look(material);
  if (look_of(material) == kLookVoid || !drawn_in_pass(look)) discard;
  vec3 normal = vec3(0.0);
  normal[axis] = keeps_high ? -1.0 : 1.0;
  vec3 color = shade(material_color(material, cell), look, normal, 1.0, normalize(pc.eye.xyz - in_position));
  out_color = vec4(brush_highlight(color, in_position), seen_alpha(look));
}
