#include "bodies/body_shape.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace granular {

Rotation Rotation::of(const Quat& q) {
  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  Rotation r;
  if (!(n > 0)) return r;
  const double w = q.w / n, x = q.x / n, y = q.y / n, z = q.z / n;
  r.m[0][0] = 1 - 2 * (y * y + z * z);
  r.m[0][1] = 2 * (x * y - w * z);
  r.m[0][2] = 2 * (x * z + w * y);
  r.m[1][0] = 2 * (x * y + w * z);
  r.m[1][1] = 1 - 2 * (x * x + z * z);
  r.m[1][2] = 2 * (y * z - w * x);
  r.m[2][0] = 2 * (x * z - w * y);
  r.m[2][1] = 2 * (y * z + w * x);
  r.m[2][2] = 1 - 2 * (x * x + y * y);
  return r;
}

Vec3 Rotation::apply(const Vec3& v) const {
  return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
          m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
}

Vec3 Rotation::inverse(const Vec3& v) const {
  return {m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z, m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z,
          m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z};
}

PlacedShape::PlacedShape(const BodyDef& def, const BodyPose& pose)
    : shape_(def.shape),
      half_(def.half_extents),
      radius_(def.radius),
      half_length_(def.half_length),
      centre_(pose.position),
      rotation_(Rotation::of(pose.orientation)) {}

Box PlacedShape::bounds(Int3 size) const {
  Vec3 reach{radius_, radius_, radius_};
  if (shape_ == BodyShape::Box) {
    const auto& m = rotation_.m;
    reach = {std::abs(m[0][0]) * half_.x + std::abs(m[0][1]) * half_.y + std::abs(m[0][2]) * half_.z,
             std::abs(m[1][0]) * half_.x + std::abs(m[1][1]) * half_.y + std::abs(m[1][2]) * half_.z,
             std::abs(m[2][0]) * half_.x + std::abs(m[2][1]) * half_.y + std::abs(m[2][2]) * half_.z};
  } else if (shape_ == BodyShape::Capsule) {
    const Vec3 axis = rotation_.apply({0, 0, half_length_});
    reach = {std::abs(axis.x) + radius_, std::abs(axis.y) + radius_, std::abs(axis.z) + radius_};
  }
  // Cell i's centre i + 0.5 lies in [c - r, c + r] for i in [floor(c - r - 0.5), ceil(c + r - 0.5)].
  auto span = [](double c, double r, int extent, int& lo, int& hi) {
    const double a = std::floor(c - r - 0.5), b = std::ceil(c + r - 0.5) + 1;
    lo = int(std::clamp(a, 0.0, double(extent)));
    hi = int(std::clamp(b, 0.0, double(extent)));
  };
  Box box;
  span(centre_.x, reach.x, size.x, box.min.x, box.max.x);
  span(centre_.y, reach.y, size.y, box.min.y, box.max.y);
  span(centre_.z, reach.z, size.z, box.min.z, box.max.z);
  return box;
}

namespace {

/// Appends to `out` the grid indices of the cells of `box` (in a grid of `size`) whose centres are
/// `inside` (a test on the body's axes, for a shape turned by `rotation` about `centre`). A row's
/// centres step by one rotated x axis from its first, and its cells inside are one run (the shape
/// is convex), so a row ends at its first cell outside after one inside.
template <class Inside>
void append_cells(const Rotation& rotation, const Vec3& centre, Int3 size, const Box& box, Inside&& inside,
                  std::vector<std::uint64_t>& out) {
  const Vec3 step = rotation.inverse({1, 0, 0});
  for (int z = box.min.z; z < box.max.z; ++z)
    for (int y = box.min.y; y < box.max.y; ++y) {
      Vec3 q = rotation.inverse({box.min.x + 0.5 - centre.x, y + 0.5 - centre.y, z + 0.5 - centre.z});
      const std::uint64_t row = grid_index(size, 0, y, z);
      bool entered = false;
      for (int x = box.min.x; x < box.max.x; ++x, q = {q.x + step.x, q.y + step.y, q.z + step.z}) {
        if (inside(q)) {
          out.push_back(row + std::uint64_t(x));
          entered = true;
        } else if (entered) {
          break;
        }
      }
    }
}

}  // namespace

void PlacedShape::cells(Int3 size, std::vector<std::uint64_t>& out) const {
  out.clear();
  const Box b = bounds(size);
  if (b.empty()) return;
  switch (shape_) {
    case BodyShape::Box:
      append_cells(
          rotation_, centre_, size, b,
          [h = half_](const Vec3& q) { return std::abs(q.x) <= h.x && std::abs(q.y) <= h.y && std::abs(q.z) <= h.z; },
          out);
      return;
    case BodyShape::Sphere:
      append_cells(
          rotation_, centre_, size, b,
          [r2 = radius_ * radius_](const Vec3& q) { return q.x * q.x + q.y * q.y + q.z * q.z <= r2; }, out);
      return;
    case BodyShape::Capsule:
      append_cells(
          rotation_, centre_, size, b,
          [r2 = radius_ * radius_, l = half_length_](const Vec3& q) {
            const double z = q.z - std::clamp(q.z, -l, l);
            return q.x * q.x + q.y * q.y + z * z <= r2;
          },
          out);
      return;
  }
}

double shape_volume(const BodyDef& def) {
  constexpr double pi = std::numbers::pi;
  switch (def.shape) {
    case BodyShape::Box:
      return 8 * def.half_extents.x * def.half_extents.y * def.half_extents.z;
    case BodyShape::Sphere:
      return 4.0 / 3.0 * pi * def.radius * def.radius * def.radius;
    case BodyShape::Capsule:
      return pi * def.radius * def.radius * (2 * def.half_length + 4.0 / 3.0 * def.radius);
  }
  return 0;
}

}  // namespace granular
