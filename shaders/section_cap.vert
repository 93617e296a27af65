#version 460
// The section's cap, draw pass: one quad over the grid's cross-section at the section plane
// (see_inside.glsl), two triangles; section_cap.frag colours it by the cells behind it.
#include "view.glsl"
#define MATERIALS_BINDING 1
#include "materials.glsl"
#include "see_inside.glsl"

layout(location = 0) out vec3 out_position;

const ivec2 kCorners[6] = ivec2[](ivec2(0, 0), ivec2(1, 0), ivec2(1, 1), ivec2(0, 0), ivec2(1, 1), ivec2(0, 1));

void main() {
  int axis = max(section_axis(), 0);
  int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
  ivec2 corner = kCorners[gl_VertexIndex];
  vec3 position;
  position[axis] = float(section_plane());
  position[u_axis] = float(corner.x * pc.grid[u_axis]);
  position[v_axis] = float(corner.y * pc.grid[v_axis]);
  gl_Position = pc.matrix * vec4(position, 1.0);
  out_position = position;
}
