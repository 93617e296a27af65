#include "world/tool_region.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "granular/errors.hpp"
#include "granular/grid.hpp"
#include "granular/rule_set.hpp"
#include "util/number_text.hpp"

namespace granular {

std::string box_string(const Box& b) {
  // Appended in turn: a literal prefixed to a temporary string draws a false -Wrestrict from GCC 12.
  std::string text = "[";
  text += std::to_string(b.min.x) + "," + std::to_string(b.min.y) + "," + std::to_string(b.min.z);
  text += ")-[";
  text += std::to_string(b.max.x) + "," + std::to_string(b.max.y) + "," + std::to_string(b.max.z);
  return text += ")";
}

void check_tool_material(Material m, const char* tool) {
  if (!is_valid_material_value(to_cell(m)))
    throw InvalidArgument(std::string(tool) + ": material value " + std::to_string(unsigned(to_cell(m))) +
                          " is not a valid state (0..7)");
}

Box sphere_region(const Sphere& s, Int3 size, const char* tool, bool& clipped) {
  const Vec3& c = s.center;
  if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z))
    throw InvalidArgument(std::string(tool) + ": sphere centre " + vec_text(c) + " is not finite");
  if (!std::isfinite(s.radius) || s.radius <= 0)
    throw InvalidArgument(std::string(tool) + ": sphere radius " + number_text(s.radius) + " must be > 0");
  const double centre[3] = {c.x, c.y, c.z};
  const int n[3] = {size.x, size.y, size.z};
  int bmin[3], bmax[3];
  clipped = false;
  for (int a = 0; a < 3; ++a) {
    // Cells whose centre k + 0.5 lies within [centre - r, centre + r].
    const double lo = std::ceil(centre[a] - s.radius - 0.5), hi = std::floor(centre[a] + s.radius - 0.5) + 1;
    if (lo < 0 || hi > n[a]) clipped = true;
    const double first = std::max(lo, 0.0), last = std::min(hi, double(n[a]));
    if (!(first < last))
      throw InvalidArgument(std::string(tool) + ": sphere at " + vec_text(c) + " with radius " +
                            number_text(s.radius) + " covers no cell of the " + to_string(size) + " grid");
    bmin[a] = int(first);
    bmax[a] = int(last);
  }
  return {{bmin[0], bmin[1], bmin[2]}, {bmax[0], bmax[1], bmax[2]}};
}

Box check_pour(const Sphere& sphere, Material material, std::int64_t amount, Int3 size, bool& clipped) {
  check_tool_material(material, "pour");
  if (material == Material::Void) throw InvalidArgument("pour: material is void; pour a material (dig removes grains)");
  if (amount < 0) throw InvalidArgument("pour: amount = " + std::to_string(amount) + " must be >= 0");
  return sphere_region(sphere, size, "pour", clipped);
}

void check_shake(const RuleSet& rules, int level) {
  const MotionParams& motion = rules.motion;
  if (!motion.enabled())
    throw InvalidArgument("shake: rule set '" + rules.name +
                          "' has no motion model (MotionParams::substeps 1), so its cells have no motion level to set");
  if (level < 1 || level > motion.max_level())
    throw InvalidArgument("shake: level = " + std::to_string(level) + " is outside 1.." +
                          std::to_string(motion.max_level()) + " (the rule set's highest motion level)");
}

Box check_paint_box(const Box& box, Material material, Int3 size, bool& clipped) {
  check_tool_material(material, "paint");
  if (box.empty()) throw InvalidArgument("paint: box " + box_string(box) + " is empty");
  const Box region = intersect(box, Box{{0, 0, 0}, size});
  if (region.empty())
    throw InvalidArgument("paint: box " + box_string(box) + " lies outside the " + to_string(size) + " grid");
  clipped = !(region == box);
  return region;
}

}  // namespace granular
