#pragma once
/// @file suite_tests.hpp
/// The fifteen tests of the accuracy suite. Each builds its scenes programmatically (sizes depend on
/// SuiteOptions::quick), runs them on the configured backend, measures from the grid and returns
/// a TestReport with measured values, references and their sources, and the series of its plot.

#include <string>
#include <vector>

#include "granular/accuracy/report.hpp"
#include "granular/accuracy/suite_options.hpp"

namespace granular::accuracy {

/// A test's report as every test opens it: its name, title and scene set, and the scene logged
/// as "<test>: <scene>" (log_line).
TestReport open_report(const SuiteOptions& options, std::string test, std::string title, std::string scene);

/// 1. Poured cone: sand poured from a spout onto a floor (quick 96^2, full 256^2), measured with
/// measure_cone: the angle of repose against the material's target, r_max / r_min at half height
/// and the 1-, 2- and 4-fold Fourier amplitudes of r(phi) against a round footprint.
TestReport run_cone_test(const SuiteOptions& options);

/// 2. Cone sizes: the cone test's pour (pour_cone) scaled to piles of three sizes (quick 10^4,
/// 10^4.75 and 10^5.5 grains; full 10^4, 10^5 and 10^6), poured until every grain is in and settled;
/// each pile's angle of repose (measure_cone) against the material's target (+- 2 deg) and the
/// largest minus the smallest of the three against 0 (+- 2 deg), with the angle against the grains.
TestReport run_cone_sizes_test(const SuiteOptions& options);

/// 3. Gravel cone: the cone test's pour and measurement with the table's gravel against dry
/// gravel's 40 deg, with the sand cone's footprint targets.
TestReport run_gravel_cone_test(const SuiteOptions& options);

/// 4. Hysteresis: beds with a plane surface inclined at theta along x (a tilt done in steps: each
/// step is a fresh bed at the next angle) in a walled box with a run-out; theta_start is the first
/// angle at which more than 1% of the grains move, theta_stop the slope that bed relaxes to.
TestReport run_hysteresis_test(const SuiteOptions& options);

/// 5. Dug slope: a bed of sand filling a box (quick 80^2 x 24, full 208^2 x 56), settled; a
/// hemisphere (quick radius 16, full 48) centred on its surface dug out with World::dig, then
/// settled again; the crater walls' angle, measure_cone of the crater's depth map, against the
/// material's angle of repose (+- 2 deg), with the radial profiles as dug and settled (each from
/// its wall's point at half depth) and the angle per azimuth.
TestReport run_dug_slope_test(const SuiteOptions& options);

/// 6. Heap while poured: the shipped pile scene (quick N = 96, full 192) poured by its emitter, then
/// watched until fewer than 0.1% of its grains move between two samples 8 ticks apart (at most 60 s).
/// The steepest angle over the pour's second half and the angle at rest against dry sand's hysteresis
/// band (33 .. 36 deg, widened by the hysteresis test's 2 deg), and the seconds from the pour's end to
/// rest against one second, with the angle and the share of the grains moved against time.
TestReport run_pour_test(const SuiteOptions& options);

/// 7. Silo discharge: a cylindrical silo (radius 1.5 D + 6 quick, + 8 full) with a flat bottom and
/// a centred round orifice of diameter D, filled 5 silo diameters high; grains that leave are
/// removed below and counted. Steady flow rate W(D) while the fill height falls from 3 to 2 silo
/// diameters, the fit W = C (D - k)^n (Beverloo: n = 5/2), and W against the fill height; then
/// the shipped hourglass scene (quick N = 64, full 192): W against the fraction emptied, constant
/// from 20% to 80%.
TestReport run_silo_test(const SuiteOptions& options);

/// 8. Column collapse: a cylinder of sand of radius R0 and height a R0 released at once, for
/// a in {0.5, 1, 2, 4, 8}; normalised runout (R_inf - R0) / R0 against a with power-law fits below
/// and above a = 1.7 (Lube et al. 2004: exponents 1 and 1/2). Its series "stop time" holds the
/// ticks each collapse took to come to rest against H0, which run_fall_test uses.
TestReport run_collapse_test(const SuiteOptions& options);

/// 9. Free fall: a single grain dropped from 16 to 256 cells (quick: to 128); the exponent of fall
/// distance against time (2 under gravity) and of fall time against height (1/2). When `collapse`
/// is given (the collapse test's report), also the exponent of the collapse stop time against
/// H0 (1/2: t_stop is proportional to sqrt(H0 / g)).
TestReport run_fall_test(const SuiteOptions& options, const TestReport* collapse);

/// 10. Falling block: a cube of sand (quick 24 cells wide, 800 above the floor; full 96, 4000)
/// released at rest and watched every tick until its centre (the grains' mean height) has fallen
/// 2 block heights; its packing fraction then (the grains in its footprint between the 5th and
/// 95th percentile layers over the footprint's cells there: 1 at release) against the one at
/// release (ratio 1 +- 0.1), with the fall of its centre against g t^2 / 2, the packing against
/// the fall and the fill of the layers within 2 block heights of its top, at release and at the end.
TestReport run_falling_block_test(const SuiteOptions& options);

/// 11. Communicating vessels: a U-tube with one leg full of liquid and the other empty over a full
/// channel (quick: legs of 8^2 cells, 40 high; full: 32^2, 160 high), run until at rest or 20
/// oscillation periods; the level difference of the legs against 0 (+- 1 cell).
TestReport run_communicating_vessels_test(const SuiteOptions& options);

/// 12. Dam break: a liquid column H0 high and 2 H0 long released at the closed end of a dry channel
/// (quick: H0 in {16, 32}, 8 wide; full: {32, 64, 128}, 32 wide); the front's arrival times over its
/// first 2 H0 of travel fitted as x_f = U t, U / (2 sqrt(g H0)) against Ritter's 1 (+- 0.15).
TestReport run_dam_break_test(const SuiteOptions& options);

/// 13. Levelling: a block of liquid 4 h high over the first quarter of a closed tank L long (h =
/// L / 16 the depth at rest; quick: L in {64, 128}, 8 wide; full: {256, 512}, 32 wide) released at
/// once and run until its surface has been flat (every x within 1 cell of h) for 2 L / sqrt(g h),
/// at rest, or 40 L / sqrt(g h); the later of the two levelling times, in L / sqrt(g h), against 0
/// (+- 5).
TestReport run_levelling_test(const SuiteOptions& options);

/// 14. Torricelli: a cylindrical tank of liquid (quick: radius 8, 64 high, orifice 4; full: 32,
/// 192, 8) drains through a centred bottom orifice; the exponent n of Q = C h^n over windows of
/// the head from 90% to 20% of the fill against 1/2 (+- 0.1).
TestReport run_torricelli_test(const SuiteOptions& options);

/// 15. Buoyancy: a block of sand dropped onto liquid in a closed box, with a gas pocket under the
/// liquid (quick: 24^2 x 40; full: 96^2 x 160), run until at rest; sand cells with liquid below
/// them, gas cells with liquid above them, and materials whose count changed, each against 0.
TestReport run_buoyancy_test(const SuiteOptions& options);

/// 16. Conservation and stability: random scenes (void/solid/granular, and all 8 states) stepped
/// for many ticks (quick 2 x 10^4 each; full 10^6 and 10^5) must keep every material's count exactly
/// and give the same hash on the configured backend and on the CPU with 1, 2 and 3 threads (full:
/// 1 thread for the 10^6-tick scene, 1 and 3 for the other), and with sparse and dense stepping;
/// `earlier` (the other tests' reports) adds the count of tests whose grains were not conserved.
TestReport run_conservation_test(const SuiteOptions& options, const std::vector<TestReport>& earlier);

}  // namespace granular::accuracy
