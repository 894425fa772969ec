#!/usr/bin/env python3
"""Plots a run-time-against-error table (bench.csv written by pleat-train bench).

usage: plot_bench.py BENCH_CSV OUT_PNG

x: ms per frame (log scale), y: E_verts in cm. One marker per row, coloured
by engine; the Pareto front (no row both faster and more accurate) is joined
by a line and labelled.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = {"pleat": "tab:blue", "libtorch": "tab:orange", "LBS": "tab:grey"}


def main():
    csv_path, out_path = sys.argv[1:3]
    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{csv_path}: no rows")
    fig, ax = plt.subplots(figsize=(8, 5), dpi=100)
    # Pareto rows are labelled in full; the others by their setting, small
    # and grey, so that the front stays readable where settings crowd.
    for r in rows:
        x, y = float(r["ms_per_frame"]), float(r["e_verts_cm"])
        ax.scatter(x, y, color=COLOURS.get(r["engine"], "black"), zorder=3)
        on_front = r["pareto"] == "1"
        ax.annotate(f'{r["engine"]}: {r["setting"]}' if on_front else r["setting"], (x, y),
                    fontsize=7 if on_front else 6, color="black" if on_front else "grey",
                    xytext=(4, 3) if on_front else (4, -9), textcoords="offset points")
    front = sorted((float(r["ms_per_frame"]), float(r["e_verts_cm"])) for r in rows if r["pareto"] == "1")
    ax.plot([p[0] for p in front], [p[1] for p in front], color="tab:red", linewidth=1, zorder=2,
            label="Pareto front")
    ax.set_xscale("log")
    ax.set_xlabel("ms per frame (log)")
    ax.set_ylabel("E_verts (cm)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="upper right")
    fig.tight_layout()
    fig.savefig(out_path)


if __name__ == "__main__":
    main()
