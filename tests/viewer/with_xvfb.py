#!/usr/bin/env python3
"""Runs a command on a virtual X display of its own, as `xvfb-run -a` does, without its race: Xvfb
picks the free display number itself (-displayfd), so runs started at the same moment (ctest -j,
other checkouts' tests) never share one or lose it to another. The display is 1280x1024x24, as
xvfb-run's, and does not reset when its last client disconnects (-noreset): an X server resetting
refuses connections for a moment, so a client that connects twice in a row (vulkaninfo, which
scripts/launch runs first) or right after another one (the sandbox after vulkaninfo) would fail at
random, about once in fifty. It ends with the command (or with this script).

usage: with_xvfb.py COMMAND [ARGS...]; exit status: the command's (1 when Xvfb does not start).
"""

import ctypes
import os
import select
import signal
import subprocess
import sys
import tempfile

START_SECONDS = 30


def die_with_parent():
    """In the Xvfb child: the kernel ends it when this script ends, even if this script is killed."""
    ctypes.CDLL(None).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG


def start_server(log):
    read_end, write_end = os.pipe()
    server = subprocess.Popen(
        ["Xvfb", "-displayfd", str(write_end), "-screen", "0", "1280x1024x24", "-nolisten", "tcp", "-noreset"],
        pass_fds=(write_end,), stdin=subprocess.DEVNULL, stdout=log, stderr=log, preexec_fn=die_with_parent)
    os.close(write_end)
    number = b""
    while not number.endswith(b"\n"):
        ready, _, _ = select.select([read_end], [], [], START_SECONDS)
        chunk = os.read(read_end, 16) if ready else b""
        if not chunk:
            break
        number += chunk
    os.close(read_end)
    if not number.strip().isdigit():
        server.kill()
        server.wait()
        return server, None
    return server, number.strip().decode()


def main():
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    with tempfile.TemporaryFile() as log:
        server, display = start_server(log)
        if display is None:
            log.seek(0)
            sys.stderr.write(log.read().decode(errors="replace"))
            print(f"with_xvfb: Xvfb did not start within {START_SECONDS} s", file=sys.stderr)
            return 1
        env = dict(os.environ, DISPLAY=":" + display)
        env.pop("WAYLAND_DISPLAY", None)
        try:
            return subprocess.call(sys.argv[1:], env=env)
        finally:
            server.terminate()
            try:
                server.wait(timeout=10)
            except subprocess.TimeoutExpired:
                server.kill()
                server.wait()


if __name__ == "__main__":
    sys.exit(main())
