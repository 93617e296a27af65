#include "session/world_files.hpp"

#include "granular/extend/hex.hpp"
#include "granular/world_snapshot.hpp"

namespace viewer {

std::string world_state_text(const granular::World& world) {
  const granular::Int3 s = world.size();
  return std::to_string(std::uint64_t(s.x) * std::uint64_t(s.y) * std::uint64_t(s.z)) + " cells, tick " +
         std::to_string(world.tick()) + ", hash " + granular::hex64(world.hash());
}

std::string save_world(const granular::World& world, const std::string& path) {
  granular::save_snapshot(world.capture(), path);
  return "saved: " + path + " (" + world_state_text(world) + ")";
}

std::string loaded_line(const granular::World& world, const std::string& path) {
  return "loaded: " + path + " (" + world_state_text(world) + ")";
}

}  // namespace viewer
