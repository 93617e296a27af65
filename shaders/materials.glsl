// The world's material table as the viewer's shaders read it (viewer/src/material_palette.hpp
// fills the buffer): for each cell state, its display colour (MaterialDef::colour) and its look,
// how the renderers draw it. The including shader defines MATERIALS_BINDING, the buffer's binding
// in set 0, before including this file.

const uint kLookVoid = 0u;    // nothing is drawn
const uint kLookOpaque = 1u;  // static and granular materials: opaque, a per-cell brightness jitter
const uint kLookLiquid = 2u;  // liquids: translucent, smooth, a sun glint
const uint kLookGas = 3u;     // gases: faint, smooth

struct MaterialEntry {
  vec4 colour;  // rgb: the display colour (0..1 per channel); a: unused
  uvec4 look;   // x: the look (kLook*); y: 1 for a static material (x-ray draws it translucent); zw: unused
};

layout(std140, set = 0, binding = MATERIALS_BINDING) uniform Materials { MaterialEntry materials[8]; };

uint look_of(uint material) { return materials[material & 7u].look.x; }

// Drawing order of the looks: void 0, gas 1, liquid 2, opaque 3.
uint see_through_rank(uint look) { return look == kLookOpaque ? 3u : (look == kLookLiquid ? 2u : (look == kLookGas ? 1u : 0u)); }

bool is_translucent(uint look) { return look == kLookLiquid || look == kLookGas; }

// Whether the face between a cell of `material` and a neighbour of `neighbour` shows: where the
// neighbour has a lower rank (so the ground under water or gas is drawn and seen through it), or
// both are translucent and differ (a gas bubble in water, oil on water).
bool face_shows(uint material, uint neighbour) {
  uint look = look_of(material), other = look_of(neighbour);
  return see_through_rank(other) < see_through_rank(look) ||
         (is_translucent(look) && is_translucent(other) && neighbour != material);
}

// How much a translucent surface covers what lies behind it (the raster renderers draw one layer).
float surface_alpha(uint look) { return look == kLookLiquid ? 0.55 : (look == kLookGas ? 0.28 : 1.0); }

// Per-cell brightness in [0.90, 1.06] of opaque materials, so a flat heap shows its grains.
float cell_jitter(ivec3 p) {
  uint h = uint(p.x) * 73856093u ^ uint(p.y) * 19349663u ^ uint(p.z) * 83492791u;
  h = (h ^ (h >> 13)) * 1274126177u;
  return 0.90 + 0.16 * (float(h & 255u) / 255.0);
}

// Base colour of cell p holding `material`: the table's colour, jittered per cell where opaque.
vec3 material_color(uint material, ivec3 p) {
  vec3 base = materials[material & 7u].colour.rgb;
  return look_of(material) == kLookOpaque ? base * cell_jitter(p) : base;
}
