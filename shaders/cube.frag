#version 460
// Instanced cubes, shading: sun + sky with per-vertex ambient occlusion and a brush highlight.
#include "view.glsl"
layout(location = 0) in vec3 in_color;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in float in_occlusion;
layout(location = 3) in vec3 in_position;
layout(location = 0) out vec4 out_color;

const vec3 kSun = normalize(vec3(0.45, 0.30, 0.84));

void main() {
  float diffuse = max(dot(in_normal, kSun), 0.0);
  float sky = 0.5 + 0.5 * in_normal.z;
  vec3 color = in_color * (0.72 * diffuse + 0.38 * sky) * in_occlusion;
  if (pc.eye.w > 0.0 && distance(in_position, pc.brush.xyz) < pc.eye.w) color = mix(color, vec3(1.0, 0.35, 0.2), 0.35);
  out_color = vec4(color, 1.0);
}
