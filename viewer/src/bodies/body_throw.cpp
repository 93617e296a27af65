#include "bodies/body_throw.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace viewer {

namespace {

constexpr double kGravity = 9.81;  // m/s^2

bool finite(granular::Vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void check_positive(double value, const char* what) {
  if (!std::isfinite(value) || value <= 0)
    throw std::invalid_argument(std::string(what) + " = " + std::to_string(value) + "; must be finite and > 0");
}

void check_choice(const ThrowChoice& choice) {
  if (choice.shape != granular::BodyShape::Box && choice.shape != granular::BodyShape::Sphere)
    throw std::invalid_argument("throw: shape " + std::to_string(int(choice.shape)) + " is not a box or a ball");
  if (!(choice.half_size >= kMinThrowHalfSize && choice.half_size <= kMaxThrowHalfSize))
    throw std::invalid_argument("throw: half size " + std::to_string(choice.half_size) + " cells; use " +
                                std::to_string(int(kMinThrowHalfSize)) + ".." + std::to_string(int(kMaxThrowHalfSize)));
  if (!(choice.density >= kMinThrowDensity && choice.density <= kMaxThrowDensity))
    throw std::invalid_argument("throw: density " + std::to_string(choice.density) + " kg/m^3; use " +
                                std::to_string(int(kMinThrowDensity)) + ".." + std::to_string(int(kMaxThrowDensity)));
}

}  // namespace

double default_half_size(granular::Int3 size) {
  const int smallest = std::min({size.x, size.y, size.z});
  return std::clamp(std::round(smallest / 32.0), kMinThrowHalfSize, kMaxThrowHalfSize);
}

double throw_speed(granular::Int3 size, double cell_metres) {
  if (size.x <= 0 || size.y <= 0 || size.z <= 0)
    throw std::invalid_argument("throw_speed: the grid " + std::to_string(size.x) + " x " + std::to_string(size.y) +
                                " x " + std::to_string(size.z) + " is empty");
  check_positive(cell_metres, "throw_speed: cell_metres");
  const double width = std::min(size.x, size.y) * cell_metres;
  const double fall_seconds = std::sqrt(2 * size.z * cell_metres / kGravity);
  return width / fall_seconds;
}

std::string density_effect(double density) {
  if (density < 1000) return "floats in water and sand";
  if (density < 1600) return "sinks in water, floats in sand";
  return "sinks in water and sand";
}

double bounding_radius(const ThrowChoice& choice) {
  return choice.shape == granular::BodyShape::Box ? choice.half_size * std::sqrt(3.0) : choice.half_size;
}

const char* shape_name(granular::BodyShape shape) {
  switch (shape) {
    case granular::BodyShape::Box:
      return "box";
    case granular::BodyShape::Sphere:
      return "ball";
    case granular::BodyShape::Capsule:
      return "capsule";
  }
  return "body";
}

std::optional<granular::BodyDef> aim_throw(const ThrowChoice& choice, granular::Vec3 origin, granular::Vec3 direction,
                                           granular::Int3 size, double speed_mps, double cell_metres,
                                           double tick_seconds) {
  check_choice(choice);
  if (!finite(origin)) throw std::invalid_argument("throw: the camera's position is not finite");
  const double length = std::sqrt(direction.x * direction.x + direction.y * direction.y + direction.z * direction.z);
  if (!finite(direction) || !(length > 0)) throw std::invalid_argument("throw: the view ray has no direction");
  check_positive(speed_mps, "throw: speed");
  check_positive(cell_metres, "throw: cell_metres");
  check_positive(tick_seconds, "throw: tick_seconds");
  const granular::Vec3 d{direction.x / length, direction.y / length, direction.z / length};

  // The centres whose bounding sphere lies a cell or more inside the grid: a box per axis, clipped
  // against the ray from just in front of the eye (slab method).
  const double inset = bounding_radius(choice) + 1;
  double t_in = inset, t_out = std::numeric_limits<double>::infinity();
  const double o[3] = {origin.x, origin.y, origin.z}, v[3] = {d.x, d.y, d.z};
  const int n[3] = {size.x, size.y, size.z};
  for (int axis = 0; axis < 3; ++axis) {
    const double lo = inset, hi = n[axis] - inset;
    if (lo > hi) return std::nullopt;  // the grid is too small for the body
    if (v[axis] == 0) {
      if (o[axis] < lo || o[axis] > hi) return std::nullopt;
      continue;
    }
    double t0 = (lo - o[axis]) / v[axis], t1 = (hi - o[axis]) / v[axis];
    if (t0 > t1) std::swap(t0, t1);
    t_in = std::max(t_in, t0);
    t_out = std::min(t_out, t1);
  }
  if (t_in > t_out) return std::nullopt;

  granular::BodyDef def;
  def.shape = choice.shape;
  def.half_extents = {choice.half_size, choice.half_size, choice.half_size};
  def.radius = choice.half_size;
  def.density = choice.density;
  def.pose.position = {origin.x + t_in * d.x, origin.y + t_in * d.y, origin.z + t_in * d.z};
  const double cells_per_tick = speed_mps * tick_seconds / cell_metres;
  def.pose.velocity = {d.x * cells_per_tick, d.y * cells_per_tick, d.z * cells_per_tick};
  return def;
}

}  // namespace viewer
