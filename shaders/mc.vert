#version 460
// Marching cubes, draw pass: unpacks the vertices the build pass wrote (brick = instance index):
// position, normal, material; the colour and look come from the material table. The opaque and
// the translucent pass draw the same way from their own triangles (mc_build.comp). The section
// plane clips every surface (gl_ClipDistance; section_cap.frag closes the cut), and under x-ray
// the opaque pass leaves the static materials' triangles to the x-ray pass, which draws the opaque
// triangles again, only those, translucent (see_inside.glsl).
#include "view.glsl"
layout(std430, set = 0, binding = 2) readonly buffer Vertices { uvec2 vertices[]; };
#define MATERIALS_BINDING 5
#include "materials.glsl"
#include "see_inside.glsl"

layout(location = 0) out vec4 out_color;  // rgb: base colour; a: coverage (surface_alpha)
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec3 out_position;
layout(location = 3) flat out uint out_look;
out float gl_ClipDistance[1];

vec3 decode_octahedral(uint packed_normal) {
  vec2 e = vec2(float(packed_normal & 16383u), float((packed_normal >> 14) & 16383u)) / 16383.0 * 2.0 - 1.0;
  vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
  return normalize(n);
}

void main() {
  uint brick = uint(gl_InstanceIndex);
  uvec2 vertex = vertices[gl_VertexIndex];
  uint bx = uint(pc.bricks.x), by = uint(pc.bricks.y);
  vec3 origin = vec3(float(brick % bx), float((brick / bx) % by), float(brick / (bx * by))) * 16.0;
  vec3 local = vec3(float(vertex.x & 1023u), float((vertex.x >> 10) & 1023u), float((vertex.x >> 20) & 1023u)) / 50.0 - 2.0;
  vec3 position = origin + local;
  uint material = vertex.y >> 28;
  uint look = seen_look(material);
  if (!drawn_in_pass(look)) {  // every vertex of a triangle has its material: the whole triangle goes
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    gl_ClipDistance[0] = -1.0;
    out_look = kLookVoid;
    return;
  }
  vec3 base = materials[material].colour.rgb;
  if (look_of(material) == kLookOpaque) {
    // A brightness jitter per half cell, so a smooth heap still shows grains.
    ivec3 cell = ivec3(floor(position * 2.0));
    uint h = uint(cell.x) * 73856093u ^ uint(cell.y) * 19349663u ^ uint(cell.z) * 83492791u;
    base *= 0.93 + 0.10 * (float(((h ^ (h >> 13)) * 1274126177u) & 255u) / 255.0);
  }
  gl_Position = pc.matrix * vec4(position, 1.0);
  gl_ClipDistance[0] = section_distance(position);
  out_color = vec4(base, seen_alpha(look));
  out_normal = decode_octahedral(vertex.y);
  out_position = position;
  out_look = look;
}
