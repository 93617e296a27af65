#version 460
// Compacts a brick renderer's indirect draw commands to the bricks that draw something, so the
// draw pass issues one command per such brick instead of one per brick of the grid (most bricks are
// empty or hidden air, and an empty command still costs the GPU's command processor), in an order
// taken from the eye: the opaque list front to back, so the depth test rejects what nearer bricks
// already cover before it is shaded; the translucent list back to front, so blending composes in
// depth order. The commands are two lists of pc.bricks.w commands each (opaque, then translucent),
// each command pc.grid.x words (4: VkDrawIndirectCommand, 5: VkDrawIndexedIndirectCommand; both
// start with the count of vertices or indices, then of instances), pc.bricks.xyz bricks per axis,
// pc.eye the eye in cells. Workgroup g covers 256 ranks of list
// g / G (G workgroups a list). Pass pc.grid.w == 0 counts each workgroup's drawing commands; pass 1
// writes them at their place in the compacted lists (the sum of the workgroups before it in the
// list, then the exclusive scan within the workgroup), and the last workgroup of a list writes the
// list's count for vkCmdDrawIndirectCount.
//
// The order: on each axis the bricks go by their distance (in bricks) from the eye's brick, and a
// brick's rank is lexicographic in those distances (z, then y, then x). A brick that covers part of
// another from the eye lies between them, so on every axis it is no farther from the eye's brick,
// and it ranks first.
layout(local_size_x = 256) in;
#include "view.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Draws { uint draws[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Compact { uint compact[]; };
layout(std430, set = 0, binding = 2) buffer GroupCounts { uint group_counts[]; };
layout(std430, set = 0, binding = 3) writeonly buffer DrawCounts { uint draw_counts[]; };

shared uint scan[256];
shared uint partial[256];

/// The index on an axis of n bricks of the k-th brick by distance from brick e (e may lie outside
/// 0..n-1, the eye being outside the grid): e, then alternately below and above it, then the rest of
/// the longer side.
int nearest_first(int k, int e, int n) {
  if (e < 0) return k;
  if (e >= n) return n - 1 - k;
  const int both = min(e, n - 1 - e);
  if (k <= 2 * both) return (k & 1) == 1 ? e - (k + 1) / 2 : e + k / 2;
  const int beyond = k - both;
  return e > n - 1 - e ? e - beyond : e + beyond;
}

/// The brick of rank `rank` front to back from the eye.
uint brick_of_rank(uint rank) {
  const ivec3 n = pc.bricks.xyz;
  const ivec3 e = clamp(ivec3(floor(pc.eye.xyz / float(kBrickSize))), ivec3(-1), n);
  const int r = int(rank);
  const int x = nearest_first(r % n.x, e.x, n.x);
  const int y = nearest_first((r / n.x) % n.y, e.y, n.y);
  const int z = nearest_first(r / (n.x * n.y), e.z, n.z);
  return uint(x + n.x * (y + n.y * z));
}

void main() {
  const uint bricks = uint(pc.bricks.w);
  const uint groups = (bricks + 255u) / 256u;
  const uint list = gl_WorkGroupID.x / groups, group = gl_WorkGroupID.x % groups;
  const uint local = gl_LocalInvocationIndex;
  const uint rank = group * 256u + local;
  // The translucent list is the opaque order reversed.
  const uint brick = rank < bricks ? brick_of_rank(list == 0u ? rank : bricks - 1u - rank) : 0u;
  const uint words = uint(pc.grid.x);
  const uint command = (list * bricks + brick) * words;
  const bool draws_something = rank < bricks && draws[command] > 0u && draws[command + 1u] > 0u;
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
  if (draws_something) {
    const uint at = (list * bricks + offset + scan[local] - 1u) * words;
    for (uint w = 0u; w < words; ++w) compact[at + w] = draws[command + w];
  }
  if (group == groups - 1u && local == 255u) draw_counts[list] = offset + scan[255];
}
