// How the frame shows the inside of the world (viewer/src/see_inside.hpp): the section plane and
// x-ray, decoded from pc.grid.w. The builds (cube_build.comp, mc_build.comp) read x-ray too, so
// toggling it rebuilds the bricks once; the section is applied only when drawing. Include after view.glsl and materials.glsl, and after cells.glsl
// where the shader reads cells (visible_cell_at).

const uint kLookXray = 4u;  // a static material's surface under x-ray: translucent
const float kXrayAlpha = 0.3;

const uint kPassOpaque = 0u;
const uint kPassTranslucent = 1u;
const uint kPassXray = 2u;

uint see_inside_word() { return uint(pc.grid.w); }

// The section's axis (0, 1, 2), or -1 when there is none.
int section_axis() { return int(see_inside_word() & 3u) - 1; }

// True when the section keeps the cells at or above the plane (the eye is below it).
bool section_keeps_high() { return (see_inside_word() & 4u) != 0u; }

// The plane: the boundary between cells plane - 1 and plane along the section's axis.
int section_plane() { return int(see_inside_word() >> 8); }

bool xray_on() { return (see_inside_word() & 8u) != 0u; }

uint draw_pass() { return (see_inside_word() >> 4) & 3u; }

// True when the section's cap covers only the kept cells whose neighbour across the plane is not void.
bool cap_cut_faces_only() { return (see_inside_word() & 64u) != 0u; }

// True when cell p lies on the side of the plane the section removes.
bool section_removes(ivec3 p) {
  int axis = section_axis();
  if (axis < 0) return false;
  return section_keeps_high() ? p[axis] < section_plane() : p[axis] >= section_plane();
}

// Signed distance of `position` (cells) from the plane, positive on the kept side (1 without a section).
float section_distance(vec3 position) {
  int axis = section_axis();
  if (axis < 0) return 1.0;
  float offset = position[axis] - float(section_plane());
  return section_keeps_high() ? offset : -offset;
}

// How a material is drawn in this frame: its look, or kLookXray for a static one under x-ray.
uint seen_look(uint material) {
  return (xray_on() && materials[material & 7u].look.y != 0u) ? kLookXray : look_of(material);
}

// How much a surface of seen look `look` covers what lies behind it.
float seen_alpha(uint look) { return look == kLookXray ? kXrayAlpha : surface_alpha(look); }

// face_shows (materials.glsl) as this frame sees the materials: under x-ray a face of a drawn
// material towards a static one shows too, since the static one no longer hides it.
bool seen_face_shows(uint material, uint neighbour) {
  uint look = seen_look(material);
  return face_shows(material, neighbour) || (seen_look(neighbour) == kLookXray && look != kLookXray && look != kLookVoid);
}

// Whether this draw (its pass) shows surfaces of seen look `look`.
bool drawn_in_pass(uint look) {
  uint pass = draw_pass();
  if (pass == kPassOpaque) return look == kLookOpaque;
  if (pass == kPassTranslucent) return look == kLookLiquid || look == kLookGas;
  return look == kLookXray;
}

#ifdef CELLS_GLSL
// Material of cell p as the frame shows it: void where the section removed it.
uint visible_cell_at(ivec3 p) { return section_removes(p) ? 0u : cell_at(p); }
#endif
