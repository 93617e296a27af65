/// @file bench_bodies.cpp
/// What bodies cost a tick (World::add_body): two worlds of the same scene, one with B bodies
/// wandering through it and one without, stepped one tick at a time, alternately, so that the
/// difference of their times is what the bodies add (writing them into the grid, pushing the sand,
/// the reports, and the step of the sand they stir). The scene: an N x N x N/2 world, a bed of sand a
/// quarter of N deep on one half and a pool of water as deep on the other, a wall between; the bodies
/// (boxes, spheres and capsules of N/32 half size) wade through the surfaces of both, each heading
/// somewhere new every 25 ticks at up to 0.5 cells a tick, as crates pushed about and characters
/// walking do.
///
///   bench_bodies [--backend cpu|cuda] [--n N] [--bodies B] [--half H] [--ticks T] [--threads J]
///                [--rules NAME]
///
/// --half sets the bodies' half size in cells (default N/32, at least 2).
///
/// Prints ms per tick with and without the bodies, their difference, and the real-time factor
/// (simulated seconds per wall second) of the world with bodies; then, per tick, the phases of the
/// world with bodies (World::profile: the step of the cells, and the bodies' own work) and the
/// bricks each world stepped; and the hash of the world with bodies, the same on every backend and
/// thread count, so that two builds can be checked to write the bodies alike. Figures in bench/RESULTS.md.

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "granular/body.hpp"
#include "granular/errors.hpp"
#include "granular/step_profile.hpp"
#include "granular/time_scale.hpp"
#include "granular/world.hpp"
#include "timed_step.hpp"

namespace {

using namespace granular;

struct Options {
  std::string backend = "cpu";
  int n = 128;
  int bodies = 16;
  double half = 0;  ///< the bodies' half size; 0: N / 32
  int ticks = 200;
  int threads = 0;
  std::string rules = WorldDef{}.rules;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw InvalidArgument("bench_bodies: " + a + " needs a value");
      return argv[++i];
    };
    if (a == "--backend")
      o.backend = value();
    else if (a == "--n")
      o.n = std::atoi(value().c_str());
    else if (a == "--bodies")
      o.bodies = std::atoi(value().c_str());
    else if (a == "--ticks")
      o.ticks = std::atoi(value().c_str());
    else if (a == "--half")
      o.half = std::atof(value().c_str());
    else if (a == "--threads")
      o.threads = std::atoi(value().c_str());
    else if (a == "--rules")
      o.rules = value();
    else
      throw InvalidArgument("bench_bodies: unknown option " + a);
  }
  if (o.backend != "cpu" && o.backend != "cuda")
    throw InvalidArgument("bench_bodies: --backend " + o.backend + "; use cpu or cuda");
  if (o.n < 32 || o.n > 2048) throw InvalidArgument("bench_bodies: --n " + std::to_string(o.n) + "; use 32..2048");
  if (o.bodies < 0 || o.bodies > int(kMaxBodies))
    throw InvalidArgument("bench_bodies: --bodies " + std::to_string(o.bodies) + "; use 0.." +
                          std::to_string(kMaxBodies));
  if (o.half < 0 || o.half > kMaxBodyHalfSize)
    throw InvalidArgument("bench_bodies: --half " + std::to_string(o.half) + "; use 0 (N/32) or up to 64");
  if (o.ticks < 1) throw InvalidArgument("bench_bodies: --ticks " + std::to_string(o.ticks) + "; use 1 or more");
  return o;
}

World scene(const Options& o) {
  WorldDef def;
  def.size = {o.n, o.n, o.n / 2};
  def.backend = o.backend == "cuda" ? BackendKind::Cuda : BackendKind::Cpu;
  def.threads = o.threads;
  def.rules = o.rules;
  World w(def);
  w.paint(Box{{0, 0, 0}, {o.n / 2 - 1, o.n, o.n / 4}}, Material::Granular);
  w.paint(Box{{o.n / 2 - 1, 0, 0}, {o.n / 2 + 1, o.n, o.n / 4 + 4}}, Material::Solid);
  w.paint(Box{{o.n / 2 + 1, 0, 0}, {o.n, o.n, o.n / 4}}, Material::Liquid);
  return w;
}

}  // namespace

int main(int argc, char** argv) try {
  const Options o = parse(argc, argv);
  World with = scene(o), without = scene(o);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<BodyId> ids;
  const double half = o.half > 0 ? o.half : std::max(2.0, o.n / 32.0), edge = 2 * half;
  for (int i = 0; i < o.bodies; ++i) {
    BodyDef def;
    def.shape = BodyShape(i % 3);
    def.half_extents = {half, half, half};
    def.radius = half;
    def.half_length = half;
    const double side = i % 2 == 0 ? 0 : o.n / 2.0;  // sand, water
    def.pose.position = {side + edge + (o.n / 2.0 - 2 * edge) * unit(rng), edge + (o.n - 2 * edge) * unit(rng),
                         o.n / 4.0 + half * (unit(rng) - 0.5)};
    ids.push_back(with.add_body(def));
  }
  double with_s = 0, without_s = 0;
  StepProfile phases;  // the world with bodies, summed over the ticks
  std::uint64_t awake = 0, awake_without = 0;  // bricks stepped, summed over the ticks
  for (int t = 0; t < o.ticks; ++t) {
    if (t % 25 == 0)
      for (const BodyId id : ids) {
        BodyPose pose = with.body_pose(id);
        pose.velocity = {unit(rng) - 0.5, unit(rng) - 0.5, 0.25 * (unit(rng) - 0.5)};
        const double low = pose.position.x < o.n / 2.0 ? 0 : o.n / 2.0;  // its half
        if (pose.position.x < low + 2 * edge) pose.velocity.x = 0.5;
        if (pose.position.x > low + o.n / 2.0 - 2 * edge) pose.velocity.x = -0.5;
        if (pose.position.y < 2 * edge) pose.velocity.y = 0.5;
        if (pose.position.y > o.n - 2 * edge) pose.velocity.y = -0.5;
        if (pose.position.z < o.n / 4.0 - half) pose.velocity.z = 0.25;
        if (pose.position.z > o.n / 4.0 + half) pose.velocity.z = -0.25;
        with.set_body_pose(id, pose);
      }
    with_s += bench::timed_step(with, 1);
    without_s += bench::timed_step(without, 1);
    const StepProfile& p = with.profile();
    phases.step += p.step;
    phases.bodies += p.bodies;
    phases.bodies_shapes += p.bodies_shapes;
    phases.bodies_read += p.bodies_read;
    phases.bodies_stamp += p.bodies_stamp;
    phases.bodies_write += p.bodies_write;
    phases.bodies_forces += p.bodies_forces;
    awake += with.activity().brick_ticks;
    awake_without += without.activity().brick_ticks;
  }
  const double tick_s = tick_seconds(with.rules(), with.def().cell_metres);
  const double with_ms = 1e3 * with_s / o.ticks, without_ms = 1e3 * without_s / o.ticks;
  std::printf("bench_bodies: %s (%s), %dx%dx%d, %s, %d bodies of half size %g, %d ticks\n", o.backend.c_str(),
              with.backend_description().c_str(), o.n, o.n, o.n / 2, o.rules.c_str(), o.bodies, half, o.ticks);
  std::printf("  with bodies %.3f ms/tick (%.2fx real time), without %.3f ms/tick, bodies add %.3f ms/tick\n", with_ms,
              tick_s * 1e3 / with_ms, without_ms, with_ms - without_ms);
  const double per_tick = 1.0 / o.ticks;
  std::printf(
      "  with bodies, per tick: step %.3f ms (%.0f bricks awake; %.0f without), bodies %.3f ms: shapes %.3f, "
      "read %.3f, stamps %.3f, write %.3f, forces %.3f%s\n",
      phases.step * per_tick, double(awake) * per_tick, double(awake_without) * per_tick, phases.bodies * per_tick,
      phases.bodies_shapes * per_tick, phases.bodies_read * per_tick, phases.bodies_stamp * per_tick,
      phases.bodies_write * per_tick, phases.bodies_forces * per_tick,
      o.backend == "cuda" ? " (found while the device steps: within the step, not the bodies)" : "");
  std::printf("  the world with bodies ends with hash %016llx\n", static_cast<unsigned long long>(with.hash()));
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "%s\n", e.what());
  return 1;
}
