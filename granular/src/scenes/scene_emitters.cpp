#include <string>

#include "granular/distributed/distributed_world.hpp"
#include "granular/errors.hpp"
#include "granular/scene.hpp"
#include "granular/world.hpp"
#include "world/tool_region.hpp"

namespace granular {

namespace {

/// "emitters[i] (centre (x, y, z), radius r)" for messages.
std::string emitter_name(std::size_t i, const Emitter& e) {
  return "run_emitters: emitter " + std::to_string(i) + " (centre (" + std::to_string(e.center.x) + ", " +
         std::to_string(e.center.y) + ", " + std::to_string(e.center.z) + "), radius " + std::to_string(e.radius) + ")";
}

/// run_emitters for a World or a DistributedWorld, which have the same tick(), size() and pour().
template <class W>
MaterialCounts run_emitters_of(W& world, const std::vector<Emitter>& emitters) {
  const std::uint64_t tick = world.tick();
  auto active = [tick](const Emitter& e) { return tick >= e.start && tick < e.stop; };
  for (std::size_t i = 0; i < emitters.size(); ++i)
    if (active(emitters[i])) {
      const Emitter& e = emitters[i];
      try {
        bool clipped = false;
        check_pour(Sphere{e.center, e.radius}, e.material, e.rate, world.size(), clipped);
      } catch (const InvalidArgument& error) {
        throw InvalidArgument(emitter_name(i, e) + ": " + error.what());
      }
    }
  MaterialCounts poured{};
  for (const Emitter& e : emitters)
    if (active(e)) poured[to_cell(e.material)] += std::uint64_t(world.pour(e.center, e.radius, e.material, e.rate).cells_changed);
  return poured;
}

}  // namespace

MaterialCounts run_emitters(World& world, const std::vector<Emitter>& emitters) { return run_emitters_of(world, emitters); }

MaterialCounts run_emitters(DistributedWorld& world, const std::vector<Emitter>& emitters) {
  return run_emitters_of(world, emitters);
}

MaterialCounts counts_after_pouring(MaterialCounts before, const MaterialCounts& poured) {
  for (int m = 0; m < kMaterialCount; ++m) {
    before[m] += poured[m];
    before[to_cell(Material::Void)] -= poured[m];
  }
  return before;
}

}  // namespace granular
