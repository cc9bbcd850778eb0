#!/usr/bin/env python3
"""How the closed-loop verification grows with the number of agents and of runs (issue 24).

Circle swaps of N unicycles (scripts/circle_swap.py), each agent tracked (`marsyn track`) on the
straight-line plan (abcd: the funnel, which follows the dynamics, refuses the straight lines), then `marsyn verify --plan straight-line` timed; with --baseline, a second
build verifies the same controllers right after, so that the ratio holds on a loaded machine.
(The straight lines meet in the centre: the runs collide there, which the verification simulates
at full cost all the same; the figures measure speed, not the problem.) Prints a table (CPU and
wall seconds, runs per second, microseconds per agent-substep) and writes an SVG plot of CPU
seconds per 1000 runs against N.

    python3 scripts/verify_scaling.py --marsyn build/bin/marsyn --baseline /tmp/base/build/bin/marsyn \\
        --agents 10 20 50 100 200 --out /tmp/vscaling
"""
import argparse
import os
import re
import resource
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from svg_lines import line_plot  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def run(cmd):
    """Runs cmd; returns (stdout, CPU seconds of the child, wall seconds it printed or None)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run(cmd, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if proc.returncode not in (0, 1):
        sys.exit(f"{' '.join(cmd)} failed (exit {proc.returncode}):\n{proc.stderr[-2000:]}")
    return proc.stdout, cpu


def controllers(marsyn, n, horizon, folder):
    """The problem file and a folder of controllers for every agent (tracked once, reused)."""
    os.makedirs(folder, exist_ok=True)
    problem = os.path.join(folder, f"swap{n}.yaml")
    subprocess.run([sys.executable, os.path.join(HERE, "circle_swap.py"), str(n), "--out", problem,
                    "--guarantee", "sampled", "--tracker", "abcd", "--horizon", str(horizon)], check=True, capture_output=True)
    for i in range(1, n + 1):
        if not os.path.exists(os.path.join(folder, f"a{i}.ctrl")):
            run([marsyn, "track", problem, "--agent", f"a{i}", "--plan", "straight-line", "--out", folder])
    return problem


def verify(marsyn, problem, folder, runs, threads):
    out, cpu = run([marsyn, "verify", problem, "--controllers", folder, "--plan", "straight-line",
                    "--runs", str(runs), "--threads", str(threads)])
    m = re.search(r"closed-loop runs ([0-9.]+) s", out)
    if not m:
        sys.exit(f"no timing in the output of marsyn verify:\n{out}")
    return cpu, float(m.group(1))


def svg(rows, path, has_base):
    keys = [("cpu_per_1000", "#c0392b", "this build")] + ([("base_per_1000", "#2471a3", "baseline")] if has_base else [])
    # One point per N: its largest run count (the others are the runs sweep).
    most = {n: max(r["runs"] for r in rows if r["agents"] == n) for n in {r["agents"] for r in rows}}
    line_plot(path, [(label, colour, [(r["agents"], r[key]) for r in rows if r["runs"] == most[r["agents"]]])
                     for key, colour, label in keys],
              "agents N (circle swap, T = horizon)", "CPU s per 1000 runs")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--marsyn", default="build/bin/marsyn")
    ap.add_argument("--baseline", help="another build's marsyn, timed on the same controllers right after")
    ap.add_argument("--agents", type=int, nargs="+", default=[10, 20, 50, 100])
    ap.add_argument("--runs", type=int, nargs="+", default=[1000],
                    help="runs per problem (several: the runs sweep); large teams are capped by --budget")
    ap.add_argument("--budget", type=float, default=2e6, help="at most this many agent-runs per measurement (runs x N)")
    ap.add_argument("--horizon", type=int, default=160)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", default="marsyn-out/verify-scaling")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    print("| agents | runs | CPU s | wall s | runs/s | us per agent-substep (CPU) |" +
          (" baseline CPU s | baseline wall s | CPU ratio |" if args.baseline else ""))
    print("|---|---|---|---|---|---|" + ("---|---|---|" if args.baseline else ""))
    for n in args.agents:
        folder = os.path.join(args.out, f"swap{n}")
        problem = controllers(args.marsyn, n, args.horizon, folder)
        for runs in args.runs:
            runs = max(5, min(runs, int(args.budget / n)))
            cpu, wall = verify(args.marsyn, problem, folder, runs, args.threads)
            row = {"agents": n, "runs": runs, "cpu": cpu, "wall": wall, "cpu_per_1000": cpu * 1000 / runs}
            substeps = n * args.horizon * 20 * (runs + 10)  # the report's ten kept runs included
            line = f"| {n} | {runs} | {cpu:.2f} | {wall:.2f} | {runs / wall:.0f} | {1e6 * cpu / substeps:.3f} |"
            if args.baseline:
                bcpu, bwall = verify(args.baseline, problem, folder, runs, args.threads)
                row.update(base_cpu=bcpu, base_wall=bwall, base_per_1000=bcpu * 1000 / runs)
                line += f" {bcpu:.2f} | {bwall:.2f} | {bcpu / cpu:.2f} |"
            rows.append(row)
            print(line, flush=True)
    svg(rows, os.path.join(args.out, "verify_scaling.svg"), bool(args.baseline))
    print(f"plot: {os.path.join(args.out, 'verify_scaling.svg')}")


if __name__ == "__main__":
    main()
