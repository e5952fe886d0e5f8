#!/usr/bin/env python3
"""Plots the cost table of `fusion-loadbench --scaling` (read from its output) as an SVG.

    fusion-loadbench --offline-only --scaling | tee scaling.txt
    python3 tools/plot_scaling.py scaling.txt docs/scaling.svg

Left: CPU per set against targets, one line per sensor count; right: the multiple of real time
on one core and on two threads, with the real-time line (1x).
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_table(path):
    """Rows of the markdown table: (targets, sensors, us_per_set, x_one_core, x_two_threads, mib)."""
    rows = []
    with open(path, encoding="utf-8") as text:
        for line in text:
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if len(cells) != 7 or not cells[0].isdigit():
                continue
            targets, sensors, _, us, one, two, mib = cells
            rows.append((int(targets), int(sensors), float(us), float(one), float(two), float(mib)))
    if not rows:
        sys.exit(f"{path}: no scaling table found (run fusion-loadbench --scaling)")
    return rows


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    rows = read_table(sys.argv[1])
    sensors = sorted({r[1] for r in rows})
    fig, (cost, speed) = plt.subplots(1, 2, figsize=(10, 4))
    for n in sensors:
        mine = sorted(r for r in rows if r[1] == n)
        targets = [r[0] for r in mine]
        cost.plot(targets, [r[2] for r in mine], marker="o", label=f"{n} sensors")
        line = speed.plot(targets, [r[3] for r in mine], marker="o", label=f"{n} sensors, 1 core")
        speed.plot(targets, [r[4] for r in mine], marker="x", linestyle="--",
                   color=line[0].get_color(), label=f"{n} sensors, 2 threads")
    for axis in (cost, speed):
        axis.set_xscale("log")
        axis.set_yscale("log")
        axis.set_xlabel("targets")
        axis.grid(True, which="both", alpha=0.3)
    cost.set_ylabel("CPU per set, one core (µs)")
    speed.set_ylabel("× real time")
    speed.axhline(1.0, color="black", linewidth=1)
    speed.text(min(r[0] for r in rows), 1.05, "real time", fontsize=8)
    cost.legend(fontsize=8)
    speed.legend(fontsize=6, ncol=2)
    fig.suptitle("fusion-server engine: cost per set, sensors at 30 Hz, 20 clutter per set")
    fig.tight_layout()
    fig.savefig(sys.argv[2])


if __name__ == "__main__":
    main()
