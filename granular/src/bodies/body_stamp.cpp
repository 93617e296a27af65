#include "bodies/body_stamp.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "bodies/body_forces.hpp"
#include "bodies/body_shape.hpp"
#include "granular/grid.hpp"
#include "granular/motion.hpp"
#include "world/region_edit.hpp"

namespace granular {

namespace {

/// The six neighbours in the order ties are broken for one cell: `lead` (the body's motion, or
/// none), up, the four sideways ones from the `turn`-th (0..3) of +x, +y, -x, -y on (drawn per cell,
/// so that no side is favoured), then down.
std::array<Int3, 6> directions(Int3 lead, unsigned turn) {
  constexpr std::array<Int3, 4> kSideways{Int3{1, 0, 0}, Int3{0, 1, 0}, Int3{-1, 0, 0}, Int3{0, -1, 0}};
  std::array<Int3, 6> dirs{};
  std::size_t n = 0;
  auto add = [&](Int3 d) {
    if (!(d == lead)) dirs[n++] = d;
  };
  if (!(lead == Int3{})) dirs[n++] = lead;
  add({0, 0, 1});
  for (unsigned k = 0; k < 4; ++k) add(kSideways[(turn + k) % 4]);
  add({0, 0, -1});
  return dirs;
}

/// The axis direction `motion` (cells) mostly points along; none for no motion.
Int3 lead_of(const Vec3& motion) {
  const double ax = std::abs(motion.x), ay = std::abs(motion.y), az = std::abs(motion.z);
  if (ax == 0 && ay == 0 && az == 0) return {};
  if (ax >= ay && ax >= az) return {motion.x > 0 ? 1 : -1, 0, 0};
  if (ay >= az) return {0, motion.y > 0 ? 1 : -1, 0};
  return {0, 0, motion.z > 0 ? 1 : -1};
}

/// A cell no search has reached.
constexpr std::uint32_t kUnseen = 0xFFFFFFFFu;

/// A body's region: local indices (x fastest) of its cells.
struct Region {
  Box box;
  Int3 e;
  explicit Region(const Box& b) : box(b), e(b.extent()) {}
  std::uint32_t local(Int3 c) const {
    return std::uint32_t((std::size_t(c.z - box.min.z) * std::size_t(e.y) + std::size_t(c.y - box.min.y)) *
                             std::size_t(e.x) +
                         std::size_t(c.x - box.min.x));
  }
  Int3 cell(std::uint32_t i) const {
    const std::uint32_t row = i / std::uint32_t(e.x);
    return {box.min.x + int(i % std::uint32_t(e.x)), box.min.y + int(row % std::uint32_t(e.y)),
            box.min.z + int(row / std::uint32_t(e.y))};
  }
  bool inside(Int3 c) const {
    return c.x >= box.min.x && c.y >= box.min.y && c.z >= box.min.z && c.x < box.max.x && c.y < box.max.y &&
           c.z < box.max.z;
  }
  std::size_t volume() const { return std::size_t(e.x) * std::size_t(e.y) * std::size_t(e.z); }
};

}  // namespace

StampResult stamp_body(RegionEdit& edit, Int3 grid, const std::vector<std::uint64_t>& shape,
                       std::vector<std::uint64_t>& owned, std::uint8_t body_material, const MaterialTable& materials,
                       const Vec3& motion, std::uint64_t salt, StampScratch& s) {
  StampResult result;
  const Region region(edit.region());
  auto put = [&](std::uint32_t i, std::uint8_t byte) {
    const Int3 c = region.cell(i);
    edit.put(i, edit.row(c.y, c.z).flag(c.x), byte);
  };
  auto material = [&](std::uint32_t i) { return std::uint8_t(edit.byte(i) & kMaterialMask); };
  auto mobile = [&](std::uint8_t m) {
    const Behaviour b = materials[m].behaviour;
    return b == Behaviour::Granular || b == Behaviour::Liquid || b == Behaviour::Gas;
  };

  // Per cell of the region: 0 outside the shape, kShape inside it, kTaken once the body holds it,
  // kNear outside it but within kRingWidth cells beside a cell of it in the same layer (the
  // surroundings its buoyancy reads, sand_forces).
  constexpr std::uint8_t kShape = 1, kTaken = 2, kNear = 3;
  s.in_shape.assign(region.volume(), 0);
  for (const std::uint64_t g : shape) s.in_shape[region.local(grid_cell(grid, g))] = kShape;
  auto in_shape_at = [&](Int3 c) { return region.inside(c) && s.in_shape[region.local(c)] != 0 && s.in_shape[region.local(c)] != kNear; };
  for (const std::uint64_t g : shape) {
    const Int3 c = grid_cell(grid, g);
    if (in_shape_at({c.x + 1, c.y, c.z}) && in_shape_at({c.x - 1, c.y, c.z}) && in_shape_at({c.x, c.y + 1, c.z}) &&
        in_shape_at({c.x, c.y - 1, c.z}))
      continue;  // inside its layer
    for (int dy = -kRingWidth; dy <= kRingWidth; ++dy)
      for (int dx = -kRingWidth; dx <= kRingWidth; ++dx) {
        const Int3 n{c.x + dx, c.y + dy, c.z};
        if (region.inside(n) && s.in_shape[region.local(n)] == 0) s.in_shape[region.local(n)] = kNear;
      }
  }
  auto outside = [&](std::uint32_t i) { return s.in_shape[i] == 0 || s.in_shape[i] == kNear; };

  // The cells the body left.
  s.left.clear();
  for (const std::uint64_t g : owned) {
    const std::uint32_t i = region.local(grid_cell(grid, g));
    if (outside(i) && material(i) == body_material) {
      put(i, 0);
      s.left.push_back(i);
    }
  }

  // The cells it keeps or takes at once; those holding something mobile wait for a push.
  s.taken.clear();
  s.push.clear();
  auto was_owned = owned.begin();
  for (const std::uint64_t g : shape) {
    while (was_owned != owned.end() && *was_owned < g) ++was_owned;
    const bool kept = was_owned != owned.end() && *was_owned == g;
    const std::uint32_t i = region.local(grid_cell(grid, g));
    const std::uint8_t m = material(i);
    if (m == body_material && kept) {
      s.in_shape[i] = kTaken;
      s.taken.push_back(g);
    } else if (m == to_cell(Material::Void)) {
      put(i, body_material);
      s.in_shape[i] = kTaken;
      s.taken.push_back(g);
    } else if (mobile(m)) {
      s.push.push_back(g);
    } else {
      ++result.blocked;
    }
  }

  // The breadth-first search both the pushes and the wake's fill make: from `from`, through cells
  // `through` lets pass, trying neighbours in `order`, to the nearest cell `target` calls kFar (away
  // from the body's surroundings), else the nearest it calls kNearby, or with `nearby_will_do` the
  // nearest of either; s.parent then leads back from the cell found to `from`. Returns the cell, or -1
  // for none within the region. A search that finds none marks the cells it reached `s.dead`: targets
  // are only used up while the body is written, so a later search from one of them finds none either.
  enum Target { kNot, kNearby, kFar };
  s.parent.assign(region.volume(), kUnseen);
  s.dead.assign(region.volume(), 0);
  s.queue.clear();
  auto nearest = [&](std::uint32_t from, const std::array<Int3, 6>& order, bool nearby_will_do, auto&& through,
                     auto&& target) -> std::int64_t {
    for (const std::uint32_t i : s.queue) s.parent[i] = kUnseen;  // the last search's marks
    s.queue.assign(1, from);
    s.parent[from] = from;
    if (s.dead[from]) return -1;
    std::int64_t nearby = -1;
    for (std::size_t head = 0; head < s.queue.size(); ++head) {
      const Int3 c = region.cell(s.queue[head]);
      for (const Int3& d : order) {
        const Int3 n{c.x + d.x, c.y + d.y, c.z + d.z};
        if (!region.inside(n)) continue;
        const std::uint32_t j = region.local(n);
        if (s.parent[j] != kUnseen || !through(j)) continue;
        s.parent[j] = s.queue[head];
        s.queue.push_back(j);
        const Target t = target(j, n);
        if (t == kFar || (t == kNearby && nearby_will_do)) return j;
        if (t == kNearby && nearby < 0) nearby = j;
      }
    }
    if (nearby < 0)
      for (const std::uint32_t i : s.queue) s.dead[i] = 1;
    return nearby;
  };
  // Shifts the path s.parent gives from `end` back to `from` by one cell towards `end`: each cell
  // takes the material of the one before it on the path, `from` takes `first`, at rest.
  auto shift = [&](std::uint32_t from, std::uint32_t end, std::uint8_t first) {
    for (std::uint32_t at = end; at != from; at = s.parent[at]) put(at, material(s.parent[at]));
    put(from, first);
  };
  // Shifts that path by one cell towards `from` instead: each cell takes the material of the one
  // after it, `end` becomes void.
  auto pull = [&](std::uint32_t from, std::uint32_t end) {
    std::uint8_t carried = 0;
    for (std::uint32_t at = end;; at = s.parent[at]) {
      const std::uint8_t here = material(at);
      put(at, carried);
      carried = here;
      if (at == from) break;
    }
  };

  if (!s.push.empty()) {
    const Int3 lead = lead_of(motion);
    // The front of the body first: the cells farthest along its motion.
    auto ahead = [&](std::uint64_t g) {
      const Int3 c = grid_cell(grid, g);
      return c.x * motion.x + c.y * motion.y + c.z * motion.z;
    };
    std::stable_sort(s.push.begin(), s.push.end(), [&](std::uint64_t a, std::uint64_t b) { return ahead(a) > ahead(b); });
    // A push passes through mobile cells and voids, crossing cells of the shape that wait for their
    // own push (it moves what they hold on by one cell), and ends in a void outside the shape: away
    // from the body's surroundings where there is one within reach (so that its buoyancy does not
    // jump with what it pushed), else in them.
    auto through = [&](std::uint32_t i) { return s.in_shape[i] != kTaken && (material(i) == 0 || mobile(material(i))); };
    auto to_void = [&](std::uint32_t i, Int3) {
      if (material(i) != 0 || !outside(i)) return kNot;
      return s.in_shape[i] == 0 ? kFar : kNearby;
    };
    bool nearby_will_do = false;  // set once a search found no void away from the surroundings
    for (const std::uint64_t g : s.push) {
      const std::uint32_t start = region.local(grid_cell(grid, g));
      const Int3 c = grid_cell(grid, g);
      const std::int64_t end = nearest(start, directions(lead, unsigned(mix64(salt ^ grid_index(grid, c.x, c.y, c.z)) & 3)),
                                       nearby_will_do, through, to_void);
      if (end < 0 || s.in_shape[std::uint32_t(end)] == kNear) nearby_will_do = true;
      if (end < 0) {  // no void within reach
        ++result.blocked;
        continue;
      }
      ++result.displaced[material(start)];
      shift(start, std::uint32_t(end), body_material);
      s.in_shape[start] = kTaken;
      s.taken.push_back(g);
    }
    std::sort(s.taken.begin(), s.taken.end());
  }

  // The wake: each cell the body left that holds no liquid is filled from the nearest surface of
  // liquid higher than it (liquid outside the shape with void or gas over it, away from the body's
  // surroundings where there is one), lowest cell first; the path runs through liquid outside the
  // shape, each cell moving one cell towards the wake, so the surface drops where the fill came from.
  // Grains are left to topple into the wake by the rules: a furrow stays open as far as sand stands.
  if (!s.left.empty()) {
    std::sort(s.left.begin(), s.left.end());  // local indices: z, then y, then x
    auto liquid = [&](std::uint32_t i) { return outside(i) && materials[material(i)].behaviour == Behaviour::Liquid; };
    auto open_above = [&](Int3 c) {
      const Int3 up{c.x, c.y, c.z + 1};
      if (!region.inside(up)) return false;
      const std::uint32_t j = region.local(up);
      return outside(j) && (material(j) == 0 || materials[material(j)].behaviour == Behaviour::Gas);
    };
    std::fill(s.dead.begin(), s.dead.end(), std::uint8_t(0));
    bool nearby_will_do = false;
    for (const std::uint32_t wake : s.left) {
      if (material(wake) != 0) continue;
      const Int3 at = region.cell(wake);
      auto surface = [&](std::uint32_t j, Int3 n) {
        if (n.z <= at.z || !open_above(n)) return kNot;
        return s.in_shape[j] == 0 ? kFar : kNearby;
      };
      const std::int64_t found = nearest(wake, directions({}, unsigned(mix64(salt ^ ~grid_index(grid, at.x, at.y, at.z)) & 3)),
                                         nearby_will_do, liquid, surface);
      if (found < 0 || s.in_shape[std::uint32_t(found)] == kNear) nearby_will_do = true;
      if (found < 0) continue;
      ++result.filled[material(std::uint32_t(found))];
      pull(wake, std::uint32_t(found));
    }
  }
  owned.swap(s.taken);
  return result;
}

}  // namespace granular
