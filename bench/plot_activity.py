#!/usr/bin/env python3
"""Plots an activity CSV written by bench_activity (sparse against dense stepping over a bowl run)
into a PNG beside it: left, ms per tick against the tick, dense and sparse, with the sparse world's
active cells on a second axis; right, ms per tick against active cells (the cost of a sparse tick
follows the moving grains, a dense tick the grid).

    python3 bench/plot_activity.py path/to/activity_<backend>_<N>.csv

Exits with a message (status 0) when matplotlib is not installed, so scripts may call it blindly.
"""

import csv
import sys
from pathlib import Path


def main() -> int:
    if len(sys.argv) < 2:
        print("usage: plot_activity.py activity_<backend>_<N>.csv")
        return 2
    csv_path = Path(sys.argv[1])
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_activity.py: matplotlib is not installed; no plot written")
        return 0
    rows = list(csv.DictReader(csv_path.open(newline="")))
    if not rows:
        print(f"plot_activity.py: {csv_path} has no rows")
        return 1
    tick = [int(r["tick_end"]) for r in rows]
    dense = [float(r["dense_ms_per_tick"]) for r in rows]
    sparse = [float(r["sparse_ms_per_tick"]) for r in rows]
    active = [float(r["mean_active_cells"]) for r in rows]
    title = f"{rows[0]['backend']}, bowl N={rows[0]['n']}"

    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 4.5))
    left.plot(tick, dense, label="dense: ms/tick")
    left.plot(tick, sparse, label="sparse: ms/tick")
    left.set_yscale("log")
    left.set_xlabel("tick")
    left.set_ylabel("ms per tick")
    left.grid(True, which="both", alpha=0.3)
    cells_axis = left.twinx()
    cells_axis.plot(tick, active, color="gray", linestyle=":", label="sparse: active cells")
    cells_axis.set_ylabel("active cells per tick (sparse)")
    lines = left.get_legend_handles_labels()
    more = cells_axis.get_legend_handles_labels()
    left.legend(lines[0] + more[0], lines[1] + more[1], fontsize=8)
    left.set_title(f"{title}: falling, piling, settled")

    right.scatter(active, dense, s=12, label="dense")
    right.scatter(active, sparse, s=12, label="sparse")
    right.set_xscale("symlog", linthresh=1e3)
    right.set_yscale("log")
    right.set_xlabel("active cells per tick (sparse world)")
    right.set_ylabel("ms per tick")
    right.grid(True, which="both", alpha=0.3)
    right.legend(fontsize=8)
    right.set_title(f"{title}: time per tick against active cells")

    out = csv_path.with_suffix(".png")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
