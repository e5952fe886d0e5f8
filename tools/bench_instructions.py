#!/usr/bin/env python3
"""Counts the instructions one call of a function takes inside a criterion benchmark (callgrind).

Usage: tools/bench_instructions.py BENCH_BINARY BENCH_FILTER FUNCTION [CALLER]

Runs BENCH_BINARY --bench BENCH_FILTER --profile-time T under valgrind's callgrind twice, for a short
and a long T, and prints the instructions one more call of FUNCTION (the end of its demangled name)
takes, its callees included: the difference of the two runs' totals over the difference of their
call counts. Only calls from a function whose name contains CALLER count, when it is given. The
difference cancels what the first calls cost once (the allocator filling its pages, caches of the
benchmark's setup), which would otherwise weigh more the fewer calls a run makes.

Why: on a shared 2-vCPU host wall-clock runs of the same binary vary by ±20 %, so small changes
drown in the noise; instruction counts are the same on every run and on a loaded host. They are a
proxy for time (they miss cache misses and the cost of each instruction), so BENCHMARKS.md gives
both. Examples (bench binaries as `cargo bench -p gmphd --no-run` lists them):

    tools/bench_instructions.py target/.../deps/update-HASH '^update/camera_unscented/J100/Z50$' \\
        gmphd::update::update_gated
    # the dense step's timed calls only (its 2 s warm-up calls the same function from main)
    tools/bench_instructions.py target/.../deps/dense-HASH dense \\
        gmphd::tracker::LabelledTracker::step iter_custom

Needs valgrind (`apt-get install valgrind`); not used by CI.
"""
import os
import re
import subprocess
import sys
import tempfile

# callgrind's output names each function once, as "fn=(id) name", and refers to it later as
# "fn=(id)"; a call is "cfn=(id)" followed by "calls=N ..." and the line with its inclusive cost.
# Seconds of criterion profiling for the two runs (under callgrind, about 50 times slower than
# native).
PROFILE_SECONDS = ("2", "6")
NAME = re.compile(r"(c?)fn=\((\d+)\)(?: (.*))?")


def calls_and_cost(path: str, function: str, caller: str) -> tuple[int, int]:
    """Total calls of `function` from callers whose name contains `caller`, and their cost."""
    names: dict[str, str] = {}
    current = ""
    calls = cost = 0
    with open(path) as profile:
        lines = profile.read().split("\n")
    for i, line in enumerate(lines):
        match = NAME.match(line)
        if not match:
            continue
        is_call, ident, name = match.groups()
        if name:
            names[ident] = name
        name = names.get(ident, "")
        if not is_call:
            current = name
        elif name.endswith(function) and caller in current and lines[i + 1].startswith("calls="):
            calls += int(lines[i + 1].split("=")[1].split()[0])
            cost += int(lines[i + 2].split()[1])
    return calls, cost


def profile(binary: str, bench_filter: str, seconds: str, function: str, caller: str) -> tuple[int, int]:
    """Calls of `function` and their inclusive instructions in one callgrind run."""
    with tempfile.TemporaryDirectory() as scratch:
        out = os.path.join(scratch, "callgrind.out")
        command = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}",
                   binary, "--bench", bench_filter, "--profile-time", seconds]
        print("running:", " ".join(command), file=sys.stderr)
        run = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if run.returncode != 0:
            sys.exit(f"valgrind failed ({run.returncode}):\n{run.stderr[-2000:]}")
        return calls_and_cost(out, function, caller)


def main() -> None:
    if len(sys.argv) not in (4, 5):
        sys.exit(__doc__)
    binary, bench_filter, function = sys.argv[1:4]
    caller = sys.argv[4] if len(sys.argv) == 5 else ""
    (short_calls, short_cost), (long_calls, long_cost) = (
        profile(binary, bench_filter, seconds, function, caller) for seconds in PROFILE_SECONDS
    )
    if long_calls <= short_calls:
        sys.exit(f"{function!r}" + (f" from {caller!r}" if caller else "")
                 + f" was called {short_calls} then {long_calls} times: no difference to divide by")
    marginal = (long_cost - short_cost) / (long_calls - short_calls)
    print(f"{function}: {marginal:,.0f} instructions per call "
          f"({short_calls} and {long_calls} calls; {long_cost / long_calls:,.0f} on average in the longer run)")


if __name__ == "__main__":
    main()
