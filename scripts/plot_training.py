#!/usr/bin/env python3
"""Plots a training log (log.csv written by pleat-train) as a PNG.

usage: plot_training.py LOG_CSV OUT_PNG

Left: the weighted training loss (log scale). Right: E_verts of the training
batches and of the validation set, and the validation band errors, in cm.
Phase changes are marked with vertical lines.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    log_path, out_path = sys.argv[1:3]
    with open(log_path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{log_path}: no epochs logged")
    epoch = [int(r["epoch"]) for r in rows]
    column = lambda name: [float(r[name]) for r in rows]  # noqa: E731
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4), dpi=100)
    left.plot(epoch, column("loss"), color="black")
    left.set_yscale("log")
    left.set_xlabel("epoch")
    left.set_title("training loss (weighted)")
    right.plot(epoch, column("train_e_verts_cm"), label="E_verts, training batches")
    for name, label in [("e_verts_cm", "E_verts, validation"), ("e_low_cm", "low band"),
                        ("e_mid_cm", "mid band"), ("e_high_cm", "high band")]:
        if any(v != 0 for v in column(name)):
            right.plot(epoch, column(name), label=label)
    right.set_xlabel("epoch")
    right.set_ylabel("cm")
    right.set_title("errors")
    right.legend()
    for i in range(1, len(rows)):
        if rows[i]["phase"] != rows[i - 1]["phase"]:
            for axis in (left, right):
                axis.axvline(epoch[i], color="grey", linestyle=":")
    fig.tight_layout()
    fig.savefig(out_path)


if __name__ == "__main__":
    main()
