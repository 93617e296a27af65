#include "settle.hpp"

namespace granular::accuracy {

SettleResult settle(World& world, std::uint64_t max_ticks) {
  SettleResult r;
  std::uint64_t previous = world.hash();
  std::uint64_t done = 0;
  while (done < max_ticks) {
    world.step(8);
    done += 8;
    const std::uint64_t h = world.hash();
    if (h == previous) {
      r.settled = true;
      r.ticks = done - 8;
      return r;
    }
    previous = h;
  }
  r.ticks = done;
  return r;
}

}  // namespace granular::accuracy
