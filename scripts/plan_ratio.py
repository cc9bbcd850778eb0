#!/usr/bin/env python3
"""The continuous-time guarantee's cost in the plan stage (issue 22): `marsyn plan` of an example
under its own (continuous) guarantee and under `guarantee: sampled`, for one or more builds, the
runs shuffled round by round so that a slow minute of the machine hits every build and both
guarantees alike. Prints per build the medians of plan.json's total_time_s (the plan stage) and
solve_time_s (the solver), the rest (checks, assembly), and continuous / sampled.

    python3 scripts/plan_ratio.py --marsyn build/bin/marsyn [--marsyn OTHER/bin/marsyn] \\
        [--example examples/multi_drone.yaml] [--rounds 30]
"""
import argparse
import json
import os
import random
import statistics
import subprocess
import sys
import tempfile


def sampled_copy(example, folder):
    """The example with `guarantee: sampled` (replacing a guarantee line, or added at the top)."""
    with open(example) as f:
        lines = f.read().splitlines()
    out = [ln for ln in lines if not ln.startswith("guarantee:")]
    out.insert(0, "guarantee: sampled")
    path = os.path.join(folder, "sampled_" + os.path.basename(example))
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--marsyn", action="append", required=True, help="a marsyn binary (repeat to compare builds)")
    ap.add_argument("--example", default="examples/multi_drone.yaml")
    ap.add_argument("--rounds", type=int, default=30)
    a = ap.parse_args()
    if a.rounds < 1:
        ap.error("--rounds must be at least 1")
    for b in a.marsyn:
        if not (os.path.isfile(b) and os.access(b, os.X_OK)):
            ap.error(f"--marsyn {b}: not an executable file")
    if not os.path.isfile(a.example):
        ap.error(f"--example {a.example}: no such file")
    work = tempfile.mkdtemp(prefix="plan_ratio.")
    files = {"continuous": os.path.abspath(a.example), "sampled": sampled_copy(a.example, work)}
    times = {(b, g): [] for b in a.marsyn for g in files}
    for r in range(a.rounds):
        jobs = list(times)
        random.shuffle(jobs)
        for b, g in jobs:
            out = os.path.join(work, "out")
            p = subprocess.run([b, "plan", files[g], "--out", out], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
            if p.returncode != 0:
                sys.exit(f"{b} plan {files[g]} failed ({p.returncode}):\n{p.stderr}")
            with open(os.path.join(out, "plan.json")) as f:
                plan = json.load(f)
            times[(b, g)].append((plan["total_time_s"], plan["solve_time_s"]))
        print(f"round {r + 1}/{a.rounds}", end="\r", file=sys.stderr)
    print(file=sys.stderr)
    print(f"{a.example}, {a.rounds} rounds, medians in ms")
    print("| build | sampled: plan stage (solver, rest) | continuous: plan stage (solver, rest) | ratio | solver ratio |")
    print("|---|---|---|---|---|")
    for b in a.marsyn:
        med = {}
        for g in files:
            t = times[(b, g)]
            med[g] = (1e3 * statistics.median(x for x, _ in t), 1e3 * statistics.median(s for _, s in t),
                      1e3 * statistics.median(x - s for x, s in t))
        s, c = med["sampled"], med["continuous"]
        print(f"| {b} | {s[0]:.1f} ({s[1]:.1f}, {s[2]:.2f}) | {c[0]:.1f} ({c[1]:.1f}, {c[2]:.2f}) | "
              f"{c[0] / s[0]:.3f} | {c[1] / s[1]:.3f} |")


if __name__ == "__main__":
    main()
