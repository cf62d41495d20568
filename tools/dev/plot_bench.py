#!/usr/bin/env python3
"""Plots `vknerf bench train` output: held-out PSNR against training seconds (one curve per
configuration) and render seconds per frame against PSNR. Usage: plot_bench.py DIR [OUT.png]
(Debian: python3-matplotlib)."""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")  # headless: CI and servers have no display
import matplotlib.pyplot as plt


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit("usage: plot_bench.py DIR [OUT.png]")
    folder = sys.argv[1]
    out = sys.argv[2] if len(sys.argv) == 3 else f"{folder}/psnr_vs_time.png"
    train, render = read(f"{folder}/train.csv"), read(f"{folder}/render.csv")
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2))
    curves = defaultdict(list)
    for r in train:
        curves[r["config"]].append((float(r["seconds"]), float(r["psnr"])))
    for name, pts in curves.items():
        a.plot([0] + [p[0] for p in pts], [None] + [p[1] for p in pts], marker="o", label=name)
    a.set_xlabel("training time (s)")
    a.set_ylabel("held-out PSNR (dB)")
    a.set_title("training: PSNR against time")
    a.grid(alpha=0.3)
    a.legend()
    frames = defaultdict(list)
    for r in render:
        frames[r["config"]].append((float(r["seconds_per_frame"]), float(r["psnr"]), r["budget"]))
    for name, pts in frames.items():
        b.plot([p[0] for p in pts], [p[1] for p in pts], marker="s", label=name)
        for s, p, budget in pts:
            b.annotate(budget, (s, p), textcoords="offset points", xytext=(4, 4), fontsize=8)
    b.set_xscale("log")
    b.set_xlabel("render time per frame (s, log)")
    b.set_ylabel("PSNR (dB)")
    b.set_title("rendering: PSNR against time per frame")
    b.grid(alpha=0.3)
    b.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
