#!/usr/bin/env python3
"""How the plan stage grows with the number of agents: circle swaps of N unicycles
(scripts/circle_swap.py), each planned under the continuous guarantee (the requirements between
the samples inside the problem) and under the sampled one (knots only) in the same run, so the
ratio holds on a loaded machine. Prints a table (solves, iterations, CPU seconds, seconds per
iteration, constraint rows per step) and writes an SVG plot of CPU seconds against N.

    python3 scripts/plan_scaling.py --marsyn build/bin/marsyn --agents 10 20 50 --out /tmp/scaling
"""
import argparse
import json
import os
import resource
import subprocess
import sys

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
    width, height, pad = 640, 400, 60
    ns = [r["agents"] for r in rows]
    top = max(max(r["cont_cpu"], r["samp_cpu"]) for r in rows) * 1.1 or 1.0
    def x(n):
        return pad + (width - 2 * pad) * (n - min(ns)) / max(1, max(ns) - min(ns))
    def y(v):
        return height - pad - (height - 2 * pad) * v / top
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" font-family="sans-serif" font-size="12">',
             f'<rect width="{width}" height="{height}" fill="white"/>',
             f'<line x1="{pad}" y1="{height - pad}" x2="{width - pad}" y2="{height - pad}" stroke="black"/>',
             f'<line x1="{pad}" y1="{pad}" x2="{pad}" y2="{height - pad}" stroke="black"/>',
             f'<text x="{width / 2}" y="{height - 20}" text-anchor="middle">agents N (circle swap)</text>',
             f'<text x="15" y="{height / 2}" transform="rotate(-90 15 {height / 2})" text-anchor="middle">plan CPU s</text>']
    for n in ns:
        parts.append(f'<text x="{x(n)}" y="{height - pad + 16}" text-anchor="middle">{n}</text>')
    for frac in (0, 0.25, 0.5, 0.75, 1.0):
        v = top * frac
        parts.append(f'<text x="{pad - 6}" y="{y(v) + 4}" text-anchor="end">{v:.0f}</text>')
    for key, colour, label in (("cont_cpu", "#c0392b", "continuous (between samples in the problem)"),
                               ("samp_cpu", "#2471a3", "sampled (knots only)")):
        pts = " ".join(f"{x(r['agents'])},{y(r[key])}" for r in rows)
        parts.append(f'<polyline points="{pts}" fill="none" stroke="{colour}" stroke-width="2"/>')
        for r in rows:
            parts.append(f'<circle cx="{x(r["agents"])}" cy="{y(r[key])}" r="3" fill="{colour}"/>')
        parts.append(f'<text x="{pad + 10}" y="{pad + (14 if key == "cont_cpu" else 30)}" fill="{colour}">{label}</text>')
    parts.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(parts))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--marsyn", default="build/bin/marsyn")
    p.add_argument("--agents", type=int, nargs="+", default=[10, 20, 50])
    p.add_argument("--horizon", type=int, default=160)
    p.add_argument("--out", default="/tmp/marsyn-plan-scaling")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    rows = []
    for n in a.agents:
        r = {"agents": n}
        for mode in ("continuous", "sampled"):
            problem = os.path.join(a.out, f"swap{n}-{mode}.yaml")
            subprocess.run([sys.executable, os.path.join(HERE, "circle_swap.py"), str(n), "--horizon", str(a.horizon),
                            "--guarantee", mode, "--out", problem], check=True)
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
            its = max(1, r[key + "_its"])
            print(f"| {r['agents']} | {name} | {'yes' if r[key + '_ok'] else 'no'} | {r[key + '_solves']} | "
                  f"{r[key + '_its']} | {r[key + '_cpu']:.2f} | {1000 * r[key + '_cpu'] / its:.1f} | "
                  f"{rows_per_step(r['agents'], key == 'cont')} |")
    print("\nratio continuous / sampled (CPU): " +
          ", ".join(f"N = {r['agents']}: {r['cont_cpu'] / max(r['samp_cpu'], 1e-9):.2f}" for r in rows))
    plot = os.path.join(a.out, "plan_scaling.svg")
    svg(rows, plot)
    print(f"plot: {plot}")


if __name__ == "__main__":
    main()
