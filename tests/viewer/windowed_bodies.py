#!/usr/bin/env python3
"""A player throwing a body into the sand, on a virtual display (run it inside with_xvfb.py, as ctest
viewer.windowed_bodies does): starts LAUNCHER (scripts/launch, what ./scripts/run execs: the bowl at
N = 128), lets the sand settle (4 ticks per update with ], Ctrl+S telling the tick, then [ back to
real time), takes a screenshot with P, puts the cursor on the window's centre and taps T. The
sandbox throws the HUD's default body (a ball of 800 kg/m^3) from just in front of the camera along
the cursor's ray; the script reads its lines on stdout and checks:

* the throw: where it starts (inside the grid) and how fast it flies;
* the landing: in the sand, after as many ticks as a free fall from the throw's height and vertical
  speed to the landing height takes (g = 9.81 m/s^2 in ticks and cells from the throw line), to
  within a tick and a tenth;
* the rest: inside the grid, partly sunk in the sand (Archimedes: 800 / 1600 = half);
* the pixels: the screenshot before the throw shows no pixel of the body material's colour (a
  purple, #7A4FA0 in the presets) outside the HUD, and one in each renderer (P, then C and P twice)
  shows the body;
* a second throw, with the HUD's density slider dragged to its end (8000 kg/m^3) and the cursor
  elsewhere: the steel ball sinks under the surface, deeper than the light one floats;
* Ctrl+Z twice takes both throws back (the first to the throw's tick; each body gone from the World
  and from Bullet: "bodies: 0 (1 removed, 0 added)"; none of its pixels left), Ctrl+Shift+Z brings
  the first back ("bodies: 1 (0 removed, 1 added)"), and after Space it lands at the same tick;
* Ctrl+S and Ctrl+O: the loaded snapshot's body gets a rigid body in the new session;
* Esc closes the sandbox with exit status 0.
Every wait is bounded; exit status 0 on success, 1 with the reason otherwise.

usage: windowed_bodies.py LAUNCHER [ARGS...]
"""

import math
import os
import re
import sys
import time

from png_pixels import read_png
from windowed_session import Sandbox, find_window, session_main, xdotool

SESSION_SECONDS = 540  # every wait ends by then (ctest allows 600)
SETTLED_TICK = 240  # the bowl's sand has fallen into the lower half by then
HUD = (470, 610)  # the HUD window lies within the window's top-left 470 x 610 pixels
BODY_PIXELS = 40  # a screenshot shows the body when it has at least this many pixels of its colour
GRID = 128  # scripts/launch's --size
NUMBER = r"(-?\d+(?:\.\d+)?)"
DENSITY_SLIDER = (200, 448)  # a point of the HUD's density slider (its window at the top left, as it opens)
HEAVY_AIM = (820, 360)  # the second throw's cursor: a ray onto the flat sand beside the bowl
SKY = (1200, 80)  # a point of the window where the cursor's ray misses the grid


def body_pixels(path, colour):
    """Pixels outside the HUD whose hue is the body colour's (a purple: blue above red above green),
    whatever the shading; sand (red > green > blue), the grey solid, the sky (blue > green > red) and
    the brush's orange are none."""
    width, height, rows = read_png(path)
    red, green, blue = colour
    assert blue > red > green, f"the body colour {colour} is not a purple; this test reads purples"
    count = 0
    for y in range(height):
        row = rows[y]
        start = HUD[0] if y < HUD[1] else 0
        for x in range(start, width):
            r, g, b = row[4 * x], row[4 * x + 1], row[4 * x + 2]
            if b > g + 25 and r > g + 12 and b > r:
                count += 1
    return count


def run(command, folder):
    started = time.monotonic()

    def step(text):
        print(f"[{time.monotonic() - started:5.1f} s] {text}", flush=True)

    step("starting " + " ".join(command))
    with Sandbox(command, SESSION_SECONDS) as sandbox:
        if not sandbox.wait_for(r"^window\s+\d+x\d+", timeout=60):
            return "the sandbox did not open its window within 60 s"
        listed = sandbox.wait_for(r"^materials\s+(.*) \(number keys", timeout=1)
        body_material = re.search(r"7 (\S+) #([0-9A-F]{6})", listed.group(1)) if listed else None
        if not body_material:
            return "the sandbox did not list state 7 (the body material) with its colour at start"
        colour = tuple(bytes.fromhex(body_material.group(2)))
        step(f"bodies are drawn in state 7, {body_material.group(1)} #{body_material.group(2)}")
        window = find_window(timeout=10)
        if window is None:
            return "no X window named 'granular sandbox'"
        geometry = dict(line.split("=", 1) for line in xdotool("getwindowgeometry", "--shell", window).split())
        centre_x, centre_y = int(geometry["WIDTH"]) // 2, int(geometry["HEIGHT"]) // 2
        # Without a window manager the keyboard focus follows the pointer: put it on the window.
        xdotool("mousemove", "--window", window, str(centre_x), str(centre_y))
        if not sandbox.wait_for(r"^renderer: \w+ \(auto: .*chosen\)$", timeout=150):
            return "the automatic renderer choice printed no final 'renderer: NAME (auto: ...)' line"
        renderer = [m for m in (re.match(r"^renderer: (\w+)", line) for line in sandbox.lines) if m][-1].group(1)
        step(f"renderer {renderer}")

        def tap(key, reply, timeout=30):
            mark = len(sandbox.lines)
            xdotool("key", key)
            return sandbox.wait_for(reply, timeout=timeout, after=mark)

        def screenshot():
            shot = tap("p", r"^screenshot: (.+)$")
            if not shot or not os.path.isfile(shot.group(1)):
                return None, None
            return shot.group(1), body_pixels(shot.group(1), colour)

        # The sand settles faster at 4 ticks per update; Ctrl+S says which tick the world is at.
        for ticks in (2, 3, 4):
            if not tap("bracketright", rf"^ticks per update: {ticks}$"):
                return f"] did not print 'ticks per update: {ticks}'"
        tick = 0
        while tick < SETTLED_TICK:
            saved = tap("ctrl+s", r"^saved: .* tick (\d+), hash")
            if not saved:
                return "Ctrl+S printed no 'saved: ... tick T, hash H' line"
            tick = int(saved.group(1))
            if tick < SETTLED_TICK:
                time.sleep(3)
        for ticks in (3, 2, 1):
            if not tap("bracketleft", rf"^ticks per update: {ticks}$"):
                return f"[ did not print 'ticks per update: {ticks}'"
        step(f"the sand settled (tick {tick}); back to 1 tick per update, the rules' real-time rate")

        path, before = screenshot()
        if path is None:
            return "P wrote no screenshot before the throw"
        step(f"before the throw, {path}: {before} pixels of the body colour")
        if before > 5:
            return f"the screenshot before any throw has {before} pixels of the body colour outside the HUD"

        xdotool("mousemove", "--window", window, str(centre_x), str(centre_y))
        throw = tap("t", r"^throw: body (\d+), a (\w+) of half size (\d+) cells and (\d+) kg/m\^3 .* from \("
                         + NUMBER + ", " + NUMBER + ", " + NUMBER + r"\) at " + NUMBER + r" m/s = \(" + NUMBER + ", "
                         + NUMBER + ", " + NUMBER + r"\) cells/tick at tick (\d+) \(ticks of " + NUMBER
                         + r" ms, cells of " + NUMBER + r" mm\); 1 bodies$")
        if not throw:
            return "T printed no 'throw: body N, ...' line for the first body"
        body = throw.group(1)
        radius = int(throw.group(3))
        x0, y0, z0 = (float(throw.group(i)) for i in (5, 6, 7))
        vz = float(throw.group(11))
        tick_at_throw = int(throw.group(12))
        tick_ms, cell_mm = float(throw.group(13)), float(throw.group(14))
        step(throw.group(0))
        if not all(radius < c < GRID - radius for c in (x0, y0, z0)):
            return f"the throw starts at ({x0}, {y0}, {z0}), not inside the grid with room for its radius {radius}"

        landed = sandbox.wait_for(rf"^body {body}: landed in (\w+) at tick (\d+), (\d+) ticks after the throw, "
                                  rf"centre at z {NUMBER}", timeout=120)
        if not landed:
            return f"body {body} printed no 'landed' line within 120 s"
        step(landed.group(0))
        if landed.group(1) != "granular":
            return f"body {body} landed in {landed.group(1)}, not in the bowl's sand"
        ticks, z_landed = int(landed.group(3)), float(landed.group(4))
        # The free fall from the throw: z0 + vz t - g t^2 / 2 = z_landed, g in cells per tick^2.
        g = 9.81 * (tick_ms * 1e-3) ** 2 / (cell_mm * 1e-3)
        expected = (vz + math.sqrt(vz * vz + 2 * g * (z0 - z_landed))) / g
        step(f"landed after {ticks} ticks; a free fall from z {z0:.1f} at {vz:.2f} cells/tick to z {z_landed:.1f} "
             f"takes {expected:.1f} ticks (g = {g:.2f} cells/tick^2)")
        if ticks < 1 or abs(ticks - expected) > 1 + 0.1 * expected:
            return f"the body took {ticks} ticks to land; a free fall takes {expected:.1f}"

        rest = sandbox.wait_for(rf"^body {body}: at rest at tick (\d+), \d+ ticks after the throw: centre \({NUMBER}, "
                                rf"{NUMBER}, {NUMBER}\), bottom {NUMBER} cells up, (\d+)% submerged, on or in (\w+)$",
                                timeout=180)
        if not rest:
            return f"body {body} printed no 'at rest' line within 180 s of landing"
        step(rest.group(0))
        centre = [float(rest.group(i)) for i in (2, 3, 4)]
        submerged, under = int(rest.group(6)), rest.group(7)
        if not all(radius - 0.5 <= c <= GRID - radius + 0.5 for c in centre):
            return f"the body rests at {centre}, out of the grid"
        if under != "granular" or not 20 <= submerged <= 80:
            return f"a ball of 800 kg/m^3 rests {submerged}% submerged in {under}; expected about half in granular"

        # The cursor onto the sky, so that the brush's preview does not cover the body.
        xdotool("mousemove", "--window", window, str(SKY[0]), str(SKY[1]))
        time.sleep(0.5)
        order = ["cubes", "marching", "raymarch"]
        for k in range(3):
            if k > 0:
                renderer = order[(order.index(renderer) + 1) % 3]
                if not tap("c", rf"^renderer: {renderer}$"):
                    return f"C did not switch the renderer to {renderer}"
                time.sleep(1)
            path, seen = screenshot()
            if path is None:
                return f"P wrote no screenshot in {renderer}"
            step(f"{renderer}, {path}: {seen} pixels of the body colour")
            if seen < BODY_PIXELS:
                return f"the {renderer} screenshot {path} shows {seen} pixels of the body colour, fewer than {BODY_PIXELS}"

        # The HUD's density slider dragged past its right end: 8000 kg/m^3, steel. Thrown through
        # another point of the window, the ball sinks through the sand below the light one.
        xdotool("mousemove", "--window", window, str(DENSITY_SLIDER[0]), str(DENSITY_SLIDER[1]))
        xdotool("mousedown", "1")
        time.sleep(0.6)
        xdotool("mousemove", "--window", window, str(DENSITY_SLIDER[0] + 250), str(DENSITY_SLIDER[1]))
        time.sleep(0.6)
        xdotool("mouseup", "1")
        time.sleep(0.3)
        xdotool("mousemove", "--window", window, str(HEAVY_AIM[0]), str(HEAVY_AIM[1]))
        time.sleep(0.3)
        heavy = tap("t", r"^throw: body (\d+), a ball of half size \d+ cells and (\d+) kg/m\^3 \((.*?)\).*; 2 bodies$")
        if not heavy:
            return "a second T printed no 'throw: body N, ... ; 2 bodies' line"
        step(heavy.group(0))
        if heavy.group(2) != "8000":
            return (f"after dragging the HUD's density slider to its end the throw has {heavy.group(2)} kg/m^3, not "
                    f"8000 (did the HUD's layout move? the slider was at {DENSITY_SLIDER})")
        sunk = sandbox.wait_for(rf"^body {heavy.group(1)}: at rest at tick \d+, (\d+) ticks after the throw: centre "
                                rf"\({NUMBER}, {NUMBER}, {NUMBER}\), bottom {NUMBER} cells up, (\d+)% submerged, on or in "
                                rf"(\w+)$", timeout=240)
        if not sunk:
            return f"the steel ball (body {heavy.group(1)}) printed no 'at rest' line within 240 s"
        step(sunk.group(0))
        if float(sunk.group(4)) > centre[2] - 2 * radius or int(sunk.group(6)) < 95:
            return (f"the steel ball rests with its centre at z {sunk.group(4)}, {sunk.group(6)}% submerged; the light "
                    f"one floats at z {centre[2]}: steel should sink deeper, under the surface")

        mark = len(sandbox.lines)
        undo = tap("ctrl+z", r"^undo: tick (\d+), hash")
        if not undo or not sandbox.wait_for(r"^bodies: 1 \(1 removed, 0 added\)$", timeout=10, after=mark):
            return "the first Ctrl+Z did not take the steel ball back ('bodies: 1 (1 removed, 0 added)')"
        step("Ctrl+Z: " + undo.group(0) + "; the steel ball is gone")
        mark = len(sandbox.lines)
        undo = tap("ctrl+z", r"^undo: tick (\d+), hash")
        if not undo:
            return "Ctrl+Z printed no 'undo: tick T, hash H' line"
        if int(undo.group(1)) != tick_at_throw:
            return f"Ctrl+Z went back to tick {undo.group(1)}, not the throw's tick {tick_at_throw}"
        if not sandbox.wait_for(r"^bodies: 0 \(1 removed, 0 added\)$", timeout=10, after=mark):
            return "after Ctrl+Z the sandbox did not print 'bodies: 0 (1 removed, 0 added)'"
        step("Ctrl+Z: " + undo.group(0) + "; the body is gone from the World and Bullet")
        time.sleep(1)
        path, after_undo = screenshot()
        step(f"after the undo, {path}: {after_undo} pixels of the body colour")
        if path is None or after_undo > 5:
            return f"after Ctrl+Z the screenshot still shows {after_undo} pixels of the body colour"

        mark = len(sandbox.lines)
        redo = tap("ctrl+shift+z", r"^redo: tick (\d+), hash")
        if not redo or not sandbox.wait_for(r"^bodies: 1 \(0 removed, 1 added\)$", timeout=10, after=mark):
            return "Ctrl+Shift+Z did not print 'redo: ...' and 'bodies: 1 (0 removed, 1 added)'"
        step("Ctrl+Shift+Z: " + redo.group(0) + "; the body is back in the World and Bullet")
        mark = len(sandbox.lines)
        if not tap("space", r"^running$"):
            return "Space after the redo did not print 'running'"
        again = sandbox.wait_for(rf"^body {body}: landed in (\w+) at tick (\d+)", timeout=120, after=mark)
        if not again:
            return f"after the redo, body {body} printed no 'landed' line within 120 s"
        step(again.group(0))
        if abs(int(again.group(2)) - int(landed.group(2))) > 1:
            return f"after the redo the body landed at tick {again.group(2)}, the first time at {landed.group(2)}"

        # A snapshot holds the body: Ctrl+S, then Ctrl+O loads it into a new session, whose Bullet gets it.
        saved = tap("ctrl+s", r"^saved: (.+) \((\d+) cells, tick (\d+), hash ([0-9a-f]{16})\)$")
        if not saved:
            return "Ctrl+S printed no 'saved: FILE (N cells, tick T, hash H)' line"
        mark = len(sandbox.lines)
        loaded = tap("ctrl+o", r"^loaded: (.+) \((\d+) cells, tick (\d+), hash ([0-9a-f]{16})\)$")
        if not loaded or loaded.groups() != saved.groups():
            return f"Ctrl+O did not load what Ctrl+S saved ({saved.group(0) if saved else None})"
        if not sandbox.wait_for(r"^bodies: 1 \(0 removed, 1 added\)$", timeout=10, after=mark):
            return "the loaded snapshot's body got no rigid body ('bodies: 1 (0 removed, 1 added)')"
        step(loaded.group(0) + "; its body is in Bullet")

        xdotool("key", "Escape")
        status = sandbox.process.wait(timeout=60)
        if status != 0:
            return f"the sandbox exited with status {status}"
        step("Esc: closed with exit status 0")
        return None


def main():
    return session_main(__doc__, "windowed-bodies-", lambda command, folder: run(
        command + ["--screenshot-dir", folder, "--save", os.path.join(folder, "bodies.gsnap")], folder))


if __name__ == "__main__":
    sys.exit(main())
