#!/usr/bin/env python3
"""A user's first minute with the windowed sandbox, on a virtual display (run it inside with_xvfb.py,
as ctest viewer.windowed_session does, or `xvfb-run -a`): starts LAUNCHER (scripts/launch, what
./scripts/run execs after installing and building), checks the window is still open after 10 s and
that the automatic renderer choice (--renderer auto, the default) printed its final choice, taps C
(xdotool's default 12 ms key press) and sees the renderer switch to the next one, taps Tab through
erase to shake (the default rules have a motion model), clicks on the sand and sees cells set
moving, taps Tab back to dig, clicks on the sand and sees it dug, undoes the dig with Ctrl+Z (the
world of the stroke's start: its tick and hash) and redoes it with Ctrl+Shift+Z (the stroke's end),
saves a snapshot with Ctrl+S, resumes and loads it back with Ctrl+O (the saved tick and hash),
chooses the liquid (key 3) and pours it with a right click, chooses solid (key 1) and paints it with
a right click, taps V (a section across x), comma and period (the plane one step down and back), B
(x-ray on) and P (a screenshot, which must exist as a PNG of the window's size), keeps the window
open for more than 60 frames while tapping every material key 1..7 in turn (each must choose the
material the sandbox listed for it at start), presses Esc and sees exit status 0, the snapshot
--save names written on exit and, in the screenshot of the last frame, the HUD's colour swatch of
every listed material.
The sandbox prints one line per user action on stdout ("renderer: marching", "left button: shake
(...)", "shake: 109 cells set moving (from tick T, hash H, to tick T, hash H)", "dig: 137 cells
removed (...)", "undo: tick T, hash H (...)", "saved: FILE (N cells, tick T, hash H)", "material:
liquid (right button pours it)", "section: x 0.47", "x-ray: on", "screenshot: FILE"); this script
reads them. Every wait is bounded; exit status 0 on success, 1 with the reason otherwise.

usage: windowed_session.py LAUNCHER [ARGS...]
"""

import os
import re
import subprocess
import sys
import tempfile
import threading
import time

from png_pixels import has_square_of_colour, png_size, read_png

WINDOW_TITLE = "granular sandbox"
FRAMES_TO_OUTLAST = 61  # more frames than the 60 after which the window once closed itself
SESSION_SECONDS = 200  # every wait ends by then: the whole test ends within 205 s (ctest allows 240)
STROKE = r" \(from tick (\d+), hash ([0-9a-f]{16}), to tick (\d+), hash ([0-9a-f]{16})\)$"  # a stroke line's end
STATE = r" \((\d+) cells, tick (\d+), hash ([0-9a-f]{16})\)$"  # a save or load line's end
HUD_CORNER = 480  # the HUD window lies within the window's top-left 480 x 480 pixels
SWATCH_SQUARE = 10  # a swatch (14 pixels) holds a square of this side of its exact colour


class Sandbox:
    """The launched process and the lines it printed so far; as a context manager, the process is
    killed on leaving it if it still runs."""

    def __init__(self, command, seconds=SESSION_SECONDS):
        self.deadline = time.monotonic() + seconds
        self.process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, bufsize=1)
        self.lines = []
        self.ended = False  # its output closed
        self.changed = threading.Condition()
        threading.Thread(target=self._read, daemon=True).start()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait(timeout=10)
        return False

    def _read(self):
        for line in self.process.stdout:
            sys.stdout.write("  | " + line)
            sys.stdout.flush()
            with self.changed:
                self.lines.append(line.rstrip("\n"))
                self.changed.notify_all()
        with self.changed:
            self.ended = True
            self.changed.notify_all()

    def wait_for(self, pattern, timeout, after=0):
        """The first match of `pattern` in a line printed after line `after`, waiting up to `timeout`
        seconds (and no later than the session's deadline); None when it did not come (or the process
        ended without it)."""
        deadline = min(time.monotonic() + timeout, self.deadline)
        regex = re.compile(pattern)
        with self.changed:
            while True:
                for line in self.lines[after:]:
                    match = regex.search(line)
                    if match:
                        return match
                left = deadline - time.monotonic()
                if left <= 0 or self.ended:
                    return None
                self.changed.wait(left)


def xdotool(*args, timeout=10):
    """Runs xdotool; returns its stdout (raises on failure or after `timeout` seconds)."""
    result = subprocess.run(["xdotool", *args], capture_output=True, text=True, timeout=timeout)
    if result.returncode != 0:
        raise RuntimeError(f"xdotool {' '.join(args)} failed: {result.stderr.strip()}")
    return result.stdout


def find_window(timeout):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        result = subprocess.run(["xdotool", "search", "--name", f"^{WINDOW_TITLE}$"], capture_output=True, text=True,
                                timeout=10)
        ids = result.stdout.split()
        if ids:
            return ids[0]
        time.sleep(0.2)
    return None


def run(command, screenshot, screenshot_dir, snapshot):
    started = time.monotonic()

    def step(text):
        print(f"[{time.monotonic() - started:5.1f} s] {text}", flush=True)

    step("starting " + " ".join(command))
    with Sandbox(command) as sandbox:
        if not sandbox.wait_for(r"^window\s+\d+x\d+", timeout=60):
            return "the sandbox did not open its window within 60 s"
        listed = sandbox.wait_for(r"^materials\s+(.*) \(number keys", timeout=1)
        if not listed:
            return "the sandbox did not list its materials at start"
        items = [re.fullmatch(r"(\d) (.+) #([0-9A-F]{6})", item) for item in listed.group(1).split(", ")]
        if not all(items):
            return f"the materials line does not read 'KEY NAME #RRGGBB, ...': {listed.group(1)}"
        materials = {item.group(1): item.group(2) for item in items}
        colours = {item.group(1): bytes.fromhex(item.group(3)) for item in items}
        if sorted(materials) != [str(key) for key in range(1, 8)]:
            return f"the sandbox offers keys {sorted(materials)}, expected 1..7"
        step("materials on keys: " + ", ".join(f"{key} {name}" for key, name in sorted(materials.items())))
        window = find_window(timeout=10)
        if window is None:
            return f"no X window named '{WINDOW_TITLE}'"
        step(f"window {window} open; waiting 10 s")
        time.sleep(10)
        if sandbox.process.poll() is not None:
            return f"the sandbox closed by itself within 10 s (exit status {sandbox.process.returncode})"
        step("still running after 10 s")

        geometry = dict(line.split("=", 1) for line in xdotool("getwindowgeometry", "--shell", window).split())
        centre_x, centre_y = int(geometry["WIDTH"]) // 2, int(geometry["HEIGHT"]) // 2
        # Without a window manager the keyboard focus follows the pointer: put it on the window.
        xdotool("mousemove", "--window", window, str(centre_x), str(centre_y))
        time.sleep(0.5)

        # --renderer auto (the default) measures the three renderers, at least three frames each
        # (seconds on a loaded lavapipe), and prints its choice.
        if not sandbox.wait_for(r"^renderer: \w+ \(auto: .*chosen\)$", timeout=120):
            return "the automatic renderer choice printed no final 'renderer: NAME (auto: ...)' line within 130 s"
        chosen = [m for m in (re.match(r"^renderer: (\w+) \(auto: (.*)\)$", line) for line in sandbox.lines) if m]
        step("auto renderer choice: " + "; ".join(m.group(0) for m in chosen))
        order = ["cubes", "marching", "raymarch"]
        renderer = order[(order.index(chosen[-1].group(1)) + 1) % 3]
        mark = len(sandbox.lines)
        step("tapping C (12 ms)")
        xdotool("key", "c")
        if not sandbox.wait_for(rf"^renderer: {renderer}$", timeout=20, after=mark):
            return f"a C tap did not switch the renderer to {renderer} within 20 s"
        step("the renderer switched")

        # Tab cycles the left button through dig, erase and shake; a click with shake chosen sets
        # the sand at the cursor moving, and the next Tab brings dig back.
        for tool in ("erase", "shake"):
            mark = len(sandbox.lines)
            xdotool("key", "Tab")
            if not sandbox.wait_for(rf"^left button: {tool} \(", timeout=20, after=mark):
                return f"a Tab tap did not switch the left button to {tool} within 20 s"
        step("Tab switched the left button to erase, then to shake")

        def click_centre(button, line, unanswered, nothing, hold=0.0):
            """A click of `button` at the window's centre (held for `hold` seconds) must print `line`
            with a count above 0: returns the match, or the failure's text."""
            mark = len(sandbox.lines)
            xdotool("mousemove", "--window", window, str(centre_x), str(centre_y))
            if hold > 0:
                xdotool("mousedown", button)
                time.sleep(hold)
                xdotool("mouseup", button)
            else:
                xdotool("click", button)
            printed = sandbox.wait_for(line, timeout=20, after=mark)
            if not printed:
                return unanswered
            if int(printed.group(1)) <= 0:
                return nothing
            return printed

        def click_sand(tool, line, did, hold=0.0):
            """A left click at the centre, on the sand, with `tool` (held for `hold` seconds); None
            when it printed `line`."""
            step(f"clicking at the window's centre ({centre_x}, {centre_y}), on the sand, with {tool}")
            printed = click_centre("1", line, f"a click with {tool} chosen printed nothing within 20 s",
                                   f"a click on the sand with {tool} chosen {did} no cell", hold)
            if isinstance(printed, str):
                return printed
            step(f"the click with {tool}: {printed.group(0)}")
            return None

        failure = click_sand("shake", r"^shake: (\d+) cells set moving" + STROKE, "set moving")
        if failure:
            return failure
        mark = len(sandbox.lines)
        xdotool("key", "Tab")
        if not sandbox.wait_for(r"^left button: dig \(", timeout=20, after=mark):
            return "a Tab tap after shake did not switch the left button back to dig within 20 s"
        step("Tab switched the left button back to dig")
        mark = len(sandbox.lines)
        # Held for 2 s, so that the world steps during the stroke (and on after it, until Ctrl+Z).
        failure = click_sand("dig", r"^dig: (\d+) cells removed" + STROKE, "removed", hold=2.0)
        if failure:
            return failure
        dig = sandbox.wait_for(r"^dig: (\d+) cells removed" + STROKE, timeout=1, after=mark)
        start, end = (dig.group(2), dig.group(3)), (dig.group(4), dig.group(5))

        # Ctrl+Z gives back the world the dig started from, Ctrl+Shift+Z the one it ended with.
        for keys, name, expected in (("ctrl+z", "undo", start), ("ctrl+shift+z", "redo", end)):
            mark = len(sandbox.lines)
            xdotool("key", keys)
            moved = sandbox.wait_for(rf"^{name}: tick (\d+), hash ([0-9a-f]{{16}}) \(", timeout=20, after=mark)
            if not moved:
                return f"{keys} printed no '{name}: tick T, hash H' line within 20 s"
            if moved.groups() != expected:
                return (f"{keys} gave tick {moved.group(1)}, hash {moved.group(2)}; the dig's "
                        f"{'start' if name == 'undo' else 'end'} was tick {expected[0]}, hash {expected[1]}")
            step(f"{keys}: {moved.group(0)}")

        # Ctrl+S saves the (paused) world; after it runs on, Ctrl+O loads the saved world back.
        mark = len(sandbox.lines)
        xdotool("key", "ctrl+s")
        saved = sandbox.wait_for(r"^saved: (.+)" + STATE, timeout=20, after=mark)
        if not saved:
            return "Ctrl+S printed no 'saved: FILE (N cells, tick T, hash H)' line within 20 s"
        if saved.group(1) != snapshot or not os.path.isfile(snapshot):
            return f"Ctrl+S saved {saved.group(1)}, expected the --save file {snapshot}"
        step(saved.group(0))
        mark = len(sandbox.lines)
        xdotool("key", "space")
        if not sandbox.wait_for(r"^running$", timeout=20, after=mark):
            return "a tap of space after the undo did not print 'running' within 20 s"
        time.sleep(2)
        mark = len(sandbox.lines)
        xdotool("key", "ctrl+o")
        loaded = sandbox.wait_for(r"^loaded: (.+)" + STATE, timeout=30, after=mark)
        if not loaded:
            return "Ctrl+O printed no 'loaded: FILE (N cells, tick T, hash H)' line within 30 s"
        if loaded.groups() != saved.groups():
            return f"Ctrl+O loaded '{loaded.group(0)}', but Ctrl+S had '{saved.group(0)}'"
        step(loaded.group(0))

        # Key 3 chooses the presets' liquid (poured), key 1 solid (painted as structure); a right
        # click applies each at the window's centre.
        for key in ("3", "1"):
            mark = len(sandbox.lines)
            xdotool("key", key)
            chosen = sandbox.wait_for(r"^material: (.+) \(right button (pours|paints) it\)$", timeout=20, after=mark)
            if not chosen:
                return f"a tap of {key} did not choose a material within 20 s"
            name, use = chosen.group(1), chosen.group(2)
            if name != materials[key]:
                return f"key {key} chose {name}, but the sandbox listed {materials[key]} for it"
            pattern = (rf"^pour: (\d+) {re.escape(name)} cells added" if use == "pours"
                       else rf"^place: (\d+) {re.escape(name)} cells placed") + STROKE
            applied = click_centre("3", pattern, f"a right click with {name} chosen did not {use[:-1]} it within 20 s",
                                   f"a right click with {name} chosen changed no cell")
            if isinstance(applied, str):
                return applied
            step(f"a right click {use} {applied.group(1)} cells of {name}")

        # More than 60 frames with the window open, counted by the sandbox's own acknowledgements:
        # each tap of a material key is sent after the previous one was acknowledged, so each
        # acknowledgement is printed by a later frame. Paused and ray marched (C taps up to it), a
        # frame costs little even on lavapipe.
        current = order.index(renderer)
        taps = [("c", f"renderer: {order[(current + k) % 3]}") for k in range(1, (2 - current) % 3 + 1)]
        for key, reply in taps + [("space", "paused")]:
            mark = len(sandbox.lines)
            xdotool("key", key)
            if not sandbox.wait_for(f"^{reply}$", timeout=20, after=mark):
                return f"a tap of {key} did not print '{reply}' within 20 s"
        # See inside (paused and ray marched, so each frame is quick): V cuts across x at the middle,
        # comma and period move the plane a step down and back, B turns x-ray on; P writes the frame
        # to the screenshot folder.
        for key, reply in (("v", "section: x 0.50"), ("comma", "section: x 0.47"), ("period", "section: x 0.50"),
                           ("b", "x-ray: on")):
            mark = len(sandbox.lines)
            xdotool("key", key)
            if not sandbox.wait_for(f"^{re.escape(reply)}$", timeout=20, after=mark):
                return f"a tap of {key} did not print '{reply}' within 20 s"
            step(f"{key}: {reply}")
        mark = len(sandbox.lines)
        xdotool("key", "p")
        shot = sandbox.wait_for(r"^screenshot: (.+)$", timeout=20, after=mark)
        if not shot:
            return "a tap of P did not print 'screenshot: FILE' within 20 s"
        written = os.path.basename(shot.group(1))
        if os.path.dirname(shot.group(1)) != screenshot_dir or not written.startswith("granular-screenshot-"):
            return f"P wrote {shot.group(1)}, expected granular-screenshot-N.png in {screenshot_dir}"
        if not os.path.isfile(shot.group(1)):
            return f"P printed {shot.group(1)}, but there is no such file"
        shot_width, shot_height = png_size(shot.group(1))
        if (shot_width, shot_height) != (int(geometry["WIDTH"]), int(geometry["HEIGHT"])):
            return f"the screenshot is {shot_width}x{shot_height}, the window {geometry['WIDTH']}x{geometry['HEIGHT']}"
        step(f"P wrote {shot.group(1)} ({shot_width}x{shot_height})")

        step(f"tapping keys 1..7 in turn until {FRAMES_TO_OUTLAST} frames have acknowledged a tap each")
        for frame in range(FRAMES_TO_OUTLAST):
            key = str(frame % 7 + 1)
            mark = len(sandbox.lines)
            xdotool("key", key)
            if not sandbox.wait_for(rf"^material: {re.escape(materials[key])} \(right button (pours|paints) it\)$",
                                    timeout=10, after=mark):
                if sandbox.process.poll() is not None:
                    return (f"the sandbox closed by itself after {frame} acknowledged taps "
                            f"(exit status {sandbox.process.returncode})")
                return f"tap {frame + 1} (key {key}, {materials[key]}) was not acknowledged within 10 s"
        if sandbox.process.poll() is not None:
            return f"the sandbox closed by itself (exit status {sandbox.process.returncode}) before Esc"
        step(f"still open after {FRAMES_TO_OUTLAST} frames")

        step("pressing Esc")
        mark = len(sandbox.lines)
        xdotool("key", "Escape")
        try:
            status = sandbox.process.wait(timeout=30)
        except subprocess.TimeoutExpired:
            return "the sandbox did not close within 30 s of Esc"
        if status != 0:
            return f"the sandbox exited with status {status}"
        summary = sandbox.wait_for(r"^frames\s+(\d+)", timeout=5)
        if not summary:
            return "the sandbox did not print its summary"
        if int(summary.group(1)) <= FRAMES_TO_OUTLAST:
            return f"the summary counts {summary.group(1)} frames, expected more than {FRAMES_TO_OUTLAST}"
        step("closed with exit status 0")
        if not sandbox.wait_for(rf"^saved: {re.escape(snapshot)}" + STATE, timeout=5, after=mark):
            return f"the sandbox did not write the --save file {snapshot} on exit"
        step("the --save file was written on exit")

        png = read_png(screenshot, HUD_CORNER, HUD_CORNER)
        missing = [f"{key} {materials[key]}" for key in sorted(colours)
                   if not has_square_of_colour(png, colours[key], SWATCH_SQUARE)]
        if missing:
            return "the HUD of the last frame shows no colour swatch of " + ", ".join(missing)
        step("the last frame's HUD shows the swatch of each of the 7 materials")
        return None


def session_main(usage, prefix, run_in):
    """The main of a scripted session: `usage` without a command, else run_in(command, folder) in a
    fresh temporary folder named from `prefix`, then "PASSED" or "FAILED: why"; the exit status."""
    if len(sys.argv) < 2:
        print(usage, file=sys.stderr)
        return 2
    with tempfile.TemporaryDirectory(prefix=prefix) as folder:
        failure = run_in(sys.argv[1:], folder)
    if failure:
        print("FAILED: " + failure, flush=True)
        return 1
    print("PASSED", flush=True)
    return 0


def run_in_folder(command, folder):
    """The session, its screenshot and snapshot in `folder`."""
    screenshot = os.path.join(folder, "last-frame.png")
    snapshot = os.path.join(folder, "session.gsnap")
    return run(command + ["--screenshot", screenshot, "--screenshot-dir", folder, "--save", snapshot], screenshot,
               folder, snapshot)


def main():
    return session_main(__doc__, "windowed-session-", run_in_folder)


if __name__ == "__main__":
    sys.exit(main())
