#!/usr/bin/env python3
"""Plots bench_cuda.csv (written by bench_cuda_step) as cell-updates per second against grid cells,
log-log, one line per variant, into bench_cuda.png beside the CSV.

    python3 bench/plot_cuda.py [path/to/bench_cuda.csv]   (default: ./bench_cuda.csv)

Exits with a message (status 0) when matplotlib is not installed, so scripts may call it blindly.
"""

import csv
import sys
from collections import defaultdict
from pathlib import Path

LABELS = {
    "paper_int32_lut": "(1) paper layout: int32 cells, permutation table",
    "backend_u8_paper": "(2) CUDA backend, paper rule",
    "backend_u8_isotropic": "(2) CUDA backend, isotropic rule",
    "backend_u8_paper_midfall": "(2) CUDA backend, paper rule, mid-fall (worst case)",
    "backend_u8_pair_paper": "(2) CUDA backend, fused tick pairs, paper rule",
    "backend_u8_pair_midfall": "(2) CUDA backend, fused tick pairs, paper rule, mid-fall",
    "memcpy_d2d": "(3) device-to-device copy (bytes/s)",
}


def main() -> int:
    csv_path = Path(sys.argv[1] if len(sys.argv) > 1 else "bench_cuda.csv")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_cuda.py: matplotlib is not installed; no plot written")
        return 0
    series = defaultdict(list)
    with csv_path.open(newline="") as f:
        for row in csv.DictReader(f):
            series[row["variant"]].append((int(row["cells"]), float(row["cell_updates_per_s"])))
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for variant, points in series.items():
        if variant not in LABELS:  # tuning experiments (e.g. fixed chunk heights) stay in the CSV only
            continue
        points.sort()
        ax.plot([p[0] for p in points], [p[1] for p in points], marker="o", label=LABELS.get(variant, variant))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("grid cells (bowl scene, N^3)")
    ax.set_ylabel("cell-updates per second")
    ax.set_title("granular: GPU step throughput")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    out = csv_path.with_suffix(".png")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
