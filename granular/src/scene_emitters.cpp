#include "granular/scene.hpp"
#include "granular/world.hpp"

namespace granular {

void run_emitters(World& world, const std::vector<Emitter>& emitters) {
  const std::uint64_t tick = world.tick();
  for (const Emitter& e : emitters)
    if (tick >= e.start && tick < e.stop) world.pour(e.center, e.radius, e.material, e.rate);
}

}  // namespace granular
