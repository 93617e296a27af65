#version 460
// Marching cubes, shading: sun + sky on the interpolated density-gradient normal, a liquid's glint,
// the brush highlight; translucent looks keep their coverage in alpha (the translucent pass blends).
#include "view.glsl"
#define MATERIALS_BINDING 5
#include "materials.glsl"
#include "shading.glsl"
layout(location = 0) in vec4 in_color;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec3 in_position;
layout(location = 3) flat in uint in_look;
layout(location = 0) out vec4 out_color;

void main() {
  vec3 color = shade(in_color.rgb, in_look, normalize(in_normal), 1.0, normalize(pc.eye.xyz - in_position));
  out_color = vec4(brush_highlight(color, in_position), in_color.a);
}
