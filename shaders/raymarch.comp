#version 460
// Ray-march renderer: one invocation per pixel walks the grid cell by cell (3D DDA, Amanatides &
// Woo) from the eye until the first non-void cell, crossing empty bricks (brick_occupancy.comp) in
// one step, and shades the cell like the cube renderer does (face normal, sun + sky, ambient
// occlusion from the cells around the hit face). No geometry.
#extension GL_EXT_shader_8bit_storage : require
#extension GL_EXT_shader_explicit_arithmetic_types_int8 : require
layout(local_size_x = 8, local_size_y = 8) in;
#include "view.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Cells { uint8_t cells[]; };
layout(set = 0, binding = 1, rgba8) uniform writeonly image2D color_out;
layout(std430, set = 0, binding = 3) readonly buffer Occupancy { uint occupancy[]; };
#include "cells.glsl"

const vec3 kBackground = vec3(0.62, 0.72, 0.84);

float occupied(ivec3 p) { return cell_at(p) != 0u ? 1.0 : 0.0; }

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(pc.bricks.w, int(pc.brush.w));
  if (pixel.x >= size.x || pixel.y >= size.y) return;
  vec2 ndc = (vec2(pixel) + 0.5) / vec2(size) * 2.0 - 1.0;
  vec4 far_point = pc.matrix * vec4(ndc, 1.0, 1.0);
  vec3 origin = pc.eye.xyz;
  vec3 direction = normalize(far_point.xyz / far_point.w - origin);
  vec3 inv = 1.0 / direction;
  vec3 t0 = (vec3(0.0) - origin) * inv, t1 = (vec3(pc.grid.xyz) - origin) * inv;
  float t_enter = max(max(min(t0.x, t1.x), min(t0.y, t1.y)), max(min(t0.z, t1.z), 0.0));
  float t_exit = min(min(max(t0.x, t1.x), max(t0.y, t1.y)), max(t0.z, t1.z));
  vec3 color = kBackground;
  if (t_enter < t_exit) {
    vec3 start = origin + direction * (t_enter + 1e-4);
    ivec3 cell = clamp(ivec3(floor(start)), ivec3(0), pc.grid.xyz - 1);
    ivec3 step_dir = ivec3(sign(direction));
    vec3 next_boundary = vec3(cell) + max(vec3(step_dir), vec3(0.0));
    vec3 t_max = (next_boundary - origin) * inv;
    vec3 t_delta = abs(inv);
    // The axis of the face the ray entered the grid through (the normal if the first cell is hit).
    float tx = min(t0.x, t1.x), ty = min(t0.y, t1.y), tz = min(t0.z, t1.z);
    int axis = (tx >= ty && tx >= tz) ? 0 : (ty >= tz ? 1 : 2);
    int max_steps = pc.grid.x + pc.grid.y + pc.grid.z + 3;
    for (int i = 0; i < max_steps; ++i) {
      if (!inside_grid(cell)) break;
      ivec3 brick = cell / kBrickSize;
      if (occupancy[uint(brick.x) + uint(pc.bricks.x) * (uint(brick.y) + uint(pc.bricks.y) * uint(brick.z))] == 0u) {
        // Jump to where the ray leaves this empty brick and restart the walk there.
        vec3 low = vec3(brick * kBrickSize), high = min(low + float(kBrickSize), vec3(pc.grid.xyz));
        vec3 t_out = (mix(low, high, greaterThan(direction, vec3(0.0))) - origin) * inv;
        t_out = mix(t_out, vec3(1e30), equal(direction, vec3(0.0)));
        float t_leave = min(min(t_out.x, t_out.y), t_out.z);
        axis = t_out.x <= t_out.y && t_out.x <= t_out.z ? 0 : (t_out.y <= t_out.z ? 1 : 2);
        ivec3 next = ivec3(floor(origin + direction * t_leave));
        // The exit face decides the next cell along `axis`; rounding must not keep us inside.
        next[axis] = step_dir[axis] > 0 ? int(high[axis]) : int(low[axis]) - 1;
        cell = next;
        t_max = (vec3(cell) + max(vec3(step_dir), vec3(0.0)) - origin) * inv;
        continue;
      }
      uint material = material_of(cells[cell_index(cell)]);
      if (material != 0u) {
        ivec3 n = ivec3(0);
        n[axis] = -step_dir[axis];
        ivec3 front = cell + n;
        int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
        ivec3 du = ivec3(0), dv = ivec3(0);
        du[u_axis] = 1;
        dv[v_axis] = 1;
        float around = occupied(front + du) + occupied(front - du) + occupied(front + dv) + occupied(front - dv);
        float diagonal = occupied(front + du + dv) + occupied(front + du - dv) + occupied(front - du + dv) +
                         occupied(front - du - dv);
        float occlusion = 1.0 - 0.09 * around - 0.045 * diagonal;
        color = shade(material_color(material, cell), vec3(n), occlusion);
        if (pc.eye.w > 0.0 && distance(vec3(cell) + 0.5, pc.brush.xyz) < pc.eye.w) color = mix(color, vec3(1.0, 0.35, 0.2), 0.35);
        break;
      }
      if (t_max.x < t_max.y && t_max.x < t_max.z) {
        cell.x += step_dir.x; t_max.x += t_delta.x; axis = 0;
      } else if (t_max.y < t_max.z) {
        cell.y += step_dir.y; t_max.y += t_delta.y; axis = 1;
      } else {
        cell.z += step_dir.z; t_max.z += t_delta.z; axis = 2;
      }
    }
  }
  imageStore(color_out, pixel, vec4(color, 1.0));
}
