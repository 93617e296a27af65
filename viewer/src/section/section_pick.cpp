#include "section/section_pick.hpp"

namespace viewer {
namespace {

double& component(granular::Vec3& v, int axis) { return axis == 0 ? v.x : (axis == 1 ? v.y : v.z); }
int& component(granular::Int3& v, int axis) { return axis == 0 ? v.x : (axis == 1 ? v.y : v.z); }

}  // namespace

std::optional<granular::RayHit> pick_kept_cell(const granular::World& world, const std::optional<SectionCut>& cut,
                                               glm::vec3 origin, glm::vec3 direction) {
  granular::Vec3 start{origin.x, origin.y, origin.z};
  const granular::Vec3 along{direction.x, direction.y, direction.z};
  if (!cut) return granular::raycast(world, start, along);
  const double from = origin[cut->axis], step = direction[cut->axis], plane = cut->plane;
  const bool on_kept_side = cut->keeps_high ? from >= plane : from < plane;
  double travelled = 0;
  if (!on_kept_side) {
    if (cut->keeps_high ? step <= 0 : step >= 0) return std::nullopt;  // the ray leaves the kept side behind
    travelled = (plane - from) / step;
    start = {start.x + along.x * travelled, start.y + along.y * travelled, start.z + along.z * travelled};
    component(start, cut->axis) = cut->keeps_high ? plane + 1e-6 : plane - 1e-6;  // just inside the kept side
  }
  std::optional<granular::RayHit> hit = granular::raycast(world, start, along);
  if (!hit) return hit;
  if (cut->removes(hit->cell)) return std::nullopt;
  if (!on_kept_side && hit->normal == granular::Int3{}) {
    component(hit->normal, cut->axis) = cut->keeps_high ? -1 : 1;
    hit->point = start;
  }
  hit->distance += travelled;
  return hit;
}

}  // namespace viewer
