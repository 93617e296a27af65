/// @file backend_choice.cpp
/// Which backends a program has is what it links: granular::granular is the core plus the CUDA
/// backend when granular was built with CUDA; granular::core alone is the CPU backend. This program
/// says which it has, makes an auto world, and makes a world whose backend its own factory creates
/// (WorldDef::backend_factory). Run as `backend_choice cuda-linked` or `backend_choice cpu-only`;
/// exits non-zero when the program's backends are not the ones named, or a world is not what it
/// should be.

#include <granular/extend/backend.hpp>
#include <granular/extend/backend_registry.hpp>
#include <granular/granular.hpp>

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
  const std::string expect = argc > 1 ? argv[1] : "";
  if (expect != "cuda-linked" && expect != "cpu-only") {
    std::fprintf(stderr, "usage: backend_choice cuda-linked|cpu-only\n");
    return 2;
  }
  bool ok = true;
  const bool cuda_linked = granular::registered_backend(granular::BackendKind::Cuda).has_value();
  std::printf("cuda backend linked: %s\n", cuda_linked ? "yes" : "no");
  ok = ok && cuda_linked == (expect == "cuda-linked");

  granular::WorldDef def;  // backend auto: CUDA when linked and a device is usable, else the CPU
  def.size = {32, 32, 32};
  def.threads = 2;
  granular::World world(def);
  world.paint(granular::Box{{8, 8, 16}, {24, 24, 28}}, granular::Material::Granular);
  world.step(40);
  std::printf("auto world: %s\n", world.backend_description().c_str());
  for (const std::string& notice : world.notices()) std::printf("  notice: %s\n", notice.c_str());
  if (!cuda_linked) {
    bool told = false;  // auto said why it uses the CPU
    for (const std::string& notice : world.notices()) told = told || notice.find("no CUDA backend linked") != std::string::npos;
    ok = ok && told && world.backend() == granular::BackendKind::Cpu && !granular::cuda_device_uuid();
  }

  // The game's own choice: here the CPU backend on one thread, whatever WorldDef::backend says.
  int created = 0;
  granular::WorldDef own = def;
  own.backend = granular::BackendKind::Cuda;  // not used: the factory wins
  own.backend_factory = [&created](const granular::BackendCreateInfo& info) {
    ++created;
    granular::BackendCreateInfo one_thread = info;
    one_thread.threads = 1;
    return granular::make_cpu_backend(one_thread);
  };
  granular::World mine(own);
  mine.paint(granular::Box{{8, 8, 16}, {24, 24, 28}}, granular::Material::Granular);
  mine.step(40);
  const bool same = mine.hash() == world.hash();
  std::printf("own factory: %s, created %d time(s), hash %s the auto world's\n", mine.backend_description().c_str(),
              created, same ? "equal to" : "DIFFERENT from");
  ok = ok && created == 1 && mine.backend_description() == "cpu (1 thread)" && same;
  std::printf("%s\n", ok ? "backends as expected" : "backends NOT as expected");
  return ok ? 0 : 1;
}
