#include "scenes/scene_shapes.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "granular/errors.hpp"
#include "scenes/scene_json.hpp"

namespace granular::scene_detail {

namespace {

__extension__ using Wide = __int128;

/// Type names accepted in "type", for messages.
constexpr const char* kShapeTypes = "box, sphere, cylinder, cone (or frustum), bowl";

BoxShape parse_box(const JsonFields& f) {
  f.check_known({"type", "material", "only", "min", "max"}, "a box");
  constexpr const char* needs = "a box needs min and max";
  BoxShape box{f.point<3>("min", needs), f.point<3>("max", needs)};
  constexpr const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a)
    if (box.max[a] < box.min[a])
      f.fail("max", std::string("is below min along ") + axes[a] + " (min " + number_text(box.min[a]) + ")");
  return box;
}

SphereShape parse_sphere(const JsonFields& f) {
  f.check_known({"type", "material", "only", "center", "radius"}, "a sphere");
  constexpr const char* needs = "a sphere needs center and radius";
  return SphereShape{f.point<3>("center", needs), f.length("radius", needs)};
}

CylinderShape parse_cylinder(const JsonFields& f) {
  f.check_known({"type", "material", "only", "center", "radius", "z0", "z1"}, "a cylinder");
  constexpr const char* needs = "a cylinder needs center [x, y], radius, z0 and z1";
  CylinderShape c{f.point<2>("center", needs), f.length("radius", needs), f.position("z0", needs),
                  f.position("z1", needs)};
  if (c.z1 < c.z0) f.fail("z1", "is below z0 (" + number_text(c.z0) + ")");
  return c;
}

ConeShape parse_cone(const JsonFields& f) {
  f.check_known({"type", "material", "only", "center", "z0", "z1", "r0", "r1"}, "a cone");
  constexpr const char* needs = "a cone needs center [x, y], z0, z1, r0 and r1";
  ConeShape c{f.point<2>("center", needs), f.position("z0", needs), f.position("z1", needs),
              f.length("r0", needs), f.length("r1", needs)};
  if (c.z1 < c.z0) f.fail("z1", "is below z0 (" + number_text(c.z0) + ")");
  return c;
}

BowlShape parse_bowl(const JsonFields& f) {
  f.check_known({"type", "material", "only", "center", "radius", "thickness", "thickness_cells"}, "a bowl");
  constexpr const char* needs = "a bowl needs center, radius and thickness or thickness_cells";
  BowlShape b;
  b.center = f.point<3>("center", needs);
  b.radius = f.length("radius", needs);
  if (b.radius <= 0) f.fail("radius", "must be greater than zero");
  const bool fraction = f.has("thickness"), cells = f.has("thickness_cells");
  if (fraction && cells) f.fail("thickness_cells", "give either thickness (fraction of N) or thickness_cells, not both");
  if (cells) {
    b.thickness = f.length("thickness_cells", needs);
    b.thickness_in_cells = true;
    if (b.thickness <= 0) f.fail("thickness_cells", "must be greater than zero");
  } else {
    b.thickness = f.length("thickness", needs);
    if (b.thickness <= 0) f.fail("thickness", "must be greater than zero");
    if (b.thickness > b.radius)
      f.fail("thickness", "must not exceed the radius (" + number_text(b.radius) + ")");
  }
  return b;
}

/// Cell index range [lo, hi) of the cells whose centre (16k + 8 sixteenths) lies in [a, b].
std::pair<std::int64_t, std::int64_t> centres_within(std::int64_t a, std::int64_t b) {
  const std::int64_t lo = -floor_div(-(a - kSubcell / 2), kSubcell);  // ceil((a - 8) / 16)
  const std::int64_t hi = floor_div(b - kSubcell / 2, kSubcell) + 1;
  return {lo, hi};
}

/// Clips a cell range to [0, extent).
std::pair<int, int> clip(std::pair<std::int64_t, std::int64_t> r, int extent) {
  const std::int64_t lo = std::clamp<std::int64_t>(r.first, 0, extent);
  const std::int64_t hi = std::clamp<std::int64_t>(r.second, lo, extent);
  return {int(lo), int(hi)};
}

/// Writes `shape.material` into every cell of the ranges for which inside(x, y, z) holds, subject to
/// shape.only. Centres passed to `inside` are in sixteenths.
template <class Inside>
void paint(Grid& grid, const ShapeDef& shape, std::pair<int, int> xs, std::pair<int, int> ys, std::pair<int, int> zs,
           Inside&& inside) {
  const std::uint8_t value = to_cell(shape.material);
  const bool filtered = shape.only.has_value();
  const std::uint8_t only = filtered ? to_cell(*shape.only) : 0;
  auto cells = grid.cells();
  for (int z = zs.first; z < zs.second; ++z) {
    const std::int64_t cz = std::int64_t(z) * kSubcell + kSubcell / 2;
    for (int y = ys.first; y < ys.second; ++y) {
      const std::int64_t cy = std::int64_t(y) * kSubcell + kSubcell / 2;
      std::uint8_t* row = cells.data() + grid.index({0, y, z});
      for (int x = xs.first; x < xs.second; ++x) {
        if (filtered && row[x] != only) continue;
        if (inside(std::int64_t(x) * kSubcell + kSubcell / 2, cy, cz)) row[x] = value;
      }
    }
  }
}

std::int64_t sq(std::int64_t v) { return v * v; }

}  // namespace

std::int64_t to_sixteenths(double fraction, int n, const std::string& what) {
  const double cells = fraction * double(n);
  if (!std::isfinite(cells) || std::fabs(cells) > kMaxScaledCells)
    throw InvalidArgument(what + ": " + number_text(fraction) + " times N=" + std::to_string(n) +
                          " is out of range (at most " + number_text(kMaxScaledCells) + " cells)");
  return std::llround(cells * double(kSubcell));
}

ShapeDef parse_shape(const nlohmann::json& value, const std::string& path, const std::string& source) {
  const JsonFields f(value, path, source);
  ShapeDef shape;
  shape.field = path;
  const std::string needs = std::string("every shape needs type and material; types: ") + kShapeTypes;
  const std::string type = f.text("type", needs);
  shape.material = f.material("material", needs);
  if (f.has("only")) shape.only = f.material("only", "");
  if (type == "box") shape.geometry = parse_box(f);
  else if (type == "sphere") shape.geometry = parse_sphere(f);
  else if (type == "cylinder") shape.geometry = parse_cylinder(f);
  else if (type == "cone" || type == "frustum") shape.geometry = parse_cone(f);
  else if (type == "bowl") shape.geometry = parse_bowl(f);
  else f.fail("type", std::string("unknown shape type (valid: ") + kShapeTypes + ")");
  return shape;
}

void draw_shape(Grid& grid, const ShapeDef& shape, int n, const std::string& source) {
  const Int3 size = grid.size();
  const std::string where = source + ": " + shape.field;
  auto q = [&](double v, const char* field) { return to_sixteenths(v, n, where + "." + field); };

  std::visit(
      [&](const auto& g) {
        using T = std::decay_t<decltype(g)>;
        if constexpr (std::is_same_v<T, BoxShape>) {
          std::pair<int, int> r[3];
          const int extents[3] = {size.x, size.y, size.z};
          for (int a = 0; a < 3; ++a)
            r[a] = clip({cell_boundary(q(g.min[a], "min")), cell_boundary(q(g.max[a], "max"))}, extents[a]);
          paint(grid, shape, r[0], r[1], r[2], [](std::int64_t, std::int64_t, std::int64_t) { return true; });
        } else if constexpr (std::is_same_v<T, SphereShape>) {
          const std::int64_t cx = q(g.center[0], "center"), cy = q(g.center[1], "center"),
                             cz = q(g.center[2], "center"), r = q(g.radius, "radius");
          paint(grid, shape, clip(centres_within(cx - r, cx + r), size.x), clip(centres_within(cy - r, cy + r), size.y),
                clip(centres_within(cz - r, cz + r), size.z), [&](std::int64_t x, std::int64_t y, std::int64_t z) {
                  return sq(x - cx) + sq(y - cy) + sq(z - cz) <= sq(r);
                });
        } else if constexpr (std::is_same_v<T, CylinderShape>) {
          const std::int64_t cx = q(g.center[0], "center"), cy = q(g.center[1], "center"), r = q(g.radius, "radius");
          const std::pair<std::int64_t, std::int64_t> zr{cell_boundary(q(g.z0, "z0")), cell_boundary(q(g.z1, "z1"))};
          paint(grid, shape, clip(centres_within(cx - r, cx + r), size.x), clip(centres_within(cy - r, cy + r), size.y),
                clip(zr, size.z), [&](std::int64_t x, std::int64_t y, std::int64_t) {
                  return sq(x - cx) + sq(y - cy) <= sq(r);
                });
        } else if constexpr (std::is_same_v<T, ConeShape>) {
          const std::int64_t cx = q(g.center[0], "center"), cy = q(g.center[1], "center");
          const std::int64_t r0 = q(g.r0, "r0"), r1 = q(g.r1, "r1"), rmax = std::max(r0, r1);
          const std::int64_t b0 = cell_boundary(q(g.z0, "z0")), b1 = cell_boundary(q(g.z1, "z1"));
          const std::int64_t z0 = b0 * kSubcell, z1 = b1 * kSubcell, h = z1 - z0;
          if (h <= 0) return;
          // Inside when d <= r(z) with r linear from r0 at z0 to r1 at z1; multiplied through by h.
          paint(grid, shape, clip(centres_within(cx - rmax, cx + rmax), size.x),
                clip(centres_within(cy - rmax, cy + rmax), size.y), clip({b0, b1}, size.z),
                [&](std::int64_t x, std::int64_t y, std::int64_t z) {
                  const Wide d2 = Wide(sq(x - cx) + sq(y - cy));
                  const Wide rh = Wide(r0) * (z1 - z) + Wide(r1) * (z - z0);
                  return d2 * h * h <= rh * rh;
                });
        } else if constexpr (std::is_same_v<T, BowlShape>) {
          const std::int64_t cx = q(g.center[0], "center"), cy = q(g.center[1], "center"),
                             cz = q(g.center[2], "center"), r = q(g.radius, "radius");
          std::int64_t t = 0;
          if (g.thickness_in_cells)
            t = std::llround(g.thickness * double(kSubcell));
          else
            t = q(g.thickness, "thickness");
          const std::int64_t inner = r - t;
          if (inner < 0)
            throw InvalidArgument(where + ": at N=" + std::to_string(n) + " the wall thickness (" +
                                  number_text(double(t) / kSubcell) + " cells) exceeds the radius (" +
                                  number_text(double(r) / kSubcell) + " cells)");
          paint(grid, shape, clip(centres_within(cx - r, cx + r), size.x), clip(centres_within(cy - r, cy + r), size.y),
                clip(centres_within(cz - r, cz), size.z), [&](std::int64_t x, std::int64_t y, std::int64_t z) {
                  const std::int64_t d2 = sq(x - cx) + sq(y - cy) + sq(z - cz);
                  return d2 <= sq(r) && d2 >= sq(inner);
                });
        }
      },
      shape.geometry);
}

}  // namespace granular::scene_detail
