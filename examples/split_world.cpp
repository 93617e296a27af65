/// @file split_world.cpp
/// A world split into z-slabs (granular::DistributedWorld): here four ranks that are threads of this
/// process (granular::run_local_ranks); under MPI each rank is a process and passes a
/// granular::MpiCommunicator (granular::mpi) instead. Every rank runs the same code; the split
/// world ends with the hash of one World of the whole grid, which the program checks (exit 1 if
/// not), so the test suite runs it as a check.

#include <granular/distributed/distributed_world.hpp>
#include <granular/distributed/local_group.hpp>
#include <granular/granular.hpp>

#include <cstdio>

int main() {
  granular::WorldDef def;
  def.size = {64, 64, 128};
  def.backend = granular::BackendKind::Cpu;
  def.threads = 1;  // per rank
  granular::Grid initial(def.size);
  const auto shape = [](auto& world) {  // a World and a DistributedWorld take the same tools
    world.paint(granular::Box{{0, 0, 0}, {64, 64, 2}}, granular::Material::Solid);
    world.paint(granular::Box{{16, 16, 70}, {48, 48, 110}}, granular::Material::Granular);
  };

  std::uint64_t split_hash = 0;
  granular::run_local_ranks(4, [&](granular::Communicator& comm) {
    granular::DistributedWorld world(def, comm, initial);  // each rank keeps its slab and halo
    shape(world);
    for (int frame = 0; frame < 60; ++frame) {
      world.step(1);  // halos first, then each slab one tick
      if (frame == 30) world.dig({{32, 32, 64}, 8.0});  // across the slab boundary at z = 64
    }
    const std::uint64_t hash = world.hash();  // collective: every rank gets the whole world's hash
    if (comm.rank() == 0) split_hash = hash;
  });

  granular::World whole(def, initial);
  shape(whole);
  for (int frame = 0; frame < 60; ++frame) {
    whole.step(1);
    if (frame == 30) whole.dig({{32, 32, 64}, 8.0});
  }
  std::printf("4 slabs: hash %016llx; one World: hash %016llx\n", static_cast<unsigned long long>(split_hash),
              static_cast<unsigned long long>(whole.hash()));
  return split_hash == whole.hash() ? 0 : 1;
}
