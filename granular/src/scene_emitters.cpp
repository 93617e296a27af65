#include <algorithm>
#include <cmath>
#include <string>

#include "granular/errors.hpp"
#include "granular/scene.hpp"
#include "granular/world.hpp"

namespace granular {

namespace {

/// "emitters[i] (centre (x, y, z), radius r)" for messages.
std::string emitter_name(std::size_t i, const Emitter& e) {
  return "run_emitters: emitter " + std::to_string(i) + " (centre (" + std::to_string(e.center.x) + ", " +
         std::to_string(e.center.y) + ", " + std::to_string(e.center.z) + "), radius " + std::to_string(e.radius) + ")";
}

/// Throws InvalidArgument for an emitter World::pour would refuse in a grid of `size`: the same
/// conditions, checked before any emitter pours.
void check_emitter(std::size_t i, const Emitter& e, Int3 size) {
  if (!is_valid_material_value(to_cell(e.material)))
    throw InvalidArgument(emitter_name(i, e) + ": material value " + std::to_string(unsigned(to_cell(e.material))) +
                          " is not a valid state (0..7)");
  if (e.material == Material::Void) throw InvalidArgument(emitter_name(i, e) + ": pours void");
  if (e.rate < 0) throw InvalidArgument(emitter_name(i, e) + ": rate " + std::to_string(e.rate) + " must be >= 0");
  const double c[3] = {e.center.x, e.center.y, e.center.z};
  const int n[3] = {size.x, size.y, size.z};
  if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2]))
    throw InvalidArgument(emitter_name(i, e) + ": the centre is not finite");
  if (!std::isfinite(e.radius) || e.radius <= 0)
    throw InvalidArgument(emitter_name(i, e) + ": the radius must be > 0");
  for (int a = 0; a < 3; ++a) {
    // The cells whose centres the sphere can reach along this axis, as World::pour computes them.
    const double lo = std::ceil(c[a] - e.radius - 0.5), hi = std::floor(c[a] + e.radius - 0.5) + 1;
    if (lo >= hi || std::max(lo, 0.0) >= std::min(hi, double(n[a])))
      throw InvalidArgument(emitter_name(i, e) + ": covers no cell of the " + to_string(size) + " grid");
  }
}

}  // namespace

void run_emitters(World& world, const std::vector<Emitter>& emitters) {
  const std::uint64_t tick = world.tick();
  auto active = [tick](const Emitter& e) { return tick >= e.start && tick < e.stop; };
  for (std::size_t i = 0; i < emitters.size(); ++i)
    if (active(emitters[i])) check_emitter(i, emitters[i], world.size());
  for (const Emitter& e : emitters)
    if (active(e)) world.pour(e.center, e.radius, e.material, e.rate);
}

}  // namespace granular
