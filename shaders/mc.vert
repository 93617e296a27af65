#version 460
// Marching cubes, draw pass: unpacks the vertices the build pass wrote (brick = instance index).
#include "view.glsl"
layout(std430, set = 0, binding = 2) readonly buffer Vertices { uvec2 vertices[]; };

layout(location = 0) out vec3 out_color;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec3 out_position;

vec3 decode_octahedral(uint packed_normal) {
  vec2 e = vec2(float(packed_normal & 65535u), float(packed_normal >> 16)) / 65535.0 * 2.0 - 1.0;
  vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
  return normalize(n);
}

void main() {
  uint brick = uint(gl_InstanceIndex);
  uvec2 vertex = vertices[gl_VertexIndex];
  uint bx = uint(pc.bricks.x), by = uint(pc.bricks.y);
  vec3 origin = vec3(float(brick % bx), float((brick / bx) % by), float(brick / (bx * by))) * 16.0;
  vec3 local = vec3(float(vertex.x & 1023u), float((vertex.x >> 10) & 1023u), float((vertex.x >> 20) & 1023u)) / 50.0 - 1.0;
  vec3 position = origin + local;
  uint material = vertex.x >> 30;
  ivec3 cell = ivec3(floor(position * 2.0));
  uint h = uint(cell.x) * 73856093u ^ uint(cell.y) * 19349663u ^ uint(cell.z) * 83492791u;
  float jitter = float(((h ^ (h >> 13)) * 1274126177u) & 255u) / 255.0;
  vec3 base = material == 0u ? vec3(0.87, 0.72, 0.46) : (material == 1u ? vec3(0.46, 0.47, 0.50) : vec3(0.25, 0.45, 0.85));
  gl_Position = pc.matrix * vec4(position, 1.0);
  out_color = base * (0.93 + 0.10 * jitter);
  out_normal = decode_octahedral(vertex.y);
  out_position = position;
}
