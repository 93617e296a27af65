#version 460
// Instanced cubes, build pass: for each brick of the list, writes the brick's instances into its
// slot (4096 instances): opaque ones from the slot's start, translucent ones (liquid, gas) from its
// end, and then its two indirect draw commands: draws[brick] for the opaque instances,
// draws[bricks in the grid + brick] for the translucent ones.
//
// A non-void cell's face shows (materials.glsl's face_shows: towards void, a translucent neighbour
// in front of a denser look, or another translucent material; under x-ray also towards a static
// material: see_inside.glsl's seen_face_shows). A showing face is *open* when none of the eight
// cells around the cell in front of it shades its corners (cube.vert's ambient occlusion: a cell of
// the face's own see-through rank or above). The brick is drawn one of two ways:
// - quads (6 vertices an instance): in each slice of the brick across a face direction, along
//   each row on the face's run axis (x, or y for the x faces: horizontal, so the sides of thin
//   horizontal layers merge as well as their tops), consecutive open faces of one material merge
//   into a run, and a run grows across the rows after it while they hold the same run (a
//   rectangle); a face that is not open is a quad of its own. Instance: bits 0-11 the quad's first
//   cell in the brick, 12-14 material, 15-17 face (axis * 2 + 1 for the positive side), 18-21
//   length along the run axis - 1, 22 open, 23-26 rows across - 1, 31 set.
// - cells (18 vertices an instance, the three faces that can face the camera), when the brick has
//   more quads than its slot holds (a brick of scattered cells). Instance: bits 0-11 cell in brick,
//   12-14 material, 16-21 showing faces, 31 clear.
#extension GL_EXT_shader_8bit_storage : require
#extension GL_EXT_shader_explicit_arithmetic_types_int8 : require
layout(local_size_x = 256) in;
#include "view.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Cells { uint8_t cells[]; };
layout(std430, set = 0, binding = 1) readonly buffer BrickList { uint brick_list[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Instances { uint instances[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Draws { uint draws[]; };
#define MATERIALS_BINDING 4
#include "cells.glsl"
#include "materials.glsl"
#include "see_inside.glsl"

const uint kQuadInstance = 0x80000000u;

const int kTile = 18;  // cells -1..16 around the brick
const uint kTileCells = uint(kTile * kTile * kTile);

// The materials of the brick's cells and a border of one, 4 cells a word.
shared uint tile[(kTileCells + 3u) / 4u];
// Per cell of the brick, 2 cells a word: bits 0-5 showing faces, 6-8 material, 9-14 open faces.
shared uint cell_faces[kBrickCells / 2u];
// Per material m, bit n: a face of m towards n shows (seen_face_shows); n shades m's faces (its
// seen look's see-through rank is at least m's).
shared uint shows_towards_material[8];
shared uint shaded_by_material[8];
shared uint opaque_count;
shared uint translucent_count;
shared uint quad_count;  // the brick's quads, counted when its faces outnumber the slot
shared uint face_count;       // showing faces of the brick: an upper bound of its quads
shared uint face_directions;  // bit f: some cell of the brick shows face f

// The material of the cell at `local` (-1..16 on each axis) from the tile.
uint tile_material(ivec3 local) {
  uint i = uint((local.x + 1) + kTile * ((local.y + 1) + kTile * (local.z + 1)));
  return (tile[i >> 2u] >> ((i & 3u) * 8u)) & 7u;
}

uint face_info(uint cell) { return (cell_faces[cell >> 1u] >> ((cell & 1u) * 16u)) & 0xFFFFu; }

bool shows_towards(uint material, ivec3 neighbour) { return ((shows_towards_material[material] >> tile_material(neighbour)) & 1u) != 0u; }

// True when no cell around the cell in front of face `face` of `local` (the eight of the face's
// plane) shades a face of `material`: all four corners of the face are unshaded.
bool face_open(ivec3 local, uint face, uint material) {
  uint shaded = shaded_by_material[material];
  int axis = int(face >> 1u);
  int u = (axis + 1) % 3, v = (axis + 2) % 3;
  ivec3 front = local;
  front[axis] += (face & 1u) != 0u ? 1 : -1;
  for (int a = -1; a <= 1; ++a)
    for (int b = -1; b <= 1; ++b) {
      if (a == 0 && b == 0) continue;
      ivec3 q = front;
      q[u] += a;
      q[v] += b;
      if (((shaded >> tile_material(q)) & 1u) != 0u) return false;
    }
  return true;
}

// The faces of the cell at `local` in the brick: bits 0-5 showing faces, 6-8 material, 9-14 open
// faces; 0 for void or a cell with no face showing.
uint cell_face_info(ivec3 local) {
  uint material = tile_material(local);
  if (look_of(material) == kLookVoid) return 0u;
  uint faces = (shows_towards(material, local + ivec3(-1, 0, 0)) ? 1u : 0u) | (shows_towards(material, local + ivec3(1, 0, 0)) ? 2u : 0u) |
               (shows_towards(material, local + ivec3(0, -1, 0)) ? 4u : 0u) | (shows_towards(material, local + ivec3(0, 1, 0)) ? 8u : 0u) |
               (shows_towards(material, local + ivec3(0, 0, -1)) ? 16u : 0u) | (shows_towards(material, local + ivec3(0, 0, 1)) ? 32u : 0u);
  if (faces == 0u) return 0u;
  uint open = 0u;
  for (uint face = 0u; face < 6u; ++face)
    if ((faces & (1u << face)) != 0u && face_open(local, face, material)) open |= 1u << face;
  return faces | (material << 6u) | (open << 9u);
}

// The axis a face of axis `axis` runs along (cube.vert has the same).
int run_axis(int axis) { return axis == 0 ? 1 : 0; }

// The cell in brick of step k along row `row` of face `face`'s runs: the row's position on the
// face's axis is row & 15, on its other in-plane axis row >> 4, and k runs along its run axis.
uint row_cell(uint face, uint row, uint k) {
  int axis = int(face >> 1u);
  int along = run_axis(axis);
  ivec3 l = ivec3(0);
  l[axis] = int(row & 15u);
  l[3 - axis - along] = int(row >> 4u);
  l[along] = int(k);
  return uint(l.x) | (uint(l.y) << 4u) | (uint(l.z) << 8u);
}

// The slot in the brick for an instance of `material`'s next instance.
uint take_slot(uint material) {
  return is_translucent(look_of(material)) ? kBrickCells - 1u - atomicAdd(translucent_count, 1u)
                                           : atomicAdd(opaque_count, 1u);
}

// Writes the instance of a quad of face `face`: `run_length` cells from cell `first` along the run
// axis, `rows` rows across.
void write_quad(uint brick, uint first, uint material, uint face, uint run_length, uint rows, bool open) {
  instances[brick * kBrickCells + take_slot(material)] = first | (material << 12u) | (face << 15u) | ((run_length - 1u) << 18u) |
                                                        (open ? 1u << 22u : 0u) | ((rows - 1u) << 23u) | kQuadInstance;
}

// Whether the cell at step k of row `row` of face `face`'s rows shows that face, open, in `material`.
bool open_face_of(uint face, uint row, uint k, uint material) {
  uint info = face_info(row_cell(face, row, k));
  return (info & (1u << face)) != 0u && (info & (1u << (9u + face))) != 0u && ((info >> 6u) & 7u) == material;
}

// Whether row `row` of face `face`'s rows holds the open run of `material` over steps
// k..k + run_length - 1: those faces open in that material, and the steps on either side not.
bool holds_run(uint face, uint row, uint k, uint run_length, uint material) {
  if (k > 0u && open_face_of(face, row, k - 1u, material)) return false;
  if (k + run_length < 16u && open_face_of(face, row, k + run_length, material)) return false;
  for (uint i = 0u; i < run_length; ++i)
    if (!open_face_of(face, row, k + i, material)) return false;
  return true;
}

// Walks the quads of face `face` that start in row `row` (bits 0-3 its position on the face's
// axis, 4-7 across): along the run axis, consecutive open faces of one material merge into a run,
// and a run that the row before does not hold grows across the rows after that hold it (a
// rectangle; a run the row before holds belongs to that row's quad); a face that is not open is a
// quad of its own. Writes each quad when `write`; returns their number.
uint walk_row(uint brick, uint face, uint row, bool write) {
  const uint shows = 1u << face, open = 1u << (9u + face);
  const uint slice = row & 15u, w = row >> 4u;
  uint quads = 0u;
  uint k = 0u;
  while (k < 16u) {
    uint first = row_cell(face, row, k);
    uint info = face_info(first);
    if ((info & shows) == 0u) {
      ++k;
      continue;
    }
    uint material = (info >> 6u) & 7u;
    bool is_open = (info & open) != 0u;
    uint run_length = 1u;
    if (is_open)
      while (k + run_length < 16u && open_face_of(face, row, k + run_length, material)) ++run_length;
    if (!is_open || w == 0u || !holds_run(face, slice | ((w - 1u) << 4u), k, run_length, material)) {
      uint rows = 1u;
      if (is_open)
        while (w + rows < 16u && holds_run(face, slice | ((w + rows) << 4u), k, run_length, material)) ++rows;
      if (write) write_quad(brick, first, material, face, run_length, rows, is_open);
      ++quads;
    }
    k += run_length;
  }
  return quads;
}

void main() {
  uint brick = brick_list[gl_WorkGroupID.x];
  if (gl_LocalInvocationIndex == 0u) {
    opaque_count = 0u;
    translucent_count = 0u;
    quad_count = 0u;
    face_count = 0u;
    face_directions = 0u;
  }
  if (gl_LocalInvocationIndex < 8u) {
    uint m = gl_LocalInvocationIndex, rank = see_through_rank(look_of(m));
    uint shows = 0u, shaded = 0u;
    for (uint n = 0u; n < 8u; ++n) {
      if (seen_face_shows(m, n)) shows |= 1u << n;
      if (see_through_rank(seen_look(n)) >= rank) shaded |= 1u << n;
    }
    shows_towards_material[m] = shows;
    shaded_by_material[m] = shaded;
  }
  ivec3 origin = brick_origin(brick);
  for (uint w = gl_LocalInvocationIndex; w < (kTileCells + 3u) / 4u; w += 256u) {
    uint word = 0u;
    for (uint b = 0u; b < 4u; ++b) {
      uint i = w * 4u + b;
      if (i >= kTileCells) break;
      ivec3 t = ivec3(int(i % uint(kTile)), int((i / uint(kTile)) % uint(kTile)), int(i / uint(kTile * kTile)));
      word |= cell_at(origin + t - 1) << (b * 8u);
    }
    tile[w] = word;
  }
  barrier();
  uint faces = 0u, directions = 0u;
  for (uint pair = gl_LocalInvocationIndex; pair < kBrickCells / 2u; pair += 256u) {
    uint i = pair * 2u;
    ivec3 local = ivec3(int(i & 15u), int((i >> 4) & 15u), int(i >> 8));
    uint first = cell_face_info(local), second = cell_face_info(local + ivec3(1, 0, 0));
    cell_faces[pair] = first | (second << 16u);
    faces += bitCount(first & 63u) + bitCount(second & 63u);
    directions |= (first | second) & 63u;
  }
  atomicAdd(face_count, faces);
  atomicOr(face_directions, directions);
  barrier();
  // The quads of the directions shown, 256 rows each. With more faces than the slot holds, count
  // the quads first: written only if the slot holds them all.
  bool as_quads = face_count <= kBrickCells;
  if (!as_quads) {
    uint quads = 0u;
    for (uint task = gl_LocalInvocationIndex; task < 6u * 256u; task += 256u)
      if ((face_directions & (1u << (task >> 8u))) != 0u) quads += walk_row(brick, task >> 8u, task & 255u, false);
    atomicAdd(quad_count, quads);
    barrier();
    as_quads = quad_count <= kBrickCells;
  }
  if (as_quads) {
    for (uint task = gl_LocalInvocationIndex; task < 6u * 256u; task += 256u)
      if ((face_directions & (1u << (task >> 8u))) != 0u) walk_row(brick, task >> 8u, task & 255u, true);
  } else {
    for (uint i = gl_LocalInvocationIndex; i < kBrickCells; i += 256u) {
      uint info = face_info(i);
      if (info == 0u) continue;
      uint material = (info >> 6u) & 7u;
      instances[brick * kBrickCells + take_slot(material)] = i | (material << 12u) | ((info & 63u) << 16u);
    }
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    uint grid_bricks = uint(pc.bricks.x * pc.bricks.y * pc.bricks.z);
    uint opaque = brick * 4u, translucent = (grid_bricks + brick) * 4u;
    uint vertices = as_quads ? 6u : 18u;  // cube.vert: one quad an instance; three camera-facing faces a cell
    draws[opaque + 0u] = vertices;
    draws[opaque + 1u] = opaque_count;
    draws[opaque + 2u] = 0u;
    draws[opaque + 3u] = brick * kBrickCells;
    draws[translucent + 0u] = vertices;
    draws[translucent + 1u] = translucent_count;
    draws[translucent + 2u] = 0u;
    draws[translucent + 3u] = brick * kBrickCells + kBrickCells - translucent_count;
  }
}
