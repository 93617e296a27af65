#!/usr/bin/env python3
"""Plots of the accuracy suite (`granular accuracy --json` / `--out`) and docs/ACCURACY.md.

    plot_accuracy.py --out DIR [--markdown FILE] RESULT.json [RESULT.json ...]

Reads one or more suite JSON files (each holds one or more configurations: rule set, size,
backend), writes one PNG per test into DIR (accuracy_<test>.png: every series of every
configuration, references as lines) and accuracy_summary.png (run time against mean normalized
error, one point per configuration and test). With --markdown, also writes the report: the
calibration, per test the scene, the plot and a table of measured values against references with
their sources, and the summary. A test's section also takes, verbatim, the Markdown file
DIR/<test>.md when there is one (a record kept by hand, e.g. the values tried while tuning the
rules against that test). Needs matplotlib (optional dependency, scripts/install-deps).
"""

import argparse
import json
import math
import os
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:  # a clear message, not a traceback
    sys.stderr.write("error: plot_accuracy.py needs matplotlib (apt-get install python3-matplotlib)\n")
    sys.exit(1)

MARKERS = "osD^v<>p*hXPd8H"

# What limits the present rule family (the paper's table, with or without random symmetry and
# offset order): a statement about the model, printed under the measured gaps.
LIMITS = [
    "The default rules' misses (inertial-24-flow, full size on the H200), each with what limits it",
    "and the levers tried against it; the paragraphs below give the measurements:",
    "",
    "| test: metric | measured | target | what limits it | tried (full size unless marked) |",
    "| --- | --- | --- | --- | --- |",
    "| hysteresis: theta_start, theta_stop | 40.0, 35.14 | 36 +- 2, 33 +- 2 | the smallest pile reaches 31 degrees only where the avalanche stops above 35; theta_start lies 3.7 to 5.6 above theta_stop, and the settings that start it at 38 or less leave the crater's walls at 29.7 to 30.4 | 20 settings of topple gain, roll cost, entrain and flow level (docs/accuracy/flow.md), 21 without the flow level (docs/accuracy/hysteresis.md; entrain alone: 38.5, 34.10) |",
    "| gravel_cone: r_max_over_r_min | 1.056 | 1 +- 0.05 | the block sees 3 of a cell's 8 neighbours and diagonal moves are sqrt 2 long: the footprint rounds only as far as the random symmetry and offset order take it | entrain alone 1.049, columns 1.028 (met) |",
    "| pour: pour_angle_max, rest_seconds (quick) | 63.2, 18.7 s | 34.5 +- 3.5, 0.5 +- 0.5 | a grain that rolls or topples keeps level 1 (the flow level): grains that land on the top stop there and the slopes shed grains one surface layer at a time, so while poured the top grows into a spike near 60 degrees | entrain alone 36.3 and 11.0 s (quick; its small cone 29.5); the flow level only from level 8: 40.8 while poured, small cone 29.4 (quick); full size 78.2, the spike buries the spout (docs/accuracy/pour.md) |",
    "| silo: beverloo_exponent, rate_at_largest_D, fill_dependence | 1.31, 146, 0.16 | 2.5 +- 0.25, 1970 +- 197, 0 +- 0.05 | no free-fall arch: every orifice flows dense, 0.56 grains per orifice cell per tick at D = 6 falling to 0.32 at D = 24 (grains that topple toward the orifice move at most a cell a tick) | entrain alone (2.19, 365, 0.52: a dilute burst at D = 24); inertial-24 (2.65 from a switch, fill 0.89); columns (1.31, 2464, 0.19); a wake level handed on only in full layers (quick fill 0.98); columns with a support plane (quick: fill 0.024 to 0.045, met; exponent 0.6 to 1.5; docs/accuracy/columns-default.md) |",
    "| silo: hourglass_flow_spread | 0.29 | 0 +- 0.05 | the speed of the grains that reach the neck sets its rate: avalanche-fed, it flows faster | inertial-24 0.01 (its crater stays off the neck); entrain alone 0.17; columns 0.26 |",
    "| collapse: runout_exponent_low_a | 0.85 | 1 +- 0.1 | rolling lengthens short collapses | inertial 0.84, inertial-24 0.85, entrain alone 0.83, columns 0.83 (quick, flow level: 0.98, met) |",
    "| fall: collapse_stop_time_exponent | 1.01 | 0.5 +- 0.05 | avalanches end by random stops, not a friction force | inertial-24 0.69, inertial 0.75, entrain alone 0.91, columns 0.67 (quick 0.55, met) |",
    "| falling_block: packing_fraction_ratio, fall_time_ratio | 0.48, 13.9 | 1 +- 0.1, 1 +- 0.15 | a void rises one cell a sub-step: a column falling v cells a sub-step holds at most 1 / (1 + v) | columns with trains 0.96 and 1.01, met (version 3; version 2 0.72 and 1.08; the bound 0.51; wakes alone 0.48 and 1.16); entrain alone 0.08 and 9.2 |",
    "| communicating_vessels, dam_break, torricelli | 160; 0.03; 0.00 | 0 +- 1; 1 +- 0.15; 0.5 +- 0.1 | no pressure: liquid never moves up through a connected body | a head in a liquid's spare bits (froze at 34 of 40 cells), per brick (froze at 20), on a plane of its own (quick 0.25, full 160 to 82 in 940 ticks); the pressure lever, a head field beside the cells (inertial-24-pressure, quick: 0; 0.044; 0.17) |",
    "| levelling: levelling_time (quick) | 40 (never flat; flat at 391 and 1421 L / sqrt(g h)) | 0 +- 5 | the surface walks sideways one cell at a time: levelling is diffusion | the pressure lever (quick 8.5 and 16.5) |",
    "",
    "What limits them:",
    "",
    "* **One step per tick (paper, d4, isotropic).** A grain topples only across a drop of two cells",
    "  inside its 2x2x2 block, so a slope rests at up to 45 degrees along the axes and 35 along the",
    "  diagonals (about 39 on average, at every pile size; a dug crater's walls rest at about 36.5), and a",
    "  grain moves at most one cell per tick: falls are linear in time, stop times grow like H0, a",
    "  released block falls one cell a tick as one-cell slabs at half its density, and the discharge rate",
    "  grows linearly with D (W = 2 (D - 1) grains a tick in the quick silo).",
    "* **The motion model (inertial, inertial-24)** lifts these: grains carry a fall level and a phase",
    "  in their cell byte, fall t^2 cells in t ticks through sub-steps that only fast grains take part",
    "  in, and roll on down slopes while a topple's gain outweighs a roll's cost (docs/design/motion-model.md,",
    "  \"Motion model\"). What it does not reach yet:",
    "  * the repose angle depends on the pile's size: the pours of cone_sizes, one scene scaled to",
    "    10^4, 10^4.75 and 10^5.5 grains, rest at 29.0, 29.4 and 30.9 degrees (inertial-24) and 28.8,",
    "    31.0 and 33.6 (inertial); the roll cost is tuned on the full cone (6.7 x 10^5 grains);",
    "  * r_max/r_min stays near 1.09: the block sees 3 of a cell's 8 neighbours and diagonal moves are",
    "    sqrt 2 long; the random symmetry and offset order remove only the 1- and 2-fold terms;",
    "  * the silo: the discharge has two regimes, and neither is Beverloo's. Dense: the pack over the",
    "    orifice moves only as the voids rising from it let it, its grains at levels 0 and 1, and W is",
    "    about 0.5 grains per orifice cell per tick (6.0, 15.8, 25.6 and 54.6 grains a tick at D = 4,",
    "    6, 8 and 12; 101 to 104 at 16, 217 to 224 at 24), steady and independent of the fill, but",
    "    growing as D^2: the speed at the orifice does not grow as sqrt(g D), because only grains with",
    "    nothing beside them accelerate, so there is no free-fall arch. Dilute: once the grains over the",
    "    orifice come apart they accelerate, the density over the orifice falls from 0.6-0.76 to",
    "    0.15-0.3 and W reaches 1.6 to 1.9 grains per orifice cell (350 to 385 at D = 16, up to 868 at",
    "    24), falling again as the fill drops. Through the quick orifices (D = 4 to 12) every preset",
    "    stays dense: W grows as D^1.4 (with the offset k = 0 of the fit) and the fill dependence is",
    "    under 1%. At full size any exponent above 2 comes from a switch between the regimes. Measured",
    "    per 100 ticks on the CPU (the full-size silo of the suite, seed 1; the GPU gives the same",
    "    cells): under inertial-24 D = 16 and 24 flow dense (104 and 224) until about 1.5 diameters",
    "    have drained, then turn dilute for good (D = 16 swings between 126 and 385 through the",
    "    window: fill dependence 0.89; D = 24 reaches 868 and falls to 530); under entrain (the",
    "    default) D = 16 stays dense from 4.9 to 1.1 diameters of fill (100.6 to 101.2 grains a tick)",
    "    and D = 24 flows dense at 220, bursts dilute between 3.7 and 2.1 diameters (up to 487) and",
    "    flows dense again at 217 from 1.7: the window, 3 to 2 diameters, sees the burst's decay (1.31",
    "    to 0.77 times its mean: fill dependence 0.52, W = 365 at D = 24 and n = 2.19). The silo is",
    "    filled 5 diameters high so that the flow has drained two diameters before the window. What it",
    "    needs is a dense flow that accelerates over the last diameter above the orifice and nowhere",
    "    else (the columns lever, below, lets every falling column accelerate: 9.5 grains per orifice",
    "    cell per tick at D = 4, where Beverloo gives 0.6);",
    "  * the hourglass (its neck about 11.5 cells wide, in the dense regime) flows at 54 to 56 grains a",
    "    tick under both presets while the pack feeds its neck. Under entrain the crater over the neck",
    "    reaches it at 76% emptied (N = 192, tick 1100); from then grains reach the neck only as",
    "    avalanches down the crater's walls, at levels 2 to 8 where the dense feed is at 0 and 1, and",
    "    they cross it faster: W rises to 64 to 68 (the last window, 70 to 80% emptied, at 1.14 times the",
    "    mean: spread 0.17). Under inertial-24 the crater's walls stand at 45 degrees and its bottom is",
    "    still 14 cells over the neck at 80% emptied (spread 0.01). In sand the orifice sets the rate",
    "    whatever feeds it; here the speed of the grains that arrive does;",
    "  * a released block does not fall as a block: only a grain with nothing beside it accelerates, so",
    "    the block's bottom falls one cell a tick, grains that come free run ahead at up to the top",
    "    speed and the rest follows in one-cell slabs: when its centre has fallen 2 block heights (35",
    "    ticks where free fall takes 7) the middle 90% of its grains spans 209 layers where the block",
    "    had 22, a packing fraction 0.09 of the one at release (lever tried: columns, below);",
    "  * rolling lengthens short collapses (runout exponent below 1 for a < 1.7), and without the",
    "    entrain lever (below) the tilt test's start and stop angles are both set by the static",
    "    45-degree rule (no hysteresis): a slope that nothing moves on stands to 45 degrees. A crater",
    "    dug steeper than that fails, and its walls come to rest at 32.6 to 32.7 degrees (quick): the",
    "    grains that fall roll on until they stop, as on a pile's flank;",
    "  * avalanches end by random stops, not a friction force: the stop-time exponent is about 0.7.",
    "* **Lever tried: columns (`inertial-24-columns`; `MotionParams::columns`, docs/design/motion-model.md,",
    "  \"Motion model\").** The void a grain falling straight down leaves is a wake for one sub-step:",
    "  the grain above follows it whatever its window, at its level, and every grain that falls straight",
    "  down at the start of its window accelerates, whatever is beside it (versions 1 and 2: only when its",
    "  block's whole top layer fell, so grains beside a wall lagged). Against inertial-24, quick / full size:",
    "  * falling_block: the centre falls 2 block heights in 7 / 16 ticks (free fall 6.9 / 13.9;",
    "    inertial-24 35 / 121) at a packing fraction 0.46 / 0.48 of the one at release (0.09 / 0.08).",
    "    No rule on 2x2x2 blocks reaches the target's 0.9 at free-fall speed: a grain moves only into a",
    "    void and a void rises at most one cell a sub-step, so a column falling at v cells a sub-step",
    "    holds at most 1 / (1 + v) of its cells. Free fall through 2 block heights ends at 0.58 (quick)",
    "    and 0.96 (full, the 23-cell top speed) cells a sub-step: at most 0.63 and 0.51. Holding 0.9",
    "    needs v <= 1/9, about 200 sub-steps a tick at full size instead of 24 (the wakes alone, the",
    "    lever's first version; the preset's trains, next, go past the bound);",
    "  * trains (`MotionParams::trains`, in the preset since 2026-12-05): a design beyond one-cell moves.",
    "    After each tick every column closes the gaps of its falling trains (grains of one level, each",
    "    at most one tick's travel above the one below, only void between them), a permutation of the",
    "    column; and a fast grain over a grain falling as fast waits for it instead of slipping around",
    "    it, so the block's columns stay side by side. The block's packing after 2 heights: 0.97 quick",
    "    (CPU) and 0.96 full size (CUDA, an H100), both meeting the target (version 2: 0.86 and 0.72),",
    "    where wakes alone gave 0.46 and 0.48 and the bound is 0.63 and 0.51; its fall time 1.01 and 1.01",
    "    of free fall (version 2: 1.01 and 1.08; wakes alone 1.01 and 1.15). Version 3",
    "    (2026-12-05) makes a moving grain wait from level 1 (version 2: from level 2) and gravity",
    "    accelerate every falling grain, so no column of the block starts late. Against version 2 on the",
    "    quick suite: silo fill dependence 0.053 (0.092), hourglass spread 0.17 (0.29), collapse",
    "    stop-time exponent 0.52 (0.55), runout exponent 0.99 (1.08), Torricelli's head exponent 0.12",
    "    (0.44: a falling liquid now accelerates whatever is beside it, missed): the same 22 of 39",
    "    targets met (docs/accuracy/columns-default.md); at full size it meets 19 of 35 where version 2",
    "    met 17 (the block's packing and the cone's footprint, 1.047). The 1024^3 bowl's fall costs 88 ms",
    "    a tick on an H100, 21.7 times inertial-24's in the same call (version 2: 118 ms, 29.0 times;",
    "    bench/RESULTS.md, \"Columns version 3\"). A DistributedWorld refuses it: a train may cross a slab;",
    "  * met with it, missed without: cone_sizes' largest pile (31.8 / 34.6 degrees), the gravel",
    "    footprint (1.028 / 1.042), the stop-time exponent on the quick suite (0.52; full size 0.70,",
    "    missed), and under version 2 Torricelli's head exponent (quick 0.44; full size 0.22, missed);",
    "    the full cone rests at 31.7 degrees with r_max/r_min 1.047 (inertial-24: 31.5 and 1.085);",
    "  * missed with it, met without: cone_sizes' spread of angles (4.3 / 7.1 degrees: the smallest",
    "    pour rests at 27.5, its stream now landing at free-fall speed and rolling on), the quick",
    "    silo's fill dependence (0.053 under version 3, from 0.009) and hourglass spread (0.17), the full silo's Beverloo",
    "    exponent (1.00 under version 3, from 2.65: the wide orifices' jump is gone; W = 1554 grains a",
    "    tick at D = 24, Beverloo's 1970, the whole pack falling at up to the top speed)",
    "    and the quick gravel cone's angle (37.9);",
    "  * its cost: while a block falls every grain of it moves in every sub-step, so the 1024^3 bowl's",
    "    first 63 ticks take 105 ms a tick on an H200 (0.30x real time) against 3.99 ms (8.0x); over",
    "    400 ticks of the 512^3 bowl, 4.24 ms against 3.67 (its block lands sooner and sleeps).",
    "  * a variant that hands the wake's level on only inside a full falling layer (every top cell over",
    "    a wake), meant to keep levels out of the silo's dense pack, did worse on the quick suite: fill",
    "    dependence 0.98, falling block 0.36, Torricelli -0.24 (not kept, not a preset);",
    "  * version 4 (2026-12-06): the preset takes the default's grain (entrain, flow level 1); a grain",
    "    that rolls or topples over a grain falling at level 2 or faster keeps its level (the flow level",
    "    caps a grain flowing over a surface, not one slipping past another inside a falling body); and",
    "    an airborne train (its first grain at level 2 or more over a tick's travel of void) takes in",
    "    moving grains of every level. Without the first rule the full suite's block spread to 0.21",
    "    under the default's grain; without the second, blocks of 32 to 64 cells kept 0.63 to 0.68 of",
    "    their packing (now 0.97 to 0.98, CPU probes). On the quick suite it meets 26 of the 32 granular",
    "    targets against the default's 24: both falling-block targets (0.996 and 1.01; full size on the",
    "    CPU 0.981 and 1.08), the silo's rate at its widest orifice (295 grains a tick at D = 12,",
    "    Beverloo's 293, the default's 54), the dug crater's wall (31.2 degrees) and the gravel cone's",
    "    footprint (1.049); it loses cone_sizes' smallest pile (30.6 degrees), the silo's fill",
    "    dependence (0.48) and the hourglass's spread (0.66). At full size (CUDA, an H100, with the first",
    "    rule and before the second, cab9ae9) it met 23 of the 32 against the default's 21: the falling",
    "    block (0.91 and 1.08) and the gravel cone's footprint (1.045); it lost the smallest pile",
    "    (30.8); the silo's rate at D = 24 was 729 grains a tick (Beverloo's 1970, the default's 146) and",
    "    the pour's spike stood as the default's (75 degrees). The sandbox's bowl at N = 128 opens a gap",
    "    under its top 16 layers by tick 4 and has fallen as one block by tick 8 (README);",
    "  * version 5 (2026-12-06, later): an airborne train with a tick's travel of void under it is",
    "    carried: the block step reads its grains as a static material and the trains pass moves it a",
    "    tick's travel in one move, so a released block falls exactly g t^2 / 2 a tick and the inside of",
    "    a falling body sleeps; grains at rest over an airborne train join it, so a tall block falls as",
    "    one. The quick suite's figures are version 4's within the run-to-run spread (30 of 42 either",
    "    way; docs/accuracy/columns-default.md); at full size (CUDA, an H100) it meets the granular",
    "    targets version 4 met, the 96-cell block keeping 0.993 of its packing (0.911 before airborne",
    "    trains) in 1.08 of free-fall time, the silo's rate at D = 24 598 grains a tick (729 under",
    "    version 4 at cab9ae9; Beverloo's 1970). On an H100 the 1024^3 bowl's first 20 ticks cost 1.6",
    "    times less (31.0 against 50.4 ms a tick), its whole fall 5% less (66.0 against 69.6 ms a tick,",
    "    0.48x real time; the default 4.07 ms, 7.8x): once the block lands every grain of it flows and is",
    "    stepped, which is what a default whose block falls whole would cost (bench/RESULTS.md,",
    "    \"Carried trains\").",
    "  So the lever is not in the default: it trades the silo's steady rate and the smallest pile for the",
    "  falling block, and a falling volume's cost for its physics; a game that drops large blocks",
    "  chooses it per world. The silo's pack takes the speed of the grains leaving the orifice and",
    "  falls as a mass, so its rate grows with the fill; docs/accuracy/columns-default.md lists the",
    "  variants tried and their figures.",
    "* **Lever kept: entrain (`inertial-24-entrain`, and under the default rules; `GrainMotion::entrain`,",
    "  docs/design/motion-model.md, \"Motion model\").** A grain that rolls or topples sets the grains at rest",
    "  on step edges of its block moving (level 1) with chance entrain / 256: a flowing layer erodes the",
    "  slope it runs on, as in the two-species (rolling and static grains) models of Bouchaud et al. and",
    "  Mehta. A slope that nothing moves on still stands to where a first grain topples, but the",
    "  avalanche that starts there now spreads and stops at the angle where moving grains stop: start",
    "  and stop angles part. Topple gain 192, roll cost 224, entrain 128 (docs/accuracy/hysteresis.md",
    "  lists the 21 settings tried). Full size on the H200, against inertial-24:",
    "  * met with it, missed without: theta_stop 34.1 (45.0) and start minus stop 4.4 (-0.5); the",
    "    cone's footprint r_max/r_min 1.026 (1.085) and the gravel cone's 1.049 (1.054); cone_sizes'",
    "    middle pile 31.4 (28.7);",
    "  * closer, still missed: theta_start 38.5 (44.5; target 36 +- 2), cone_sizes' smallest pile 29.5",
    "    (29.0) and the spread of the three angles 2.05 (3.61), the silo's fill dependence 0.52 (0.89).",
    "    What limits theta_start: in every setting tried the dug crater's walls settle 2.4 to 3.9",
    "    degrees below theta_stop and theta_start lies 3.1 to 5.2 above it, and every setting with a",
    "    theta_start of 38 or less misses another target: the crater (29.6 to 30.6 at 37.0 and 37.5) or",
    "    the cones (topple gain 256, roll cost 160, entrain 64: 38.0, quick cone 29.3). What",
    "    limits the smallest pile: its angle rises with a smaller topple gain (fewer grains roll on),",
    "    and so do the avalanche's angles: the settings that pour it at 31 or more (topple gain 128)",
    "    stop the tilted bed at 37.1 to 38.0;",
    "  * missed with it, met without: the silo's Beverloo exponent 2.19 (2.65) and the hourglass's flow",
    "    spread 0.17 (0.01). Both come from the two regimes of the discharge (the silo and hourglass",
    "    bullets above): inertial-24's n = 2.65 is its switch to the dilute regime at D = 16 and 24,",
    "    with W at D = 16 swinging through the window (fill dependence 0.89); entrain keeps D = 16",
    "    dense and steady and D = 24 bursts, and its hourglass speeds up once avalanches feed the",
    "    neck. The collapse stop-time exponent moves further from 0.5 (0.91 against 0.69);",
    "  * unchanged: the cone 31.7 (31.5), the crater's walls 31.3 (34.6, both met), the falling block,",
    "    the liquids (a liquid's entrain is 0);",
    "  * its cost: none measurable: the 1024^3 bowl's first 63 ticks take 3.89 to 3.91 ms a tick",
    "    against 3.92 to 3.94 for inertial-24 in the same H200 call (8.1x to 8.2x real time).",
    "  So it is kept: it meets 21 of the full suite's 35 targets where inertial-24 meets 18 (quick: 25",
    "  of 38 against 21), and the two it loses are a switch between flow regimes that inertial-24 has",
    "  too, not a steadier discharge.",
    "* **Lever kept: flow level (`inertial-24-flow`, the default rules; `GrainMotion::flow_level`,",
    "  docs/design/motion-model.md, \"Motion model\").** A grain that rolls or topples keeps at most level 1",
    "  and so moves at most one cell a tick over a surface; a falling grain still accelerates. Under",
    "  entrain alone a grain poured from high up lands fast and rolls on until its roll costs stop it,",
    "  which flattens small piles more than large ones (their grains fall about one pile height). On",
    "  top of entrain, at the same topple gain, roll cost and entrain (docs/accuracy/flow.md lists the",
    "  20 settings and the caps of 2 and 3 tried), full size on the H200, against entrain alone:",
    "  * met with it, missed without: cone_sizes' smallest pile 31.25 (29.54) and the spread of the",
    "    three angles 0.95 (2.05): 10^4, 10^5 and 10^6 grains rest at 31.25, 31.98 and 32.20 degrees.",
    "    The smallest pile's angle varies with the seed: the quick cone_sizes at seeds 2 and 3 (`granular",
    "    accuracy --quick --tests cone_sizes --seed S`) pour it at 30.94 and 30.78 (entrain alone: 29.51",
    "    and 30.33), so at 10^4 grains the target is met at the suite's seed 1 and missed by 0.06 and",
    "    0.22 degrees at the other two, while the spread of the three sizes stays within 2 degrees at",
    "    all three seeds (0.91, 1.14, 1.33; entrain alone 1.89, 2.05, 1.11);",
    "  * missed with it, met without: theta_stop 35.14 (34.10), 0.14 degrees over its band, and the",
    "    gravel cone's footprint 1.056 (1.049). In every setting tried the smallest pile reaches 31",
    "    degrees only where the tilted bed's avalanche stops above 35: both rise as fewer grains roll on;",
    "  * closer, still missed: the silo's fill dependence 0.16 (0.52): every orifice now flows dense and",
    "    steady; the falling block's packing fraction 0.48 (0.08);",
    "  * further, still missed: theta_start 40.0 (38.5), the Beverloo exponent 1.31 (2.19: W at D = 16",
    "    and 24 is 89 and 146 grains a tick where dense flow under entrain gives 101 and 217), the",
    "    hourglass's spread 0.29 (0.17), the stop-time exponent 1.01 (0.91), the falling block's fall",
    "    time 13.9 (9.2) times free fall;",
    "  * unchanged: the cone 32.1 (31.7) and its footprint 1.030 (1.026), the crater's walls 32.0",
    "    (31.3), the collapse's runout exponents 0.85 and 0.53 (0.83 and 0.52), the fall, the liquids",
    "    (a liquid's flow level is 0: no limit);",
    "  * its cost: none measurable: the 1024^3 bowl's first 63 ticks take 3.873 and 3.875 ms a tick",
    "    against 3.871 and 3.877 for entrain alone in the same H200 call (8.24x real time; no grain",
    "    rolls in those ticks, and both reach the same hash).",
    "  So it is the default: it meets 21 of the full suite's 35 targets, as entrain alone does, and 27",
    "  of the quick suite's 38 against 25; the targets it trades are the pile's angle at every size,",
    "  the issue this suite's cone_sizes test was written for (met at the suite's seed, within 0.22",
    "  degrees at two others), against theta_stop by 0.14 degrees and the gravel footprint by 0.006.",
    "* **The levers the literature suggests, and which were built.** A two-threshold rule (start and",
    "  stop angles, as in Mehta-Luck style sandpile models) is the entrain lever in this model's terms:",
    "  a slope starts failing where a grain at rest topples and the flowing layer stops where moving",
    "  grains stop (kept, in the default). Grains in free fall moving as columns is the columns lever",
    "  (built, measured above, a preset). Toppling decided over a taller neighbourhood (2x2x3) was not",
    "  built: the table method keys a block by its cells' states, and 12 cells of 3 bits make a 36-bit",
    "  key, a table of 64 Gi entries against the 16 Mi of the 2x2x2 table; it would need a step",
    "  computed per block and an offset cycle of its own. A solid fraction or contact count in the",
    "  cell's spare bits was not built: a grain's byte is full (3 bits of material, 4 of motion level,",
    "  1 of phase); at rest its level bits are 0 and a quiet block is recognised by them, so a count",
    "  kept there would wake every settled block whose count changes and end sparse stepping's",
    "  savings. The flow level and entrain act on the same angles through the motion level instead.",
    "* **No pressure (every rule set but inertial-24-pressure).** A liquid falls, topples and rolls as a grain does and walks",
    "  sideways on liquid into void, but no cell pushes another: liquid never moves up through a",
    "  connected body, and a column does not spread under its own weight. So the U-tube's legs keep",
    "  the levels they start with (the level difference stays the starting head), a tank drains through",
    "  its orifice at a rate the orifice alone sets (the flow of a dense column of grains, independent of",
    "  the head, where Torricelli's grows as its square root), and a released column erodes from its face as a",
    "  frictionless pile would, its front creeping at the speed of the cells that topple and walk instead",
    "  of running at Ritter's 2 sqrt(g H0). A pressure state (or a pressure pass that moves liquid up",
    "  along a connected body toward lower heads) is what these three need; buoyancy needs none: density",
    "  exchanges in a column sort sand below and gas above the liquid.",
    "  Why there is none yet (prototypes on the quick U-tube, 2026-12-02): a resting liquid cell has 4 or",
    "  5 spare bits. A hydraulic head kept modulo 16 in them, relaxed block by block, with void inside",
    "  the liquid moving up the head field, levels the legs only while neighbouring cells differ by less",
    "  than half the modulus; under a low free surface fed from a high head the field is steeper than",
    "  that, the value wraps and the legs freeze at a difference the field cannot see (34 cells after",
    "  470 ticks, from 40). A head kept per 16^3 brick has no bit limit but cannot see walls and channels",
    "  thinner than a brick, and froze at 20 cells. A head that wraps only at gradients of tens of cells",
    "  per cell needs a byte of its own per liquid cell: with one (a second plane, prototyped outside",
    "  the library) the quick U-tube levels to 0.25 cells in 470 ticks, but the full-size one only",
    "  from 160 to 82 cells in 940: relaxed block by block, the head diffuses too slowly along a",
    "  250-cell path, so it also needs a faster solve (over-relaxation or multigrid on the plane).",
    "  The pressure lever (`MotionParams::pressure`, preset inertial-24-pressure, 2026-12-05;",
    "  docs/design/pressure.md) keeps a head per coarse cell of 2x2x2 cells beside the cells, solved",
    "  each tick in a bounded number of sweeps as the highest free surface of each body, and moves",
    "  liquid into voids below that head. Quick: the U-tube levels to 0 cells and comes to rest, the",
    "  levelling tank is flat after 8.5 and 16.5 shallow-water times (never, under the default), but the",
    "  head is the body's highest surface, not a pressure field: a released column froths as every",
    "  cell connected to it is pushed up (dam_break 0.044 of Ritter), and the orifice's rate hardly",
    "  follows the head (exponent 0.17).",
    "  The momentum lever (`MotionParams::momentum`, preset inertial-24-momentum, 2026-12-05;",
    "  docs/design/momentum.md) adds a per-cell plane carried by the permutation on both backends: a",
    "  liquid's sideways velocity, sub-steps whose x and y offsets flip with z in about 3 of 4 from",
    "  sub-step 2 (a top sideways speed of about 18 cells a tick; sand keeps its sub-steps 0 and 1), and",
    "  a moving liquid that falls into the void under it. Quick, seeds 1..4: the U-tube still levels to",
    "  0, the levelling tank is flat after 3.2 (L = 64) and 6.3 (L = 128) shallow-water times, the",
    "  dam's front runs at 0.19 of Ritter's and the orifice's exponent is 0.35. At full size (CUDA, an",
    "  H100, 2026-12-05, the lever's first full-size run) it falls apart: the U-tube's legs are 101.5",
    "  cells apart after 944 ticks and still moving (the quick U-tube: 0), the dam's front runs at 0.29",
    "  of Ritter's (2 H0 in 20.2, 17.9 and 19.8 ticks at H0 = 32, 64, 128; Ritter 4.0, 5.7, 8.0), the",
    "  256-cell tank is flat after 14.5 shallow-water times and the 512-cell one never within 40, and",
    "  the orifice's rate does not follow the head (exponent -0.02, r^2 0.07). What is missing: a head",
    "  that falls toward free surfaces (a potential, multigrid), so that the liquid at rest behind a",
    "  released column's face accelerates too, and whatever keeps the full-size U-tube's head-driven",
    "  voids from overshooting (under pressure alone the quick U-tube levels; its full size was not run).",
    "  The shallow-water lever (`MotionParams::shallow`, preset inertial-24-shallow, 2026-12-06;",
    "  docs/design/shallow-water.md) moves the liquid as shallow water after every tick: a plane of",
    "  face velocities and carried fractions beside the columns (4 int32 per column), 32 integer",
    "  iterations a tick, whole cells moved from the top of one column to the top of the next, on the",
    "  CPU and CUDA alike; under a static cover, a column more than half full is a pipe whose surface",
    "  is the steady head between the pipe's ends. It meets levelling at both sizes (quick 1.0, full",
    "  1.875 shallow-water times; 40, never flat, under the default) and communicating vessels at both",
    "  (quick 0.25 cells, at rest after 64 ticks; full 0.03, but the legs, 89 cells deep, still move a",
    "  partly filled top layer after 944 ticks; the default: 40 and 160), runs the dam's front at 0.49",
    "  (quick) and 0.45 (full) of Ritter's (the default: 0.02 and 0.03; whole cells bound it near 0.85,",
    "  and the bed friction that levels the tanks slows the rarefaction), and lets the dam break, the",
    "  shipped u_tube and reservoir scenes and deep pools poured at rest come to rest. An orifice in a tank's floor",
    "  is not a pipe: the liquid over it hangs over void, and the block step's free fall sets the",
    "  outflow (Torricelli 0.00, the default's). It refuses pressure, whose head worked against it.",
    "  Every granular figure equals the default's (no liquid, no pass).",
    "  A liquid against sand: a cell holds one material, so water does not seep into the pores of a sand",
    "  bed (there are none at this scale); it stands on loose sand as on a floor, sand poured into it",
    "  sinks through it and lifts it (fluid_block.hpp), and a grain stops a liquid's velocity. The side",
    "  plane carries no state on a grain, so it changes none of this; seeping stays out of scope.",
    "",
]


def load(paths):
    calibration, configurations, commands = None, [], []
    for path in paths:
        try:
            with open(path, encoding="utf-8") as f:
                data = json.load(f)
        except (OSError, json.JSONDecodeError) as e:
            sys.stderr.write(f"error: cannot read suite results '{path}': {e}\n")
            sys.exit(1)
        if "configurations" not in data:
            sys.stderr.write(f"error: '{path}' is not a `granular accuracy` JSON file (no 'configurations')\n")
            sys.exit(1)
        calibration = calibration or data.get("calibration")
        if data.get("command"):
            commands.append((data["command"], data.get("date", ""), data.get("machine", "")))
        configurations.extend(data["configurations"])
    return calibration, configurations, commands


def label(config):
    c = config["config"]
    # Files written before sparse stepping existed hold no "stepping": they stepped densely.
    return f'{c["rules"]} / {c["size"]} / {c["backend"]} / {c.get("stepping", "dense")}'


def finite(v):
    return v is not None and isinstance(v, (int, float)) and math.isfinite(v)


def physics_seconds(config):
    """Run time of the tests measured against physical references (conservation is an absolute)."""
    return sum(t["seconds"] for t in config["tests"] if t["test"] != "conservation")


def physics_error(config):
    """Mean over the physics tests of their mean |error| / tolerance (None when there are none)."""
    errors = [t["mean_normalized_error"] for t in config["tests"]
              if t["test"] != "conservation" and t["metrics"] and finite(t.get("mean_normalized_error"))]
    return sum(errors) / len(errors) if errors else None


def test_names(configurations):
    names = []
    for c in configurations:
        for t in c["tests"]:
            if t["test"] not in names:
                names.append(t["test"])
    return names


def runs_of(name, configurations):
    """(index, configuration, test result) of every run of the test `name`, in the configurations' order."""
    return [(ci, c, t) for ci, c in enumerate(configurations) for t in c["tests"] if t["test"] == name]


def log_axes(x_label, y_label):
    """Power laws (fits against D, H, H0, a, t, h; a front against time) are drawn on log-log axes."""
    return (any(w in x_label for w in ("D (cells)", "H (cells)", "H0 (cells)", "aspect ratio", "ticks t", "head h (cells)"))
            or "front travel" in y_label)


def log_x_axis(x_label):
    """Quantities measured over decades of size (the poured cones' grains) get a log x axis alone."""
    return "grains in the pile" in x_label


def plot_test(name, configurations, out_dir):
    """One figure per test: a panel per (x label, y label) pair of its series."""
    panels = []
    for _, c, t in runs_of(name, configurations):
        for s in t["series"]:
            key = (s["x_label"], s["y_label"])
            if key not in panels:
                panels.append(key)
    if not panels:
        return None
    fig, axes = plt.subplots(1, len(panels), figsize=(5.2 * len(panels), 4.0), squeeze=False)
    title = name
    references_drawn = {}
    for ci, c, t in runs_of(name, configurations):
        title = t["title"]
        for s in t["series"]:
            ax = axes[0][panels.index((s["x_label"], s["y_label"]))]
            log = log_axes(s["x_label"], s["y_label"])
            pts = [(x, y) for x, y in zip(s["x"], s["y"])
                   if finite(x) and finite(y) and (not log or (x > 0 and y > 0))
                   and (not log_x_axis(s["x_label"]) or x > 0)]
            if not pts:
                continue
            xs, ys = zip(*pts)
            if s["reference"]:
                # A reference shared by configurations is drawn once; one that depends on the
                # configuration (a fit) is drawn for each configuration it differs in, in its colour.
                key = (s["x_label"], s["y_label"], s["name"])
                data = (tuple(xs), tuple(ys))
                if data in references_drawn.get(key, []):
                    continue
                if key in references_drawn:
                    ax.plot(xs, ys, "--", color=f"C{ci % 10}", lw=1, label=f'{label(c)}: {s["name"]}')
                else:
                    ax.plot(xs, ys, "k--", lw=1.2, label=s["name"])
                references_drawn.setdefault(key, []).append(data)
            else:
                ax.plot(xs, ys, marker=MARKERS[ci % len(MARKERS)], ms=4, lw=1,
                        label=f'{label(c)}: {s["name"]}')
    for (xl, yl), ax in zip(panels, axes[0]):
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
        ax.grid(alpha=0.3)
        if log_axes(xl, yl):
            ax.set_xscale("log")
            ax.set_yscale("log")
        elif log_x_axis(xl):
            ax.set_xscale("log")
            ax.ticklabel_format(useOffset=False, axis="y")
        else:
            ax.ticklabel_format(useOffset=False, axis="y")
    # The legends go below the axes, in two columns: with every configuration a legend outgrows its
    # panel. The figure grows by the tallest legend; the axes keep their size.
    entries = max(len(ax.get_legend_handles_labels()[1]) for ax in axes[0])
    rows = (entries + 1) // 2
    axes_h, legend_h = 3.0, 0.12 * rows + 0.5
    fig.set_size_inches(5.2 * len(panels), axes_h + legend_h + 0.6)
    height = axes_h + legend_h + 0.6
    fig.subplots_adjust(left=0.06, right=0.98, wspace=0.3, top=1 - 0.45 / height, bottom=(legend_h + 0.15) / height)
    for ax in axes[0]:
        ax.legend(fontsize=6, loc="upper center", bbox_to_anchor=(0.5, -0.5 / axes_h), ncol=2, frameon=False)
    fig.suptitle(title, fontsize=10)
    path = os.path.join(out_dir, f"accuracy_{name}.png")
    fig.savefig(path, dpi=72, bbox_inches="tight")
    plt.close(fig)
    return path


def plot_summary(configurations, out_dir):
    fig, ax = plt.subplots(figsize=(7, 4.5))
    names = test_names(configurations)
    for ci, c in enumerate(configurations):
        color = plt.cm.tab20(ci % 20)  # 20 distinct colours: one per configuration
        for t in c["tests"]:
            if finite(t.get("mean_normalized_error")) and t["metrics"] and t["seconds"] > 0:
                ax.scatter(t["seconds"], t["mean_normalized_error"], color=color, alpha=0.5, s=18,
                           marker=MARKERS[names.index(t["test"]) % len(MARKERS)])
        if finite(physics_error(c)) and physics_seconds(c) > 0:
            ax.scatter(physics_seconds(c), physics_error(c), color=color, s=90, edgecolor="k",
                       label=f"{label(c)} (all physics tests)")
    for ti, n in enumerate(names):
        ax.scatter([], [], color="gray", marker=MARKERS[ti % len(MARKERS)], s=18, label=f"test: {n}")
    ax.axhline(1.0, color="k", ls="--", lw=1, label="target edge (|error| = tolerance)")
    ax.set_xscale("log")
    ax.set_yscale("symlog", linthresh=0.1)
    ax.set_ylim(bottom=0)
    ax.set_xlabel("run time (s): one test (small), all physics tests (large)")
    ax.set_ylabel("mean |error| / tolerance")
    ax.set_title("Run time against error, every configuration tried")
    ax.grid(alpha=0.3)
    # Beside the axes: with every configuration the legend would cover the points inside them.
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0), frameon=False)
    path = os.path.join(out_dir, "accuracy_summary.png")
    fig.savefig(path, dpi=96, bbox_inches="tight")
    plt.close(fig)
    return path


def fmt(v):
    if not finite(v):
        return "n/a"
    return f"{v:.4g}"


def write_markdown(md_path, calibration, configurations, commands, images, out_dir):
    md_dir = os.path.dirname(os.path.abspath(md_path))

    def rel(p):
        return os.path.relpath(os.path.abspath(p), md_dir)

    lines = ["# Accuracy", "",
             "Generated by `accuracy/plot_accuracy.py` from the JSON of `granular accuracy`; do not edit by hand.",
             "Each test builds its scene programmatically, runs it, measures from the grid and compares with a",
             "physical reference. *Error* is measured - reference; a target is met when |error| <= tolerance",
             "(the suite's targets); *norm.* is |error| / tolerance.", ""]
    if commands:
        lines += ["## How these figures were made", ""]
        for cmd, date, machine in commands:
            lines.append(f"* `{cmd}` ({date}; {machine})")
        lines.append("")
    per_rules = {}
    for c in configurations:
        desc = (c.get("calibration") or calibration or {}).get("description")
        if desc:
            per_rules.setdefault(desc, [])
            if c["config"]["rules"] not in per_rules[desc]:
                per_rules[desc].append(c["config"]["rules"])
    if per_rules:
        lines += ["## Calibration", ""]
        for desc, rules in per_rules.items():
            lines.append(f"* {', '.join(rules)}: {desc}.")
        lines += ["",
                  "Rules without a motion model (paper, d4, isotropic) move a grain one cell per tick at most, so",
                  "their calibration is exact only for a fall of H_c = 64 cells; the free-fall test shows how far",
                  "off other heights are. With the motion model (inertial, inertial-24) a grain falling from rest",
                  "covers t^2 cells in t ticks up to its top speed (15 or 23 cells per tick), which is free fall",
                  "with g = 2 cells/tick^2: H_c = 1 makes that the real g (granular/time_scale.hpp).", ""]
    lines += ["## Summary: run time against error", "", f"![summary]({rel(images['summary'])})", "",
              "Large points: each configuration's physics tests (all but conservation, whose error is 0 by",
              "construction and whose long runs are not a physics measurement); small points: single tests.",
              "Run times are wall-clock on the machine named above, shared with other jobs: compare",
              "configurations measured in the same run.", "",
              "| configuration | physics tests (s) | whole suite (s) | mean norm. error (physics tests) | targets met | grains conserved |",
              "| --- | --- | --- | --- | --- | --- |"]
    for c in configurations:
        metrics = [m for t in c["tests"] for m in t["metrics"]]
        met = sum(1 for m in metrics if m["met"])
        lines.append(f"| {label(c)} | {physics_seconds(c):.2f} | {c['seconds']:.2f} | {fmt(physics_error(c))} | {met} / {len(metrics)} | "
                     f"{'yes' if c['conserved'] else 'NO'} |")
    lines.append("")
    for name in test_names(configurations):
        first = next(t for c in configurations for t in c["tests"] if t["test"] == name)
        lines += [f"## {first['title']}", "", f"Scene: {first['scene']}.", ""]
        if name in images:
            lines += [f"![{name}]({rel(images[name])})", ""]
        lines += ["| configuration | metric | measured | reference | error | tolerance | norm. | met | run time (s) |",
                  "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
        sources = []
        notes = []
        for _, c, t in runs_of(name, configurations):
            for m in t["metrics"]:
                unit = f" ({m['unit']})" if m["unit"] else ""
                lines.append(f"| {label(c)} | {m['name']}{unit} | {fmt(m['measured'])} | {fmt(m['reference'])} | "
                             f"{fmt(m['error'])} | {fmt(m['tolerance'])} | {fmt(m['normalized_error'])} | "
                             f"{'yes' if m['met'] else '**no**'} | {t['seconds']:.2f} |")
                if (m["name"], m["source"]) not in sources:
                    sources.append((m["name"], m["source"]))
            for n in t["notes"]:
                notes.append(f"{label(c)}: {n}")
        lines += ["", "References:", ""]
        lines += [f"* {n}: {s}" for n, s in sources]
        if notes:
            lines += ["", "Notes:", ""] + [f"* {n}" for n in notes]
        lines.append("")
        kept = os.path.join(out_dir, f"{name}.md")
        if os.path.isfile(kept):
            with open(kept, encoding="utf-8") as f:
                lines += [f.read().rstrip("\n"), ""]
    gaps = [(label(c), t["test"], m) for c in configurations for t in c["tests"] for m in t["metrics"] if not m["met"]]
    lines += ["## Gaps", ""]
    if gaps:
        lines += ["Targets not met, per configuration (|error| / tolerance in brackets):", ""]
        for cfg, test, m in gaps:
            lines.append(f"* {cfg}, {test}: {m['name']} = {fmt(m['measured'])} against {fmt(m['reference'])} "
                         f"+- {fmt(m['tolerance'])} ({fmt(m['normalized_error'])})")
        lines += [""]
    else:
        lines += ["Every target is met.", ""]
    lines += LIMITS
    lines += ["## Reproduce", "",
              "* Quick, CPU (CI sizes; regenerates this file): `scripts/accuracy-docs`",
              "* Full size, GPU: `GRANULAR_CACHE_DIR=build-gpu/lut-cache build-gpu/cli/granular accuracy "
              "--backend cuda --rules inertial,inertial-24 --out gpu-out/accuracy` (and `--rules isotropic,paper`), then copy "
              "each `accuracy.json` to `docs/accuracy/full-cuda-<name>.json` and run `scripts/accuracy-docs --no-run`.",
              ""]
    with open(md_path, "w", encoding="utf-8") as f:
        f.write("\n".join(lines))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True, help="folder for the PNG files")
    ap.add_argument("--markdown", help="also write the Markdown report to this file")
    ap.add_argument("results", nargs="+", help="JSON files written by `granular accuracy --json` or --out")
    args = ap.parse_args()
    calibration, configurations, commands = load(args.results)
    if not configurations:
        sys.stderr.write("error: the result files hold no configuration\n")
        return 1
    os.makedirs(args.out, exist_ok=True)
    images = {}
    for name in test_names(configurations):
        path = plot_test(name, configurations, args.out)
        if path:
            images[name] = path
    images["summary"] = plot_summary(configurations, args.out)
    for p in images.values():
        print(p)
    if args.markdown:
        write_markdown(args.markdown, calibration, configurations, commands, images, args.out)
        print(args.markdown)
    return 0


if __name__ == "__main__":
    sys.exit(main())
