#!/usr/bin/env python3
"""Prints criterion's latest results as a Markdown table (median and its 95 % interval).

Usage: tools/criterion_table.py [--grid] [CRITERION_DIR]   (default: target/criterion)

With --grid, benchmarks of three parts or more whose ids share all but their last part
(`update/camera/J100/Z10`, `…/Z50`, …) share a row, one column per last part, each cell the
median; the others follow in the plain table.

Criterion keeps each benchmark's last run in <dir>/<group>/<id...>/new/{benchmark,estimates}.json;
BENCHMARKS.md's tables come from this script, so that figures are copied, not retyped.
"""
import json
import pathlib
import sys


def fmt(ns: float) -> str:
    for unit, scale in (("s", 1e9), ("ms", 1e6), ("µs", 1e3)):
        if ns >= scale:
            return f"{ns / scale:.3g} {unit}"
    return f"{ns:.3g} ns"


def print_grid(rows) -> None:
    """One row per id without its last part, one column per last part (medians)."""
    columns, table = [], {}
    for name, median, _, _ in [r for r in rows if r[0].count("/") >= 2]:
        head, _, last = name.rpartition("/")
        if last not in columns:
            columns.append(last)
        table.setdefault(head or name, {})[last] = median
    print("| benchmark | " + " | ".join(f"`{c}`" for c in columns) + " |")
    print("|---|" + "---|" * len(columns))
    for head, cells in table.items():
        print(f"| `{head}` | " + " | ".join(fmt(cells[c]) if c in cells else "–" for c in columns) + " |")


def main() -> None:
    args = sys.argv[1:]
    grid = "--grid" in args
    args = [a for a in args if a != "--grid"]
    root = pathlib.Path(args[0] if args else "target/criterion")
    rows = []
    for bench in sorted(root.glob("**/new/benchmark.json")):
        meta = json.loads(bench.read_text())
        estimates = json.loads((bench.parent / "estimates.json").read_text())["median"]
        interval = estimates["confidence_interval"]
        rows.append((meta["full_id"], estimates["point_estimate"], interval["lower_bound"], interval["upper_bound"]))
    if not rows:
        sys.exit(f"no criterion results under {root}")
    if grid:
        print_grid(rows)
        rows = [r for r in rows if r[0].count("/") < 2]
        if not rows:
            return
        print()
    print("| benchmark | median | 95 % interval |")
    print("|---|---|---|")
    for name, median, low, high in rows:
        print(f"| `{name}` | {fmt(median)} | {fmt(low)} – {fmt(high)} |")


if __name__ == "__main__":
    main()
