#version 460
// Instanced cubes, draw pass (cube_build.comp writes the instances). A quad instance is 6 vertices:
// a rectangle of faces, stretched over its cells along the face's run axis and across it; it
// collapses when the face points away from the eye. A cell instance is 18 vertices, two triangles
// for each of the three faces that can face the camera (on each axis, the side towards the eye);
// faces not showing collapse. Ambient occlusion per vertex from the three cells around each face
// corner (cells of the face's own see-through rank or above occlude; cells the section removed and
// static ones under x-ray do not); an open quad (nothing around it shades it) reads none. The opaque
// and the translucent pass draw the same way from their own instances; cells on the side the
// section removes collapse (a quad crossing the plane is cut at it), and under x-ray the opaque pass
// leaves the static materials to the x-ray pass, which draws the opaque instances again, only
// those, translucent (see_inside.glsl). The colour is the fragment's (cube.frag), per cell.
#extension GL_EXT_shader_8bit_storage : require
#extension GL_EXT_shader_explicit_arithmetic_types_int8 : require
#include "view.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Cells { uint8_t cells[]; };
layout(std430, set = 0, binding = 2) readonly buffer Instances { uint instances[]; };
#define MATERIALS_BINDING 4
#include "cells.glsl"
#include "materials.glsl"
#include "see_inside.glsl"

layout(location = 0) flat out uint out_material;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out float out_occlusion;
layout(location = 3) out vec3 out_position;
layout(location = 4) flat out uint out_look;

const uint kQuadInstance = 0x80000000u;
const ivec2 kCorners[6] = ivec2[](ivec2(0, 0), ivec2(1, 0), ivec2(1, 1), ivec2(0, 0), ivec2(1, 1), ivec2(0, 1));

// The axis a face of axis `axis` runs along (cube_build.comp has the same).
int run_axis(int axis) { return axis == 0 ? 1 : 0; }

void collapse() {
  gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
  out_look = kLookVoid;
}

void main() {
  uint brick = uint(gl_InstanceIndex) / kBrickCells;
  uint instance = instances[gl_InstanceIndex];
  uint local = instance & 4095u;
  ivec3 p = brick_origin(brick) + ivec3(int(local & 15u), int((local >> 4) & 15u), int(local >> 8));
  uint material = (instance >> 12) & 7u;
  uint look = seen_look(material);
  int axis;
  bool positive;
  // The quad's extent from p along the face's run axis (first..last) and across it (low..high).
  int first = 0, last = 1, low = 0, high = 1;
  bool open_face = false;
  if ((instance & kQuadInstance) != 0u) {
    uint face = (instance >> 15) & 7u;
    axis = int(face >> 1u);
    positive = (face & 1u) != 0u;
    last = int((instance >> 18) & 15u) + 1;
    high = int((instance >> 23) & 15u) + 1;
    open_face = (instance & (1u << 22u)) != 0u;
    if (positive != (pc.eye[axis] > float(p[axis]) + 0.5)) {
      collapse();
      return;
    }
    int along = run_axis(axis), across = 3 - axis - along;
    int plane = section_plane();
    if (section_axis() == along) {
      if (section_keeps_high()) first = max(first, plane - p[along]);
      else last = min(last, plane - p[along]);
    } else if (section_axis() == across) {
      if (section_keeps_high()) low = max(low, plane - p[across]);
      else high = min(high, plane - p[across]);
    } else if (section_removes(p)) {
      first = last;
    }
  } else {
    axis = gl_VertexIndex / 6;
    positive = pc.eye[axis] > float(p[axis]) + 0.5;
    uint face = uint(axis) * 2u + (positive ? 1u : 0u);
    if ((instance & (1u << (16u + face))) == 0u || section_removes(p)) first = last;
  }
  if (first >= last || low >= high || !drawn_in_pass(look)) {
    collapse();
    return;
  }
  uint rank = see_through_rank(look_of(material));
  ivec3 n = ivec3(0);
  n[axis] = positive ? 1 : -1;
  int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
  ivec2 corner = kCorners[gl_VertexIndex % 6];
  if (!positive) corner = corner.yx;
  // The quad spans first..last along the run axis and low..high across it (0..1 each for a cell).
  int along = run_axis(axis);
  ivec3 offset = ivec3(0);
  offset[axis] = positive ? 1 : 0;
  offset[u_axis] = corner.x == 1 ? (u_axis == along ? last : high) : (u_axis == along ? first : low);
  offset[v_axis] = corner.y == 1 ? (v_axis == along ? last : high) : (v_axis == along ? first : low);
  float open = 3.0;
  if (!open_face) {
    ivec3 du = ivec3(0), dv = ivec3(0);
    du[u_axis] = corner.x == 1 ? 1 : -1;
    dv[v_axis] = corner.y == 1 ? 1 : -1;
    ivec3 front = p + n;
    uint side1 = see_through_rank(seen_look(visible_cell_at(front + du))) >= rank ? 1u : 0u;
    uint side2 = see_through_rank(seen_look(visible_cell_at(front + dv))) >= rank ? 1u : 0u;
    uint diagonal = see_through_rank(seen_look(visible_cell_at(front + du + dv))) >= rank ? 1u : 0u;
    open = (side1 == 1u && side2 == 1u) ? 0.0 : float(3u - side1 - side2 - diagonal);
  }
  vec3 position = vec3(p + offset);
  gl_Position = pc.matrix * vec4(position, 1.0);
  out_material = material;
  out_normal = vec3(n);
  out_occlusion = 0.55 + 0.15 * open;
  out_position = position;
  out_look = look;
}
