// Cell reading shared by the viewer's shaders. The including shader declares
//   layout(...) buffer Cells { uint8_t cells[]; };
// before including this file, and includes view.glsl.
#define CELLS_GLSL

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
