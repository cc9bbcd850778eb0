#!/usr/bin/env python3
"""How the plan stage grows with the number of agents: circle swaps of N unicycles
(scripts/circle_swap.py), each planned under the continuous guarantee (the requirements between
the samples inside the problem) and under the sampled one (knots only) in the same run, so the
ratio holds on a loaded machine. Prints a table (solves, iterations, CPU seconds, seconds per
iteration, constraint rows per step) and writes an SVG plot of CPU seconds against N.

    python3 scripts/plan_scaling.py --marsyn build/bin/marsyn --agents 10 20 50 --out /tmp/scaling
    python3 scripts/plan_scaling.py --agents 50 100 --scaled --threads 1 --only continuous

--scaled keeps the 50-agent swap's density and speed past 50 agents (radius 12 N / 50, horizon
160 N / 50; at radius 12, 100 agents start too close for any eps-robust plan). --threads sets the
altro planner's `threads` (CPU seconds of one thread compare across loads better than wall time).
"""
import argparse
import json
import os
import resource
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from svg_lines import line_plot  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def plan(marsyn, problem, out):
    """Runs `marsyn plan`; returns (plan.json as a dict, CPU seconds of the child)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run([marsyn, "plan", problem, "--out", out], capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    path = os.path.join(out, "plan.json")
    if proc.returncode not in (0, 1) or not os.path.exists(path):
        sys.exit(f"marsyn plan {problem} failed (exit {proc.returncode}):\n{proc.stderr[-2000:]}")
    with open(path) as f:
        return json.load(f), cpu


def rows_per_step(n, continuous, points=1):
    """Constraint rows per step of a circle swap: every pair at the knot, and again at each
    interior point (plus each agent's state box there) under the continuous guarantee."""
    pairs = n * (n - 1) // 2
    return pairs + (points * (pairs + 6 * n) if continuous else 0)


def svg(rows, path):
    line_plot(path, [(label, colour, [(r["agents"], r[key]) for r in rows])
                     for key, colour, label in (("cont_cpu", "#c0392b", "continuous (between samples in the problem)"),
                                                ("samp_cpu", "#2471a3", "sampled (knots only)"))],
              "agents N (circle swap)", "plan CPU s")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--marsyn", default="build/bin/marsyn")
    p.add_argument("--agents", type=int, nargs="+", default=[10, 20, 50])
    p.add_argument("--horizon", type=int, default=160)
    p.add_argument("--out", default="/tmp/marsyn-plan-scaling")
    p.add_argument("--scaled", action="store_true", help="past 50 agents: radius 12 N / 50, horizon 160 N / 50")
    p.add_argument("--threads", type=int, help="altro's threads (default: the planner's own default)")
    p.add_argument("--only", choices=["continuous", "sampled"], help="plan one guarantee only")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    rows = []
    for n in a.agents:
        r = {"agents": n}
        radius, horizon = 12.0, a.horizon
        if a.scaled and n > 50:
            radius, horizon = 12.0 * n / 50, round(a.horizon * n / 50)
        for mode in ("continuous", "sampled"):
            if a.only and mode != a.only:
                continue
            problem = os.path.join(a.out, f"swap{n}-{mode}.yaml")
            subprocess.run([sys.executable, os.path.join(HERE, "circle_swap.py"), str(n), "--horizon", str(horizon),
                            "--radius", str(radius), "--guarantee", mode, "--out", problem], check=True)
            if a.threads is not None:
                with open(problem) as f:
                    text = f.read()
                with open(problem, "w") as f:
                    f.write(text.replace("planner: altro\n", f"planner: {{name: altro, params: {{threads: {a.threads}}}}}\n"))
            d, cpu = plan(a.marsyn, problem, os.path.join(a.out, f"plan{n}-{mode}"))
            key = "cont" if mode == "continuous" else "samp"
            its = sum(t["iterations"] for t in d["attempts"])
            r[key + "_solves"] = len(d["attempts"])
            r[key + "_its"] = its
            r[key + "_cpu"] = cpu
            r[key + "_ok"] = d["feasible"]
        rows.append(r)
        print(f"N = {n}: done", file=sys.stderr, flush=True)
    print("| N | guarantee | robust | solves | iterations | CPU s | ms per iteration | rows per step |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        for key, name in (("cont", "continuous"), ("samp", "sampled")):
            if key + "_its" not in r:
                continue
            its = max(1, r[key + "_its"])
            print(f"| {r['agents']} | {name} | {'yes' if r[key + '_ok'] else 'no'} | {r[key + '_solves']} | "
                  f"{r[key + '_its']} | {r[key + '_cpu']:.2f} | {1000 * r[key + '_cpu'] / its:.1f} | "
                  f"{rows_per_step(r['agents'], key == 'cont')} |")
    if a.only:
        return
    print("\nratio continuous / sampled (CPU): " +
          ", ".join(f"N = {r['agents']}: {r['cont_cpu'] / max(r['samp_cpu'], 1e-9):.2f}" for r in rows))
    plot = os.path.join(a.out, "plan_scaling.svg")
    svg(rows, plot)
    print(f"plot: {plot}")


if __name__ == "__main__":
    main()
