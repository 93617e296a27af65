#include "bodies/body_stamp.hpp"

#include <algorithm>
#include <array>
#include <cmath>

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

  // Per cell of the region: 0 outside the shape, kShape inside it, kTaken once the body holds it.
  constexpr std::uint8_t kShape = 1, kTaken = 2;
  s.in_shape.assign(region.volume(), 0);
  for (const std::uint64_t g : shape) s.in_shape[region.local(grid_cell(grid, g))] = kShape;

  // The cells the body left.
  s.left.clear();
  for (const std::uint64_t g : owned) {
    const std::uint32_t i = region.local(grid_cell(grid, g));
    if (!s.in_shape[i] && material(i) == body_material) {
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

  if (!s.push.empty()) {
    const Int3 lead = lead_of(motion);
    const std::array<Int3, 6> search_order = directions({}, 0);
    // The front of the body first: the cells farthest along its motion.
    auto ahead = [&](std::uint64_t g) {
      const Int3 c = grid_cell(grid, g);
      return c.x * motion.x + c.y * motion.y + c.z * motion.z;
    };
    std::stable_sort(s.push.begin(), s.push.end(), [&](std::uint64_t a, std::uint64_t b) { return ahead(a) > ahead(b); });

    // A push passes through mobile cells and ends in a void outside the shape; it may cross cells of
    // the shape that wait for their own push (it moves what they hold on by one cell).
    auto passable = [&](std::uint32_t i) { return s.in_shape[i] != kTaken && (material(i) == 0 || mobile(material(i))); };
    auto search = [&] {
      s.distance.assign(region.volume(), -1);
      s.queue.clear();
      for (std::uint32_t i = 0; i < region.volume(); ++i)
        if (!s.in_shape[i] && material(i) == 0) {
          s.distance[i] = 0;
          s.queue.push_back(i);
        }
      for (std::size_t head = 0; head < s.queue.size(); ++head) {
        const std::uint32_t i = s.queue[head];
        const Int3 c = region.cell(i);
        for (const Int3& d : search_order) {
          const Int3 n{c.x + d.x, c.y + d.y, c.z + d.z};
          if (!region.inside(n)) continue;
          const std::uint32_t j = region.local(n);
          if (s.distance[j] >= 0 || !passable(j)) continue;
          s.distance[j] = s.distance[i] + 1;
          s.queue.push_back(j);
        }
      }
    };
    // The neighbour of local cell i with the smallest distance below `below` (-1: none); ties go to
    // the first in directions(lead, turn of the cell).
    auto next = [&](std::uint32_t i, std::int32_t below) -> std::int64_t {
      const Int3 c = region.cell(i);
      const std::array<Int3, 6> dirs = directions(lead, unsigned(mix64(salt ^ grid_index(grid, c.x, c.y, c.z)) & 3));
      std::int64_t best = -1;
      std::int32_t best_distance = below;
      for (const Int3& d : dirs) {
        const Int3 n{c.x + d.x, c.y + d.y, c.z + d.z};
        if (!region.inside(n)) continue;
        const std::uint32_t j = region.local(n);
        if (s.distance[j] >= 0 && s.distance[j] < best_distance && passable(j)) {
          best = j;
          best_distance = s.distance[j];
        }
      }
      return best;
    };

    search();
    bool fresh = true;  // the distances are exact: no void was used since the search
    for (const std::uint64_t g : s.push) {
      const std::uint32_t start = region.local(grid_cell(grid, g));
      for (;;) {
        s.path.assign(1, start);
        std::int64_t step = next(start, INT32_MAX);
        while (step >= 0) {
          s.path.push_back(std::uint32_t(step));
          if (s.distance[std::uint32_t(step)] == 0) break;
          step = next(std::uint32_t(step), s.distance[std::uint32_t(step)]);
        }
        const std::uint32_t end = s.path.back();
        if (s.path.size() > 1 && s.distance[end] == 0 && material(end) == 0) {
          ++result.displaced[material(start)];
          for (std::size_t k = s.path.size() - 1; k > 0; --k) put(s.path[k], material(s.path[k - 1]));
          put(start, body_material);
          s.in_shape[start] = kTaken;
          s.distance[end] = -1;
          fresh = false;
          s.taken.push_back(g);
          break;
        }
        if (fresh) {  // no void within reach
          ++result.blocked;
          break;
        }
        search();
        fresh = true;
      }
    }
    std::sort(s.taken.begin(), s.taken.end());
  }

  // The wake: each cell the body left is filled from the nearest surface above it, lowest cell first.
  // A surface is a grain or liquid outside the shape with void or gas over it, higher than the cell;
  // the path runs through grains and liquid outside the shape, each moving one cell towards the wake,
  // so the surface drops where the fill came from.
  if (!s.left.empty()) {
    std::sort(s.left.begin(), s.left.end());  // local indices: z, then y, then x
    auto dense = [&](std::uint32_t i) {
      const Behaviour b = materials[material(i)].behaviour;
      return s.in_shape[i] == 0 && (b == Behaviour::Granular || b == Behaviour::Liquid);
    };
    auto open_above = [&](Int3 c) {
      const Int3 up{c.x, c.y, c.z + 1};
      if (!region.inside(up)) return false;
      const std::uint32_t j = region.local(up);
      return s.in_shape[j] == 0 && (material(j) == 0 || materials[material(j)].behaviour == Behaviour::Gas);
    };
    s.parent.assign(region.volume(), kUnseen);
    for (const std::uint32_t wake : s.left) {
      if (material(wake) != 0) continue;
      const Int3 at = region.cell(wake);
      const std::array<Int3, 6> fill_order =
          directions({}, unsigned(mix64(salt ^ ~grid_index(grid, at.x, at.y, at.z)) & 3));
      const int height = at.z;
      s.queue.assign(1, wake);
      s.parent[wake] = wake;
      std::int64_t found = -1;
      for (std::size_t head = 0; head < s.queue.size() && found < 0; ++head) {
        const Int3 c = region.cell(s.queue[head]);
        for (const Int3& d : fill_order) {
          const Int3 n{c.x + d.x, c.y + d.y, c.z + d.z};
          if (!region.inside(n)) continue;
          const std::uint32_t j = region.local(n);
          if (s.parent[j] != kUnseen || !dense(j)) continue;
          s.parent[j] = s.queue[head];
          s.queue.push_back(j);
          if (n.z > height && open_above(n)) {
            found = j;
            break;
          }
        }
      }
      if (found >= 0) {
        ++result.filled[material(std::uint32_t(found))];
        std::uint32_t to = std::uint32_t(found);
        std::uint8_t carried = 0;  // what the cell nearer the wake takes
        for (std::uint32_t at = to;; at = s.parent[at]) {
          const std::uint8_t here = material(at);
          put(at, carried);
          carried = here;
          if (at == wake) break;
        }
      }
      for (const std::uint32_t i : s.queue) s.parent[i] = kUnseen;
    }
  }
  owned.swap(s.taken);
  return result;
}

}  // namespace granular
