#include "bodies/body_stamp.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <climits>
#include <cmath>
#include <cstring>
#include <type_traits>

#include "bodies/body_forces.hpp"
#include "bodies/body_region.hpp"
#include "bodies/body_shape.hpp"
#include "bodies/cell_classes.hpp"
#include "granular/grid.hpp"
#include "granular/motion.hpp"

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

/// Layers below a wake cell that the path of its fill may go down to: water does not come up a
/// deeper bend to fill a wake in one tick (the rules close such a wake), and the searches stay near
/// the wake's own layers.
constexpr int kFillDepth = 2;

/// Cells a push's search from a filled void may reach before the distances are searched anew, if
/// the searches since they were last searched have reached a kRegionPerRefresh-th of the region (a
/// search of the distances works the whole region: so it costs no more than 16 times the searches).
constexpr std::size_t kSearchBeforeRefresh = 512;
constexpr std::size_t kRegionPerRefresh = 16;

/// A cell's class (StampScratch::cls): what the searches ask of it.
enum Class : std::uint8_t {
  kPass = 1,       ///< a push may pass through it: void or mobile, and not yet the body's
  kFree = 2,       ///< a push may end in it: void, outside the shape and its surroundings
  kVoidOut = 4,    ///< void outside the shape
  kLiquidOut = 8,  ///< liquid outside the shape
  kOpenOut = 16,   ///< void or gas outside the shape
  kSurface = 32,   ///< liquid outside the shape under a kOpenOut cell of the region
  kSeen = 64,      ///< the last search reached it
  kOnRoute = 128,  ///< on the route of the push being made
};

}  // namespace

StampResult stamp_body(const Box& box, std::span<std::uint8_t> bytes, Int3 grid,
                       const std::vector<std::uint64_t>& shape, std::vector<std::uint64_t>& owned,
                       std::uint8_t body_material, const MaterialTable& materials, const Vec3& motion,
                       std::uint64_t salt, StampScratch& s) {
  StampResult result;
  const BodyRegion region(box);
  s.written.clear();
  cells_at(owned, grid, s.owned_at);
  // A body that holds its whole shape, every cell still its own, writes nothing: most ticks of a
  // body moving less than a cell a tick.
  if (shape == owned && std::all_of(s.owned_at.begin(), s.owned_at.end(),
                                    [&](Int3 c) { return (bytes[region.local(c)] & kMaterialMask) == body_material; }))
    return result;
  cells_at(shape, grid, s.shape_at);
  auto material = [&](std::uint32_t i) { return std::uint8_t(bytes[i] & kMaterialMask); };
  std::array<std::uint8_t, kMaterialCount> behaviour_bits{};  // per material: 1 mobile, 2 liquid, 4 gas
  for (std::size_t m = 0; m < kMaterialCount; ++m) {
    const Behaviour b = materials[m].behaviour;
    behaviour_bits[m] = std::uint8_t((b == Behaviour::Granular || b == Behaviour::Liquid || b == Behaviour::Gas) |
                                     (b == Behaviour::Liquid) << 1 | (b == Behaviour::Gas) << 2);
  }
  auto mobile = [&](std::uint8_t m) { return (behaviour_bits[m] & 1) != 0; };

  // Per cell of the region: 0 outside the shape, kShape inside it, kTaken once the body holds it,
  // kNear outside it but within kRingWidth cells beside a cell of it in the same layer (the
  // surroundings its buoyancy reads, sand_forces).
  constexpr std::uint8_t kShape = 1, kTaken = 2, kNear = 3;
  const std::int64_t row = region.e.x, layer = std::int64_t(region.e.x) * region.e.y;
  // Once the searches begin, each cell's class (s.cls, Class bits) is kept with its byte and
  // s.in_shape, so that a search tests one byte a cell.
  // class_of[in_shape][material]: the class bits a cell's byte and mark give.
  CellClassTable class_of{};
  for (std::uint8_t in = 0; in < 4; ++in)
    for (std::uint8_t m = 0; m < kMaterialCount; ++m) {
      const std::uint8_t bits = behaviour_bits[m];
      const bool out = in == 0 || in == kNear;
      class_of[in][m] =
          std::uint8_t((in != kTaken && (m == 0 || mobile(m)) ? kPass : 0) | (m == 0 && in == 0 ? kFree : 0) |
                       (m == 0 && out ? kVoidOut : 0) | (out && (bits & 2) ? kLiquidOut : 0) |
                       (out && (m == 0 || (bits & 4)) ? kOpenOut : 0));
    }
  auto classify = [&](std::uint32_t i) {
    s.cls[i] =
        std::uint8_t((s.cls[i] & (kSurface | kSeen | kOnRoute)) | class_of[s.in_shape[i]][bytes[i] & kMaterialMask]);
  };
  auto classify_surface = [&](std::uint32_t i) {
    const bool on = (s.cls[i] & kLiquidOut) && !(s.edges[i] & 16) && (s.cls[i + std::uint32_t(layer)] & kOpenOut);
    s.cls[i] = std::uint8_t(on ? s.cls[i] | kSurface : s.cls[i] & ~kSurface);
  };
  bool classed = false;
  auto reclassify = [&](std::uint32_t i) {
    classify(i);
    classify_surface(i);
    if (!(s.edges[i] & 32)) classify_surface(i - std::uint32_t(layer));
  };
  auto put = [&](std::uint32_t i, std::uint8_t byte) {
    bytes[i] = byte;
    s.written.push_back(i);
    if (classed) reclassify(i);
  };

  s.in_shape.assign(region.volume(), 0);
  for (const Int3 c : s.shape_at) s.in_shape[region.local(c)] = kShape;
  for_each_cell_beside(region, s.shape_at, kRingWidth, s.rows, [&](std::uint32_t i, int) { s.in_shape[i] = kNear; });
  auto outside = [&](std::uint32_t i) { return s.in_shape[i] == 0 || s.in_shape[i] == kNear; };

  // The cells the body left.
  s.left.clear();
  for (const Int3 c : s.owned_at) {
    const std::uint32_t i = region.local(c);
    if (outside(i) && material(i) == body_material) {
      put(i, 0);
      s.left.push_back(i);
    }
  }

  // The cells it keeps or takes at once; those holding something mobile wait for a push.
  s.taken.clear();
  s.push.clear();
  auto was_owned = owned.begin();
  for (std::uint32_t k = 0; k < shape.size(); ++k) {
    const std::uint64_t g = shape[k];
    while (was_owned != owned.end() && *was_owned < g) ++was_owned;
    const bool kept = was_owned != owned.end() && *was_owned == g;
    const std::uint32_t i = region.local(s.shape_at[k]);
    const std::uint8_t m = material(i);
    if (m == body_material && kept) {
      s.in_shape[i] = kTaken;
      s.taken.push_back(g);
    } else if (m == to_cell(Material::Void)) {
      put(i, body_material);
      s.in_shape[i] = kTaken;
      s.taken.push_back(g);
    } else if (mobile(m)) {
      s.push.push_back(k);
    } else {
      ++result.blocked;
    }
  }

  // The breadth-first search both the pushes and the wake's fill make: from `from`, through cells of
  // the class `pass` (not on the push's route, and none before local index `lowest`: no layer below
  // its layer), trying neighbours in `order`, to the nearest cell
  // `target` calls kFar (away from the body's surroundings), else the nearest it calls kNearby, or
  // with `nearby_will_do` the nearest of either; s.parent then leads back from the cell found to
  // `from`. Returns the cell, or -1 for none within the region. A search that finds none marks the
  // cells it reached `s.dead`: targets are only used up while the body is written, so a later search
  // from one of them finds none either. The cells the last search reached are marked kSeen.
  enum Target { kNot, kNearby, kFar };
  if (s.push.empty() && s.left.empty()) {
    owned.swap(s.taken);
    return result;
  }
  s.parent.resize(region.volume());
  s.dead.assign(region.volume(), 0);
  s.queue.clear();
  // Per cell, a bit for each of its six neighbours that lies outside the region (Step's order), so
  // that a search steps by index. They depend on the extent only: most stamps reuse the last ones.
  if (!(s.edges_extent == region.e) || s.edges.size() != region.volume()) {
    s.edges_extent = region.e;
    s.edges.assign(region.volume(), 0);
    for (std::int64_t z = 0; z < region.e.z; ++z)
      for (std::int64_t y = 0; y < region.e.y; ++y) {
        const std::int64_t first = z * layer + y * row, last = first + row - 1;
        s.edges[std::size_t(first)] |= 2;
        s.edges[std::size_t(last)] |= 1;
        if (y == 0 || y + 1 == region.e.y || z == 0 || z + 1 == region.e.z) {
          const std::uint8_t bits =
              std::uint8_t((y + 1 == region.e.y) << 2 | (y == 0) << 3 | (z + 1 == region.e.z) << 4 | (z == 0) << 5);
          for (std::int64_t i = first; i <= last; ++i) s.edges[std::size_t(i)] |= bits;
        }
      }
  }
  // Every cell's class at once, what classify and classify_surface give a cell (they keep it as
  // cells are written): a table lookup a cell (classify_cells), then the surfaces (kLiquidOut, bit
  // 3, under kOpenOut, bit 4, gives kSurface, bit 5) without a branch; the top layer has none.
  static_assert(kLiquidOut == 8 && kOpenOut == 16 && kSurface == 32 && kMaterialMask == kMaterialCount - 1);
  s.cls.resize(region.volume());
  classify_cells(class_of, s.in_shape, bytes, s.cls);
  for (std::uint32_t i = 0, below_top = std::uint32_t(region.volume() - std::size_t(layer)); i < below_top; ++i)
    s.cls[i] |= std::uint8_t(((s.cls[i] >> 3) & (s.cls[i + std::uint32_t(layer)] >> 4) & 1) << 5);
  classed = true;
  // A direction as the search takes it: the edge bit that forbids it, that bit's number (the
  // direction a search notes in s.parent), and the step of the index.
  struct Step {
    std::uint8_t edge;
    std::uint8_t code;
    std::int64_t delta;
  };
  const std::array<std::int64_t, 6> step_of_code{1, -1, row, -row, layer, -layer};
  auto steps_of = [&](const std::array<Int3, 6>& order) {
    std::array<Step, 6> out{};
    for (std::size_t k = 0; k < 6; ++k) {
      const Int3 d = order[k];
      const int bit = d.x == 1 ? 0 : d.x == -1 ? 1 : d.y == 1 ? 2 : d.y == -1 ? 3 : d.z == 1 ? 4 : 5;
      out[k] = {std::uint8_t(1 << bit), std::uint8_t(bit), d.x + d.y * row + d.z * layer};
    }
    return out;
  };
  // The cell the last search reached `i` from.
  auto parent = [&](std::uint32_t i) { return std::uint32_t(std::int64_t(i) - step_of_code[s.parent[i]]); };
  auto nearest = [&](std::uint32_t from, const std::array<Int3, 6>& order, bool nearby_will_do, std::uint8_t pass,
                     auto&& target, auto skip_dead, std::uint32_t lowest) -> std::int64_t {
    for (const std::uint32_t i : s.queue) s.cls[i] &= std::uint8_t(~kSeen);  // the last search's marks
    s.queue.assign(1, from);
    s.cls[from] |= kSeen;
    if (s.dead[from]) return -1;
    const std::array<Step, 6> steps = steps_of(order);
    std::int64_t nearby = -1;
    for (std::size_t head = 0; head < s.queue.size(); ++head) {
      const std::uint32_t i = s.queue[head];
      for (const Step& step : steps) {
        if (s.edges[i] & step.edge) continue;
        const std::uint32_t j = std::uint32_t(std::int64_t(i) + step.delta);
        if ((s.cls[j] & (pass | kSeen | kOnRoute)) != pass || j < lowest) continue;
        if constexpr (decltype(skip_dead)::value)
          if (s.dead[j]) continue;
        s.cls[j] |= kSeen;
        s.parent[j] = step.code;
        s.queue.push_back(j);
        const Target t = target(j);
        if (t == kFar || (t == kNearby && nearby_will_do)) return j;
        if (t == kNearby && nearby < 0) nearby = j;
      }
    }
    if (nearby < 0)
      for (const std::uint32_t i : s.queue) s.dead[i] = 1;
    return nearby;
  };
  // Shifts the path s.parent gives from `end` back to `from` by one cell towards `from`: each cell
  // takes the material of the one after it, `end` becomes void.
  auto pull = [&](std::uint32_t from, std::uint32_t end) {
    std::uint8_t carried = 0;
    for (std::uint32_t at = end;; at = parent(at)) {
      const std::uint8_t here = material(at);
      put(at, carried);
      carried = here;
      if (at == from) break;
    }
  };

  if (!s.push.empty()) {
    const Int3 lead = lead_of(motion);
    // The front of the body first: the cells farthest along its motion.
    s.ahead.clear();
    for (const std::uint32_t k : s.push) {
      const Int3 c = s.shape_at[k];
      s.ahead.emplace_back(c.x * motion.x + c.y * motion.y + c.z * motion.z, k);
    }
    std::stable_sort(s.ahead.begin(), s.ahead.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    for (std::size_t k = 0; k < s.push.size(); ++k) s.push[k] = s.ahead[k].second;
    const std::size_t kept = s.taken.size();  // the cells taken before the pushes, ascending
    // A push passes through mobile cells and voids, crossing cells of the shape that wait for their
    // own push (it moves what they hold on by one cell), and ends in the nearest void away from the
    // body's surroundings (so that its buoyancy does not jump with what it pushed).
    auto through = [&](std::uint32_t i) { return (s.cls[i] & kPass) != 0; };
    auto free_cell = [&](std::uint32_t i) { return (s.cls[i] & kFree) != 0; };
    // Every cell's distance to the nearest such void, searched from all of them at once. A push
    // follows it down; where it leads to a void an earlier push has filled, or nowhere, a search from
    // there ends in the nearest void outside the shape, and the distances are searched anew once such
    // searches grow.
    // The search goes a distance at a time over bit rows (a bit a cell, x along a row of 64-bit
    // words): the cells at the next distance are the neighbours of those at this one, shifted along
    // x and taken from the rows beside, that a push may pass and no distance has reached yet. It
    // works only the layers next to the last distance's cells, and stops once it has reached every
    // push still to come: a push follows distances below its start's only, all known by then.
    const std::size_t words = (std::size_t(region.e.x) + 63) / 64, rows = std::size_t(region.e.y) * region.e.z;
    const std::size_t row_step = words, layer_step = words * std::size_t(region.e.y);
    std::size_t next_push = 0;            // the pushes before it are done
    std::size_t searched_since_field = 0;  // cells the searches have reached since the distances were searched
    // s.distance holds, per cell the last search reached, that search's number (s.searched, the top
    // 8 bits) and the cell's distance, so that no search clears it; a cell holding another number
    // has no distance.
    auto distance = [&](std::uint32_t i) {
      const std::uint32_t v = s.distance[i];
      return v >> 24 == s.searched ? std::int32_t(v & 0xFFFFFF) : -1;
    };
    auto field = [&] {
      static_assert(kMaxBodyHalfSize <= 64, "a region's distances fit in 24 bits");
      searched_since_field = 0;
      s.distance.resize(region.volume());
      if (++s.searched == 256) {  // the numbers wrap: none may be left over
        s.searched = 1;
        std::fill(s.distance.begin(), s.distance.end(), 0u);
      }
      const std::uint32_t numbered = s.searched << 24;
      s.passable.resize(rows * words);
      s.reached.assign(rows * words, 0);
      s.at_distance.resize(rows * words);
      s.next_distance.assign(rows * words, 0);
      s.pending.assign(rows * words, 0);  // the starts of the pushes still to come, as bits
      for (std::size_t k = next_push; k < s.push.size(); ++k) {
        const Int3 c = s.shape_at[s.push[k]];
        const int x = c.x - region.box.min.x;
        s.pending[(std::size_t(c.z - region.box.min.z) * region.e.y + std::size_t(c.y - region.box.min.y)) * words +
                  std::size_t(x / 64)] |= std::uint64_t(1) << (x % 64);
      }
      std::size_t to_reach = s.push.size() - next_push;  // pushes to come whose start it has not reached
      int low = region.e.z, high = -1;  // the layers of the cells at the current distance
      // A row's bits, 64 cells at a time, from the class bits kPass (1) and kFree (2): eight cells'
      // bytes at once, the multiply gathering bit 0 of byte k into bit 56 + k.
      static_assert(kPass == 1 && kFree == 2 && std::endian::native == std::endian::little);
      constexpr std::uint64_t kLow = 0x0101010101010101ull, kGather = 0x0102040810204080ull;
      for (std::uint32_t i = 0, r = 0; r < rows; ++r) {
        std::uint64_t any_free = 0;
        for (std::size_t w = 0; w < words; ++w) {
          std::uint64_t pass = 0, free = 0;
          const int end = std::min(64, region.e.x - int(w * 64));
          int x = 0;
          for (; x + 8 <= end; x += 8, i += 8) {
            std::uint64_t eight;
            std::memcpy(&eight, s.cls.data() + i, 8);
            pass |= (((eight & kLow) * kGather) >> 56) << x;
            free |= ((((eight >> 1) & kLow) * kGather) >> 56) << x;
          }
          for (; x < end; ++x, ++i) {
            pass |= std::uint64_t(s.cls[i] & kPass) << x;
            free |= std::uint64_t((s.cls[i] & kFree) >> 1) << x;
          }
          s.passable[r * words + w] = pass;
          s.at_distance[r * words + w] = free;
          any_free |= free;
          for (std::uint64_t bits = free; bits != 0; bits &= bits - 1)
            s.distance[r * std::size_t(region.e.x) + w * 64 + std::size_t(std::countr_zero(bits))] = numbered;
        }
        if (any_free != 0) {
          low = std::min(low, int(r / std::uint32_t(region.e.y)));
          high = std::max(high, int(r / std::uint32_t(region.e.y)));
        }
      }
      s.reached = s.at_distance;
      if (words == 1) s.no_rows.assign(std::size_t(region.e.y), 0);  // beyond the region's layers
      for (std::int32_t d = 1; to_reach > 0 && low <= high; ++d) {
        const int from = std::max(0, low - 1), to = std::min(region.e.z - 1, high + 1);
        int next_low = region.e.z, next_high = -1;
        // Row `at` (layer z, row y, word w) takes the cells of `grown` that it may pass and no
        // distance has reached: they are at distance d.
        auto take = [&](std::size_t at, int z, int y, std::size_t w, std::uint64_t grown) {
          std::uint64_t fresh = grown & s.passable[at] & ~s.reached[at];
          s.next_distance[at] = fresh;
          if (fresh == 0) return;
          s.reached[at] |= fresh;
          next_low = std::min(next_low, z);
          next_high = std::max(next_high, z);
          const std::uint32_t first =
              std::uint32_t((std::size_t(z) * region.e.y + std::size_t(y)) * region.e.x + w * 64);
          if (const std::uint64_t starts = fresh & s.pending[at]; starts != 0)
            to_reach -= std::size_t(std::popcount(starts));
          for (; fresh != 0; fresh &= fresh - 1)
            s.distance[first + std::uint32_t(std::countr_zero(fresh))] = numbered | std::uint32_t(d);
        };
        const std::uint64_t* f = s.at_distance.data();
        if (words == 1) {  // most regions: a row a word, its neighbours' rows carried along
          for (int z = from; z <= to; ++z) {
            const std::size_t row0 = std::size_t(z) * region.e.y;
            const std::uint64_t* below = z > 0 ? f + row0 - layer_step : s.no_rows.data();
            const std::uint64_t* above = z + 1 < region.e.z ? f + row0 + layer_step : s.no_rows.data();
            std::uint64_t previous = 0, here = f[row0];
            for (int y = 0; y < region.e.y; ++y) {
              const std::uint64_t next = y + 1 < region.e.y ? f[row0 + std::size_t(y) + 1] : 0;
              take(row0 + std::size_t(y), z, y, 0, here << 1 | here >> 1 | previous | next | below[y] | above[y]);
              previous = here;
              here = next;
            }
          }
        } else {
          for (int z = from; z <= to; ++z)
            for (int y = 0; y < region.e.y; ++y)
              for (std::size_t w = 0; w < words; ++w) {
                const std::size_t at = (std::size_t(z) * region.e.y + std::size_t(y)) * words + w;
                std::uint64_t grown = f[at] << 1 | f[at] >> 1;
                if (w > 0) grown |= f[at - 1] >> 63;
                if (w + 1 < words) grown |= f[at + 1] << 63;
                if (y > 0) grown |= f[at - row_step];
                if (y + 1 < region.e.y) grown |= f[at + row_step];
                if (z > 0) grown |= f[at - layer_step];
                if (z + 1 < region.e.z) grown |= f[at + layer_step];
                take(at, z, y, w, grown);
              }
        }
        // The cells at this distance are done with: their rows are cleared, the next distance's kept.
        for (int z = std::max(0, low); z <= high; ++z)
          std::fill_n(s.at_distance.begin() + std::ptrdiff_t(std::size_t(z) * layer_step), layer_step,
                      std::uint64_t(0));
        std::swap(s.at_distance, s.next_distance);
        low = next_low;
        high = next_high;
      }
    };
    field();
    auto void_found = [&](std::uint32_t i) { return s.cls[i] & kVoidOut ? kFar : kNot; };
    for (; next_push < s.push.size(); ++next_push) {
      const std::uint64_t g = shape[s.push[next_push]];
      const Int3 c = s.shape_at[s.push[next_push]];
      const std::uint32_t start = region.local(c);
      const std::array<Step, 6> steps =
          steps_of(directions(lead, unsigned(mix64(salt ^ grid_index(grid, c.x, c.y, c.z)) & 3)));
      // Down the distances, ties to the first of `steps`.
      s.route.assign(1, start);
      std::int32_t above = INT32_MAX;
      for (std::uint32_t at = start;;) {
        std::int64_t best = -1;
        for (const Step& step : steps) {
          if (s.edges[at] & step.edge) continue;
          const std::uint32_t j = std::uint32_t(std::int64_t(at) + step.delta);
          const std::int32_t d = distance(j);
          if (d >= 0 && d < above && through(j)) {
            best = j;
            above = d;
          }
        }
        if (best < 0) break;
        at = std::uint32_t(best);
        s.route.push_back(at);
        if (free_cell(at) || above == 0) break;
      }
      if (!free_cell(s.route.back())) {  // the distances led to a filled void, or nowhere: search on
        for (const std::uint32_t i : s.route) s.cls[i] |= kOnRoute;
        const std::uint32_t from = s.route.back();
        const std::int64_t end = nearest(from, directions(lead, 0), true, kPass, void_found, std::false_type{}, 0);
        for (const std::uint32_t i : s.route) s.cls[i] &= std::uint8_t(~kOnRoute);
        searched_since_field += s.queue.size();
        const bool grown =
            s.queue.size() > kSearchBeforeRefresh && searched_since_field >= region.volume() / kRegionPerRefresh;
        if (end < 0) {  // no void within reach
          ++result.blocked;
          if (grown) field();
          continue;
        }
        const std::size_t joined = s.route.size();
        for (std::uint32_t at = std::uint32_t(end); at != from; at = parent(at)) s.route.push_back(at);
        std::reverse(s.route.begin() + std::ptrdiff_t(joined), s.route.end());
        if (grown) field();
      }
      ++result.displaced[material(start)];
      for (std::size_t k = s.route.size() - 1; k > 0; --k) put(s.route[k], material(s.route[k - 1]));
      s.in_shape[start] = kTaken;
      put(start, body_material);
      s.taken.push_back(g);
    }
    std::sort(s.taken.begin() + std::ptrdiff_t(kept), s.taken.end());
    std::inplace_merge(s.taken.begin(), s.taken.begin() + std::ptrdiff_t(kept), s.taken.end());
  }

  // The wake: each cell the body left that holds no liquid is filled from the nearest surface of
  // liquid higher than it (liquid outside the shape with void or gas over it, away from the body's
  // surroundings where there is one), lowest cell first; the path runs through liquid outside the
  // shape, each cell moving one cell towards the wake, so the surface drops where the fill came from.
  // Grains are left to topple into the wake by the rules: a furrow stays open as far as sand stands.
  if (!s.left.empty()) {
    std::sort(s.left.begin(), s.left.end());  // local indices: z, then y, then x
    // The first cell over the highest layer that holds a surface (0: none): a wake cell at or over
    // that layer has none to fill it (a fill only lowers a surface), nor have the cells after it.
    std::uint32_t over_top = 0;
    for (std::uint32_t i = std::uint32_t(region.volume()); i-- > 0;)
      if (s.cls[i] & kSurface) {
        over_top = std::uint32_t((std::int64_t(i) / layer + 1) * layer);
        break;
      }
    // Liquid a search reached without finding a surface is marked s.dead, and later searches (from
    // higher cells, wanting higher surfaces) pass it by: it holds none for them either, and no fill
    // adds one to it, until a filled wake cell joins it to other liquid.
    std::fill(s.dead.begin(), s.dead.end(), std::uint8_t(0));
    const std::array<Step, 6> axes = steps_of(directions({}, 0));  // a wake cell's neighbours
    bool nearby_will_do = false;
    for (const std::uint32_t wake : s.left) {
      if (wake + std::uint32_t(layer) >= over_top) break;
      if (material(wake) != 0) continue;
      const Int3 at = region.cell(wake);
      const std::uint32_t above_wake =
          std::uint32_t((std::int64_t(wake) / layer + 1) * layer);  // first cell over its layer
      auto surface = [&](std::uint32_t j) {
        if (j < above_wake || !(s.cls[j] & kSurface)) return kNot;
        return s.in_shape[j] == 0 ? kFar : kNearby;
      };
      const std::uint32_t lowest = std::uint32_t(std::max(0, at.z - region.box.min.z - kFillDepth) * layer);
      const std::int64_t found =
          nearest(wake, directions({}, unsigned(mix64(salt ^ ~grid_index(grid, at.x, at.y, at.z)) & 3)), nearby_will_do,
                  kLiquidOut, surface, std::true_type{}, lowest);
      if (found < 0 || s.in_shape[std::uint32_t(found)] == kNear) nearby_will_do = true;
      if (found < 0) continue;
      ++result.filled[material(std::uint32_t(found))];
      pull(wake, std::uint32_t(found));
      // The wake cell, liquid now, may join liquid that reached no surface to some that does.
      for (const Step& step : axes)
        if (!(s.edges[wake] & step.edge) && s.dead[std::size_t(std::int64_t(wake) + step.delta)]) {
          std::fill(s.dead.begin(), s.dead.end(), std::uint8_t(0));
          break;
        }
    }
  }
  owned.swap(s.taken);
  return result;
}

}  // namespace granular
