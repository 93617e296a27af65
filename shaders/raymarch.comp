#version 460
// Ray-march renderer: one invocation per pixel walks the grid cell by cell (3D DDA, Amanatides &
// Woo) from the eye, crossing empty bricks (brick_occupancy.comp) in one step, until the first
// opaque cell, which it shades like the cube renderer does (face normal, sun + sky, ambient
// occlusion from the opaque cells around the hit face). Liquids and gases are seen through: where
// the ray enters one, its surface is shaded and covers part of what lies behind (liquid glints);
// inside, each cell crossed absorbs in proportion to the path's length in it (Beer-Lambert), a
// liquid strongly, a gas faintly. No geometry. The walk covers only the cells the section keeps
// (see_inside.glsl): a ray enters them through the plane, where the first cell it meets shows as
// a face towards the removed side, and the removed cells neither hit nor occlude. Under x-ray a
// static material is a medium too, covering a little where the ray enters it and absorbing
// faintly.
#extension GL_EXT_shader_8bit_storage : require
#extension GL_EXT_shader_explicit_arithmetic_types_int8 : require
layout(local_size_x = 8, local_size_y = 8) in;
#include "view.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Cells { uint8_t cells[]; };
layout(set = 0, binding = 1, rgba8) uniform writeonly image2D color_out;
layout(std430, set = 0, binding = 3) readonly buffer Occupancy { uint occupancy[]; };
#define MATERIALS_BINDING 4
#include "cells.glsl"
#include "materials.glsl"
#include "see_inside.glsl"
#include "shading.glsl"

const vec3 kBackground = vec3(0.62, 0.72, 0.84);

float occluder(ivec3 p) { return seen_look(visible_cell_at(p)) == kLookOpaque ? 1.0 : 0.0; }

// Fraction of the light a surface of seen look `look` reflects where the ray enters it.
float entry_coverage(uint look) { return look == kLookLiquid ? 0.35 : (look == kLookXray ? kXrayAlpha : 0.10); }

// Absorption per cell of path inside a medium of seen look `look`.
float absorption(uint look) { return look == kLookLiquid ? 0.12 : (look == kLookXray ? 0.04 : 0.035); }

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(pc.bricks.w, int(pc.brush.w));
  if (pixel.x >= size.x || pixel.y >= size.y) return;
  vec2 ndc = (vec2(pixel) + 0.5) / vec2(size) * 2.0 - 1.0;
  vec4 far_point = pc.matrix * vec4(ndc, 1.0, 1.0);
  vec3 origin = pc.eye.xyz;
  vec3 direction = normalize(far_point.xyz / far_point.w - origin);
  vec3 inv = 1.0 / direction;
  // The box of kept cells: the grid, less the side of the plane the section removes.
  ivec3 box_low = ivec3(0), box_high = pc.grid.xyz;
  int section = section_axis();
  if (section >= 0) {
    if (section_keeps_high()) box_low[section] = section_plane();
    else box_high[section] = section_plane();
  }
  vec3 t0 = (vec3(box_low) - origin) * inv, t1 = (vec3(box_high) - origin) * inv;
  float t_enter = max(max(min(t0.x, t1.x), min(t0.y, t1.y)), max(min(t0.z, t1.z), 0.0));
  float t_exit = min(min(max(t0.x, t1.x), max(t0.y, t1.y)), max(t0.z, t1.z));
  vec3 gathered = vec3(0.0);  // light reaching the eye from what the ray crossed so far
  float transmitted = 1.0;    // fraction of what lies further along that still reaches the eye
  if (t_enter < t_exit && all(lessThan(box_low, box_high))) {
    vec3 start = origin + direction * (t_enter + 1e-4);
    ivec3 cell = clamp(ivec3(floor(start)), box_low, box_high - 1);
    ivec3 step_dir = ivec3(sign(direction));
    vec3 next_boundary = vec3(cell) + max(vec3(step_dir), vec3(0.0));
    vec3 t_max = (next_boundary - origin) * inv;
    vec3 t_delta = abs(inv);
    float t_cell = t_enter;  // where the ray entered the current cell
    uint medium = 0u;        // the translucent material the ray is inside (0: none)
    // The axis of the face the ray entered the grid through (the normal if the first cell is hit).
    float tx = min(t0.x, t1.x), ty = min(t0.y, t1.y), tz = min(t0.z, t1.z);
    int axis = (tx >= ty && tx >= tz) ? 0 : (ty >= tz ? 1 : 2);
    int max_steps = pc.grid.x + pc.grid.y + pc.grid.z + 3;
    for (int i = 0; i < max_steps; ++i) {
      if (any(lessThan(cell, box_low)) || any(greaterThanEqual(cell, box_high))) break;
      ivec3 brick = cell / kBrickSize;
      if (occupancy[uint(brick.x) + uint(pc.bricks.x) * (uint(brick.y) + uint(pc.bricks.y) * uint(brick.z))] == 0u) {
        // Jump to where the ray leaves this empty brick and restart the walk there.
        vec3 low = vec3(max(brick * kBrickSize, box_low)), high = vec3(min(brick * kBrickSize + kBrickSize, box_high));
        vec3 t_out = (mix(low, high, greaterThan(direction, vec3(0.0))) - origin) * inv;
        t_out = mix(t_out, vec3(1e30), equal(direction, vec3(0.0)));
        float t_leave = min(min(t_out.x, t_out.y), t_out.z);
        axis = t_out.x <= t_out.y && t_out.x <= t_out.z ? 0 : (t_out.y <= t_out.z ? 1 : 2);
        ivec3 next = ivec3(floor(origin + direction * t_leave));
        // The exit face decides the next cell along `axis`; rounding must not keep us inside.
        next[axis] = step_dir[axis] > 0 ? int(high[axis]) : int(low[axis]) - 1;
        cell = next;
        t_max = (vec3(cell) + max(vec3(step_dir), vec3(0.0)) - origin) * inv;
        t_cell = t_leave;
        medium = 0u;
        continue;
      }
      uint material = material_of(cells[cell_index(cell)]);
      uint look = seen_look(material);
      if (look != kLookVoid) {
        ivec3 n = ivec3(0);
        n[axis] = -step_dir[axis];
        if (look == kLookOpaque) {
          ivec3 front = cell + n;
          int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
          ivec3 du = ivec3(0), dv = ivec3(0);
          du[u_axis] = 1;
          dv[v_axis] = 1;
          float around = occluder(front + du) + occluder(front - du) + occluder(front + dv) + occluder(front - dv);
          float diagonal = occluder(front + du + dv) + occluder(front + du - dv) + occluder(front - du + dv) +
                           occluder(front - du - dv);
          float occlusion = 1.0 - 0.09 * around - 0.045 * diagonal;
          vec3 color = shade(material_color(material, cell), look, vec3(n), occlusion, -direction);
          gathered += transmitted * brush_highlight(color, vec3(cell) + 0.5);
          transmitted = 0.0;
          break;
        }
        vec3 albedo = material_color(material, cell);
        if (material != medium) {
          float coverage = entry_coverage(look);
          gathered += transmitted * coverage * brush_highlight(shade(albedo, look, vec3(n), 1.0, -direction), vec3(cell) + 0.5);
          transmitted *= 1.0 - coverage;
        }
        float t_next = min(min(t_max.x, t_max.y), t_max.z);
        float absorbed = 1.0 - exp(-absorption(look) * max(t_next - t_cell, 0.0));
        gathered += transmitted * absorbed * albedo * 0.8;  // the medium's own colour, lit from all around
        transmitted *= 1.0 - absorbed;
        medium = material;
        if (transmitted < 0.01) break;
      } else {
        medium = 0u;
      }
      t_cell = min(min(t_max.x, t_max.y), t_max.z);
      if (t_max.x < t_max.y && t_max.x < t_max.z) {
        cell.x += step_dir.x; t_max.x += t_delta.x; axis = 0;
      } else if (t_max.y < t_max.z) {
        cell.y += step_dir.y; t_max.y += t_delta.y; axis = 1;
      } else {
        cell.z += step_dir.z; t_max.z += t_delta.z; axis = 2;
      }
    }
  }
  imageStore(color_out, pixel, vec4(gathered + transmitted * kBackground, 1.0));
}
