#version 460
// Compacts a brick renderer's indirect draw commands to the bricks that draw something, in brick
// order, so the draw pass issues one command per such brick instead of one per brick of the grid
// (most bricks are empty or hidden air, and an empty command still costs the GPU's command
// processor). The commands are two lists of pc.bricks.w commands each (opaque, then translucent);
// workgroup g covers 256 commands of list g / G (G workgroups a list). Pass pc.grid.w == 0 counts
// each workgroup's drawing commands; pass 1 writes them at their place in the compacted lists (the
// sum of the workgroups before it in the list, then the exclusive scan within the workgroup), and
// the last workgroup of a list writes the list's count for vkCmdDrawIndirectCount.
layout(local_size_x = 256) in;
#include "view.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Draws { uvec4 draws[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Compact { uvec4 compact[]; };
layout(std430, set = 0, binding = 2) buffer GroupCounts { uint group_counts[]; };
layout(std430, set = 0, binding = 3) writeonly buffer DrawCounts { uint draw_counts[]; };

shared uint scan[256];
shared uint partial[256];

void main() {
  const uint bricks = uint(pc.bricks.w);
  const uint groups = (bricks + 255u) / 256u;
  const uint list = gl_WorkGroupID.x / groups, group = gl_WorkGroupID.x % groups;
  const uint local = gl_LocalInvocationIndex;
  const uint index = group * 256u + local;
  const uint command = list * bricks + index;
  const bool draws_something = index < bricks && draws[command].x > 0u && draws[command].y > 0u;
  scan[local] = draws_something ? 1u : 0u;
  barrier();
  // Inclusive scan of the flags (Hillis-Steele).
  for (uint step = 1u; step < 256u; step <<= 1u) {
    uint add = local >= step ? scan[local - step] : 0u;
    barrier();
    scan[local] += add;
    barrier();
  }
  if (pc.grid.w == 0) {
    if (local == 255u) group_counts[gl_WorkGroupID.x] = scan[255];
    return;
  }
  // The drawing commands of the list's workgroups before this one.
  uint before = 0u;
  for (uint g = local; g < group; g += 256u) before += group_counts[list * groups + g];
  partial[local] = before;
  barrier();
  for (uint half_size = 128u; half_size > 0u; half_size >>= 1u) {
    if (local < half_size) partial[local] += partial[local + half_size];
    barrier();
  }
  const uint offset = partial[0];
  if (draws_something) compact[list * bricks + offset + scan[local] - 1u] = draws[command];
  if (group == groups - 1u && local == 255u) draw_counts[list] = offset + scan[255];
}
