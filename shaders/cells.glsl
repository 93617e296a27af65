// Cell reading shared by the viewer's shaders. The including shader declares
//   layout(...) buffer Cells { uint8_t cells[]; };
// before including this file, and includes view.glsl.

const int kBrickSize = 16;
const uint kBrickCells = 4096u;

bool inside_grid(ivec3 p) { return all(greaterThanEqual(p, ivec3(0))) && all(lessThan(p, pc.grid.xyz)); }

uint cell_index(ivec3 p) { return uint(p.x) + uint(pc.grid.x) * (uint(p.y) + uint(pc.grid.y) * uint(p.z)); }

// Material of a cell byte: its low 3 bits (a grain keeps its motion state above them).
uint material_of(uint8_t cell) { return uint(cell) & 7u; }

// Material of cell p; cells outside the grid read as void.
uint cell_at(ivec3 p) { return inside_grid(p) ? material_of(cells[cell_index(p)]) : 0u; }

ivec3 brick_origin(uint brick) {
  uint bx = uint(pc.bricks.x), by = uint(pc.bricks.y);
  return ivec3(int(brick % bx), int((brick / bx) % by), int(brick / (bx * by))) * kBrickSize;
}

// Base colour of a material; sand and stone get a per-cell brightness jitter.
vec3 material_color(uint material, ivec3 p) {
  vec3 base;
  switch (material) {
    case 1u: base = vec3(0.46, 0.47, 0.50); break;  // solid: stone
    case 2u: base = vec3(0.87, 0.72, 0.46); break;  // granular: sand
    case 3u: base = vec3(0.25, 0.45, 0.85); break;  // liquid
    case 4u: base = vec3(0.80, 0.85, 0.90); break;  // gas
    case 5u: base = vec3(0.62, 0.30, 0.28); break;
    case 6u: base = vec3(0.32, 0.58, 0.30); break;
    default: base = vec3(0.50, 0.32, 0.60); break;
  }
  uint h = uint(p.x) * 73856093u ^ uint(p.y) * 19349663u ^ uint(p.z) * 83492791u;
  h = (h ^ (h >> 13)) * 1274126177u;
  float jitter = float(h & 255u) / 255.0;
  return base * (0.90 + 0.16 * jitter);
}

// Sun and sky lighting shared by the raster and ray-march renderers.
vec3 shade(vec3 albedo, vec3 normal, float occlusion) {
  const vec3 sun = normalize(vec3(0.45, 0.30, 0.84));
  float diffuse = max(dot(normal, sun), 0.0);
  float sky = 0.5 + 0.5 * normal.z;
  return albedo * (0.72 * diffuse + 0.38 * sky) * occlusion;
}
