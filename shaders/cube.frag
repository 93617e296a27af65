#version 460
// Instanced cubes, shading: the cell's colour (a run's quad spans cells, each keeps its own), sun +
// sky with per-vertex ambient occlusion, a liquid's glint, the brush highlight; translucent looks
// keep their coverage in alpha (the translucent pass blends).
#include "view.glsl"
#define MATERIALS_BINDING 4
#include "materials.glsl"
#include "see_inside.glsl"
#include "shading.glsl"
layout(location = 0) flat in uint in_material;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in float in_occlusion;
layout(location = 3) in vec3 in_position;
layout(location = 4) flat in uint in_look;
layout(location = 0) out vec4 out_color;

void main() {
  // The cell behind the face: half a cell back along the normal.
  ivec3 cell = ivec3(floor(in_position - 0.5 * in_normal));
  vec3 color = shade(material_color(in_material, cell), in_look, in_normal, in_occlusion, normalize(pc.eye.xyz - in_position));
  out_color = vec4(brush_highlight(color, in_position), seen_alpha(in_look));
}
