// Tests of the engine loop (engine/): the fixed-timestep accumulator, its clamps, and the order
// in which EngineLoop calls subsystems. Driven by ManualClock, so every value is exact.

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "granular/engine/clock.hpp"
#include "granular/engine/engine_loop.hpp"
#include "granular/engine/fixed_timestep.hpp"
#include "granular/engine/subsystem.hpp"

namespace {

using granular::engine::EngineLoop;
using granular::engine::FixedTimestep;
using granular::engine::FixedTimestepConfig;
using granular::engine::FrameStats;
using granular::engine::FrameTicks;
using granular::engine::ManualClock;

constexpr double kHz60 = 1.0 / 60.0;

/// Records every call into a log shared with other recorders, plus the arguments it got.
class Recorder : public granular::engine::Subsystem {
 public:
  Recorder(std::string name, std::vector<std::string>& log)
      : Subsystem(std::move(name)), log_(log) {}
  void fixed_update(double dt) override {
    log_.push_back(std::string(name()) + ".fixed");
    dts.push_back(dt);
  }
  void update(double frame_seconds) override {
    log_.push_back(std::string(name()) + ".update");
    frame_times.push_back(frame_seconds);
  }
  void render(double alpha) override {
    log_.push_back(std::string(name()) + ".render");
    alphas.push_back(alpha);
  }
  std::vector<double> dts;
  std::vector<double> frame_times;
  std::vector<double> alphas;

 private:
  std::vector<std::string>& log_;
};

/// Calls request_stop() on its loop from its n-th update().
class Stopper : public granular::engine::Subsystem {
 public:
  Stopper(EngineLoop& loop, int stop_after_updates)
      : Subsystem("stopper"), loop_(loop), stop_after_(stop_after_updates) {}
  void update(double) override {
    if (++updates == stop_after_) {
      loop_.request_stop();
    }
  }
  int updates = 0;

 private:
  EngineLoop& loop_;
  int stop_after_;
};

/// Tries to add a subsystem to its own loop from inside a frame.
class Adder : public granular::engine::Subsystem {
 public:
  Adder(EngineLoop& loop, granular::engine::Subsystem& other) : Subsystem("adder"), loop_(loop), other_(other) {}
  void update(double) override { loop_.add(other_); }

 private:
  EngineLoop& loop_;
  granular::engine::Subsystem& other_;
};

/// The message of the std::invalid_argument `f` throws; fails the test when it throws nothing.
template <typename F>
std::string invalid_argument_message(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  FAIL("expected std::invalid_argument");
  return {};
}

/// Runs one frame `seconds` after the previous one.
FrameStats frame_after(ManualClock& clock, EngineLoop& loop, double seconds) {
  clock.advance(seconds);
  return loop.run_frame();
}

}  // namespace

TEST_CASE("FixedTimestep: one frame of 1/60 s at 60 Hz is exactly one tick") {
  FixedTimestep step;
  CHECK(step.tick_seconds() == doctest::Approx(kHz60).epsilon(1e-15));
  for (int i = 0; i < 600; ++i) {
    const FrameTicks t = step.advance(kHz60);
    REQUIRE(t.ticks == 1);
    CHECK(t.alpha == 0.0);
    CHECK(t.dropped_seconds == 0.0);
    CHECK(t.frame_seconds == kHz60);
  }
  CHECK(step.accumulator_seconds() == 0.0);
}

TEST_CASE("FixedTimestep: a zero frame runs nothing") {
  FixedTimestep step;
  const FrameTicks t = step.advance(0.0);
  CHECK(t.ticks == 0);
  CHECK(t.alpha == 0.0);
  CHECK(t.dropped_seconds == 0.0);
}

TEST_CASE("FixedTimestep: half-tick frames alternate 0 and 1 ticks with alpha 0.5 and 0") {
  FixedTimestep step;
  for (int i = 0; i < 10; ++i) {
    const FrameTicks a = step.advance(kHz60 / 2);
    CHECK(a.ticks == 0);
    CHECK(a.alpha == doctest::Approx(0.5));
    const FrameTicks b = step.advance(kHz60 / 2);
    CHECK(b.ticks == 1);
    CHECK(b.alpha == doctest::Approx(0.0));
  }
}

TEST_CASE("FixedTimestep: ten frames of 1/600 s accumulate into exactly one tick at 60 Hz") {
  FixedTimestep step;
  for (int i = 1; i <= 9; ++i) {
    const FrameTicks t = step.advance(1.0 / 600.0);
    CHECK(t.ticks == 0);
    CHECK(t.alpha == doctest::Approx(i / 10.0));
  }
  const FrameTicks tenth = step.advance(1.0 / 600.0);
  CHECK(tenth.ticks == 1);
  CHECK(tenth.alpha == doctest::Approx(0.0).epsilon(1e-9));
  CHECK(tenth.alpha >= 0.0);
}

TEST_CASE("FixedTimestep: alpha is the leftover fraction of a tick") {
  FixedTimestep step;
  FrameTicks t = step.advance(0.025);  // 1.5 ticks at 60 Hz
  CHECK(t.ticks == 1);
  CHECK(t.alpha == doctest::Approx(0.5));
  t = step.advance(0.025);  // 0.5 + 1.5 = 2 ticks
  CHECK(t.ticks == 2);
  CHECK(t.alpha == doctest::Approx(0.0).epsilon(1e-9));
  t = step.advance(0.02);  // 1.2 ticks
  CHECK(t.ticks == 1);
  CHECK(t.alpha == doctest::Approx(0.2));
  CHECK(step.accumulator_seconds() == doctest::Approx(0.2 * kHz60));
}

TEST_CASE("FixedTimestep: alpha stays in [0, 1) and time is conserved over uneven frames") {
  FixedTimestep step(FixedTimestepConfig{.tick_rate_hz = 50.0, .max_ticks_per_frame = 6,
                                         .max_frame_seconds = 0.1});
  const double frames[] = {0.013, 0.0, 0.0199999, 0.02, 0.021, 0.07, 0.099, 0.1, 0.003, 0.057};
  double owed_before = 0.0;
  int total_ticks = 0;
  for (double f : frames) {
    const FrameTicks t = step.advance(f);
    CHECK(t.alpha >= 0.0);
    CHECK(t.alpha < 1.0);
    CHECK(t.ticks >= 0);
    CHECK(t.ticks <= 6);
    CHECK(t.dropped_seconds == 0.0);  // no frame exceeds 0.1 s nor 6 ticks
    CHECK(t.alpha == doctest::Approx(step.accumulator_seconds() / 0.02));
    const double conserved = t.ticks * 0.02 + t.dropped_seconds +
                             (step.accumulator_seconds() - owed_before);
    CHECK(conserved == doctest::Approx(f).epsilon(1e-12));
    owed_before = step.accumulator_seconds();
    total_ticks += t.ticks;
  }
  // 0.4029999 s in all: 20 ticks of 0.02 s and 0.0029999 s left.
  CHECK(total_ticks == 20);
  CHECK(step.accumulator_seconds() == doctest::Approx(0.0029999));
}

TEST_CASE("FixedTimestep: spiral-of-death clamp on a 1 s frame") {
  FixedTimestep step;  // 60 Hz, 8 ticks, 0.25 s
  const FrameTicks t = step.advance(1.0);
  CHECK(t.ticks == 8);
  CHECK(t.frame_seconds == 0.25);
  // 0.75 s over max_frame_seconds, then 15 ticks owed in 0.25 s of which 7 dropped.
  CHECK(t.dropped_seconds == doctest::Approx(0.75 + 7.0 / 60.0));
  CHECK(t.alpha == doctest::Approx(0.0).epsilon(1e-9));
  CHECK(step.accumulator_seconds() < 1e-12);

  // The dropped ticks are not queued: the next ordinary frame runs one tick.
  const FrameTicks next = step.advance(kHz60);
  CHECK(next.ticks == 1);
  CHECK(next.dropped_seconds == 0.0);
}

TEST_CASE("FixedTimestep: the tick clamp drops whole ticks and keeps the fraction") {
  FixedTimestep step(FixedTimestepConfig{.tick_rate_hz = 60.0, .max_ticks_per_frame = 8,
                                         .max_frame_seconds = 1.0});
  const FrameTicks t = step.advance(0.21);  // 12.6 ticks owed
  CHECK(t.ticks == 8);
  CHECK(t.frame_seconds == 0.21);
  CHECK(t.dropped_seconds == doctest::Approx(4.0 / 60.0));
  CHECK(t.alpha == doctest::Approx(0.6));
  CHECK(t.ticks * kHz60 + t.dropped_seconds + step.accumulator_seconds() ==
        doctest::Approx(0.21).epsilon(1e-12));
}

TEST_CASE("FixedTimestep: an infinite max_frame_seconds disables only the frame clamp") {
  FixedTimestep step(FixedTimestepConfig{.tick_rate_hz = 10.0, .max_ticks_per_frame = 3,
                                         .max_frame_seconds =
                                             std::numeric_limits<double>::infinity()});
  const FrameTicks t = step.advance(100.05);  // 1000.5 ticks owed
  CHECK(t.ticks == 3);
  CHECK(t.frame_seconds == 100.05);
  CHECK(t.dropped_seconds == doctest::Approx(99.7));
  CHECK(t.alpha == doctest::Approx(0.5).epsilon(1e-9));
}

TEST_CASE("FixedTimestep: invalid configs and frames throw std::invalid_argument naming the field") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();

  std::string m = invalid_argument_message([] { FixedTimestep s(FixedTimestepConfig{.tick_rate_hz = 0.0}); });
  CHECK(m.find("tick_rate_hz") != std::string::npos);
  CHECK(m.find("got 0") != std::string::npos);
  m = invalid_argument_message([] { FixedTimestep s(FixedTimestepConfig{.tick_rate_hz = -30.0}); });
  CHECK(m.find("tick_rate_hz") != std::string::npos);
  CHECK(m.find("-30") != std::string::npos);
  m = invalid_argument_message([&] { FixedTimestep s(FixedTimestepConfig{.tick_rate_hz = nan}); });
  CHECK(m.find("tick_rate_hz") != std::string::npos);
  CHECK(m.find("nan") != std::string::npos);
  m = invalid_argument_message([&] { FixedTimestep s(FixedTimestepConfig{.tick_rate_hz = inf}); });
  CHECK(m.find("tick_rate_hz") != std::string::npos);
  CHECK(m.find("inf") != std::string::npos);

  m = invalid_argument_message([] { FixedTimestep s(FixedTimestepConfig{.max_ticks_per_frame = 0}); });
  CHECK(m.find("max_ticks_per_frame") != std::string::npos);
  CHECK(m.find("got 0") != std::string::npos);
  m = invalid_argument_message([] { FixedTimestep s(FixedTimestepConfig{.max_ticks_per_frame = -5}); });
  CHECK(m.find("max_ticks_per_frame") != std::string::npos);
  CHECK(m.find("-5") != std::string::npos);

  m = invalid_argument_message([] { FixedTimestep s(FixedTimestepConfig{.max_frame_seconds = 0.0}); });
  CHECK(m.find("max_frame_seconds") != std::string::npos);
  m = invalid_argument_message([&] { FixedTimestep s(FixedTimestepConfig{.max_frame_seconds = nan}); });
  CHECK(m.find("max_frame_seconds") != std::string::npos);

  FixedTimestep step;
  CHECK_THROWS_AS(step.advance(-0.001), std::invalid_argument);
  CHECK_THROWS_AS(step.advance(nan), std::invalid_argument);
  CHECK_THROWS_AS(step.advance(inf), std::invalid_argument);
  CHECK(step.accumulator_seconds() == 0.0);

  // A rejected set_config leaves the old config in place.
  CHECK_THROWS_AS(step.set_config(FixedTimestepConfig{.tick_rate_hz = 0.0}), std::invalid_argument);
  CHECK(step.config().tick_rate_hz == 60.0);
  CHECK(step.advance(kHz60).ticks == 1);

  ManualClock clock;
  CHECK_THROWS_AS(EngineLoop(clock, FixedTimestepConfig{.max_ticks_per_frame = 0}),
                  std::invalid_argument);
}

TEST_CASE("EngineLoop: the first frame has a zero delta, then 1/60 s frames give one tick each") {
  ManualClock clock(123.0);  // the epoch does not matter
  EngineLoop loop(clock);
  std::vector<std::string> log;
  Recorder sim("sim", log);
  loop.add(sim);

  clock.advance(5.0);  // time before the first frame is not simulated
  const FrameStats first = loop.run_frame();
  CHECK(first.frame == 0);
  CHECK(first.measured_seconds == 0.0);
  CHECK(first.ticks == 0);
  CHECK(first.dropped_seconds == 0.0);
  CHECK(log == std::vector<std::string>{"sim.update", "sim.render"});

  for (int i = 1; i <= 120; ++i) {
    const FrameStats f = frame_after(clock, loop, kHz60);
    CHECK(f.frame == static_cast<std::uint64_t>(i));
    REQUIRE(f.ticks == 1);
  }
  CHECK(loop.stats().frames == 121);
  CHECK(loop.stats().ticks == 120);
  CHECK(loop.stats().dropped_seconds == 0.0);
  CHECK(loop.stats().simulated_seconds == doctest::Approx(2.0));
  CHECK(sim.dts.size() == 120);
  for (double dt : sim.dts) {
    CHECK(dt == doctest::Approx(kHz60).epsilon(1e-15));
  }
  CHECK(sim.frame_times.size() == 121);
  CHECK(sim.frame_times[0] == 0.0);
  CHECK(sim.frame_times[1] == doctest::Approx(kHz60));
  CHECK(loop.last_frame().frame == 120);
}

TEST_CASE("EngineLoop: ten frames of 1/600 s run exactly one tick, on the tenth") {
  ManualClock clock;
  EngineLoop loop(clock);
  std::vector<std::string> log;
  Recorder sim("sim", log);
  loop.add(sim);
  loop.run_frame();
  for (int i = 1; i <= 9; ++i) {
    const FrameStats f = frame_after(clock, loop, 1.0 / 600.0);
    CHECK(f.ticks == 0);
    CHECK(f.alpha == doctest::Approx(i / 10.0));
  }
  CHECK(frame_after(clock, loop, 1.0 / 600.0).ticks == 1);
  CHECK(loop.stats().ticks == 1);
  CHECK(sim.dts.size() == 1);
  CHECK(sim.alphas.size() == 11);
  CHECK(sim.alphas[5] == doctest::Approx(0.5));
}

TEST_CASE("EngineLoop: render receives the alpha of the frame") {
  ManualClock clock;
  EngineLoop loop(clock);
  std::vector<std::string> log;
  Recorder sim("sim", log);
  loop.add(sim);
  loop.run_frame();
  const FrameStats a = frame_after(clock, loop, 0.025);
  CHECK(a.ticks == 1);
  CHECK(a.alpha == doctest::Approx(0.5));
  const FrameStats b = frame_after(clock, loop, 0.03);  // 0.5 + 1.8 ticks
  CHECK(b.ticks == 2);
  CHECK(b.alpha == doctest::Approx(0.3));
  REQUIRE(sim.alphas.size() == 3);
  CHECK(sim.alphas[0] == 0.0);
  CHECK(sim.alphas[1] == a.alpha);
  CHECK(sim.alphas[2] == b.alpha);
}

TEST_CASE("EngineLoop: spiral-of-death clamp on a 1 s frame") {
  ManualClock clock;
  EngineLoop loop(clock);
  std::vector<std::string> log;
  Recorder sim("sim", log);
  loop.add(sim);
  loop.run_frame();
  const FrameStats f = frame_after(clock, loop, 1.0);
  CHECK(f.measured_seconds == 1.0);
  CHECK(f.ticks == 8);
  CHECK(f.frame_seconds == 0.25);
  CHECK(f.dropped_seconds == doctest::Approx(0.75 + 7.0 / 60.0));
  CHECK(sim.dts.size() == 8);
  REQUIRE(sim.frame_times.size() == 2);
  CHECK(sim.frame_times[1] == 0.25);  // update() gets the clamped frame time
  CHECK(loop.stats().dropped_seconds == doctest::Approx(0.75 + 7.0 / 60.0));

  // Nothing was queued: the next normal frame is one tick.
  CHECK(frame_after(clock, loop, kHz60).ticks == 1);
  CHECK(loop.stats().ticks == 9);
  CHECK(loop.stats().dropped_seconds == doctest::Approx(0.75 + 7.0 / 60.0));
}

TEST_CASE("EngineLoop: subsystems are called in the order added, tick by tick") {
  ManualClock clock;
  EngineLoop loop(clock);
  std::vector<std::string> log;
  Recorder a("A", log);
  Recorder b("B", log);
  loop.add(a);
  loop.add(b);
  REQUIRE(loop.subsystems().size() == 2);
  CHECK(loop.subsystems()[0] == &a);
  CHECK(loop.subsystems()[1] == &b);

  loop.run_frame();
  CHECK(log == std::vector<std::string>{"A.update", "B.update", "A.render", "B.render"});
  log.clear();

  const FrameStats f = frame_after(clock, loop, 3 * kHz60);
  CHECK(f.ticks == 3);
  CHECK(log == std::vector<std::string>{"A.fixed", "B.fixed", "A.fixed", "B.fixed", "A.fixed",
                                        "B.fixed", "A.update", "B.update", "A.render", "B.render"});
}

TEST_CASE("EngineLoop: changing the tick rate") {
  ManualClock clock;
  EngineLoop loop(clock);
  std::vector<std::string> log;
  Recorder sim("sim", log);
  loop.add(sim);
  loop.run_frame();
  CHECK(frame_after(clock, loop, kHz60).ticks == 1);

  loop.set_tick_rate_hz(30.0);
  CHECK(loop.config().tick_rate_hz == 30.0);
  CHECK(loop.config().max_ticks_per_frame == 8);
  CHECK(loop.timestep().tick_seconds() == doctest::Approx(1.0 / 30.0));
  const int ticks30[] = {0, 1, 0, 1};
  for (int expected : ticks30) {
    CHECK(frame_after(clock, loop, kHz60).ticks == expected);
  }
  REQUIRE(sim.dts.size() == 3);
  CHECK(sim.dts[0] == doctest::Approx(1.0 / 60.0));
  CHECK(sim.dts[1] == doctest::Approx(1.0 / 30.0));
  CHECK(sim.dts[2] == doctest::Approx(1.0 / 30.0));

  loop.set_tick_rate_hz(120.0);
  CHECK(frame_after(clock, loop, kHz60).ticks == 2);
  CHECK(sim.dts.back() == doctest::Approx(1.0 / 120.0));

  // Time owed carries over, in seconds: half a 30 Hz tick owed becomes one 60 Hz tick.
  loop.set_tick_rate_hz(30.0);
  CHECK(frame_after(clock, loop, kHz60).ticks == 0);
  loop.set_tick_rate_hz(60.0);
  CHECK(frame_after(clock, loop, kHz60).ticks == 2);

  CHECK_THROWS_AS(loop.set_tick_rate_hz(0.0), std::invalid_argument);
  CHECK_THROWS_AS(loop.set_tick_rate_hz(std::numeric_limits<double>::infinity()),
                  std::invalid_argument);
  CHECK(loop.config().tick_rate_hz == 60.0);
  CHECK(loop.stats().ticks == 1 + 2 + 2 + 2);
}

TEST_CASE("EngineLoop: a clock that goes backwards gives a zero delta") {
  ManualClock clock(10.0);
  EngineLoop loop(clock);
  loop.run_frame();
  clock.set(9.0);
  const FrameStats back = loop.run_frame();
  CHECK(back.measured_seconds == 0.0);
  CHECK(back.ticks == 0);
  // The next delta is measured from the reading that went back.
  clock.set(9.0 + kHz60);
  CHECK(loop.run_frame().ticks == 1);
}

TEST_CASE("EngineLoop: run_frames, run and request_stop") {
  ManualClock clock;
  EngineLoop loop(clock);
  std::vector<std::string> log;
  Recorder sim("sim", log);
  loop.add(sim);

  CHECK(loop.run_frames(0) == 0);
  CHECK(loop.run_frames(1) == 1);
  CHECK_THROWS_AS(loop.run_frames(-1), std::invalid_argument);

  // run(): the clock moves by 1/60 s before each frame; stop after 5 frames.
  int asked = 0;
  const auto frames = loop.run([&] {
    clock.advance(kHz60);
    return ++asked <= 5;
  });
  CHECK(frames == 5);
  CHECK(asked == 6);
  CHECK(loop.stats().frames == 6);
  CHECK(loop.stats().ticks == 5);  // a tick per frame, the sixth advance not yet consumed

  // A subsystem stops the loop from inside a frame: that frame completes, then run returns.
  Stopper stopper(loop, 3);
  loop.add(stopper);
  CHECK(loop.run_frames(10) == 3);
  CHECK(stopper.updates == 3);
  CHECK_FALSE(loop.stop_requested());

  // A stop requested before run() makes it return at once, consuming the request.
  loop.request_stop();
  CHECK(loop.stop_requested());
  CHECK(loop.run({}) == 0);
  CHECK_FALSE(loop.stop_requested());
  CHECK(loop.stats().frames == 9);
}

TEST_CASE("EngineLoop: add rejects duplicates and calls from inside a frame") {
  ManualClock clock;
  EngineLoop loop(clock);
  std::vector<std::string> log;
  Recorder a("A", log);
  Recorder b("B", log);
  loop.add(a);
  CHECK_THROWS_AS(loop.add(a), std::invalid_argument);
  Adder adder(loop, b);
  loop.add(adder);
  CHECK_THROWS_AS(loop.run_frame(), std::logic_error);
  CHECK(loop.subsystems().size() == 2);
  CHECK(loop.stats().frames == 0);  // the failed frame is not counted
}

TEST_CASE("SteadyClock never goes backwards and starts near 0") {
  granular::engine::SteadyClock clock;
  const double t0 = clock.now_seconds();
  CHECK(t0 >= 0.0);
  CHECK(t0 < 1.0);
  double prev = t0;
  for (int i = 0; i < 1000; ++i) {
    const double t = clock.now_seconds();
    CHECK(t >= prev);
    prev = t;
  }
}
