#!/usr/bin/env python3
"""Prints criterion's latest results as a Markdown table (median and its 95 % interval).

Usage: tools/criterion_table.py [CRITERION_DIR]   (default: target/criterion)

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


def main() -> None:
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "target/criterion")
    rows = []
    for bench in sorted(root.glob("**/new/benchmark.json")):
        meta = json.loads(bench.read_text())
        estimates = json.loads((bench.parent / "estimates.json").read_text())["median"]
        interval = estimates["confidence_interval"]
        rows.append((meta["full_id"], estimates["point_estimate"], interval["lower_bound"], interval["upper_bound"]))
    if not rows:
        sys.exit(f"no criterion results under {root}")
    print("| benchmark | median | 95 % interval |")
    print("|---|---|---|")
    for name, median, low, high in rows:
        print(f"| `{name}` | {fmt(median)} | {fmt(low)} – {fmt(high)} |")


if __name__ == "__main__":
    main()
