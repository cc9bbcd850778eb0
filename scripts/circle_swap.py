#!/usr/bin/env python3
"""Writes a circle-swap problem: N unicycles on a circle, each to the antipodal point.

The scaling problem of `git show f9b6c78:docs/benchmarks.md` ("Circle swap end to end"; plan, track and verification time against the number
of agents). Parameters follow examples/multi_drone.yaml (eps, eta, W, U, delta); the circle's
radius, the horizon and the tracker are options.

    python3 scripts/circle_swap.py 50 > /tmp/swap50.yaml
    python3 scripts/circle_swap.py 100 --radius 24 --horizon 320 --out /tmp/swap100.yaml

At radius 12 neighbours stand 2 pi 12 / N apart: for N = 100 closer (0.533 in the inf-norm)
than delta plus both tubes (0.64), so no eps-robust plan exists at any horizon (`marsyn check`
warns, "crowded starts"); the script warns too. That diary scaled the circle with N
past 50 (radius 12 N / 50, horizon 160 N / 50: the 50-agent swap's density and speed).
"""
import argparse
import math
import sys


def problem(n, radius, horizon, tracker, guarantee):
    lim = radius + 1.5
    lines = [
        f"# {n} unicycles swapping places across a circle of radius {radius} (scripts/circle_swap.py).",
        f"name: circle-swap-{n}",
        "tau: 0.1",
        f"horizon: {horizon}",
        "delta: 0.24",
        "delta_norm: inf",
        "planner: altro",
        f"tracker: {tracker}",
        f"guarantee: {guarantee}",
        "",
        "defaults:",
        "  dynamics: unicycle",
        f"  state_bounds: {{lo: [{-lim}, {-lim}, -7], hi: [{lim}, {lim}, 7]}}",
        "  input_bounds: {lo: [-2.4, -2.4], hi: [2.4, 2.4]}",
        "  disturbance: [0, 0.025, 0.025]",
        "  eps: [0.20, 0.20, 0.24]",
        "  eta_x: [0.025, 0.025, 0.03]",
        "  eta_u: [0.3, 0.3]",
        "  workspace: {position: [0, 1]}",
        "",
        "agents:",
    ]
    for i in range(n):
        a = 2.0 * math.pi * i / n
        x, y = radius * math.cos(a), radius * math.sin(a)
        heading = math.atan2(-y, -x)
        gx, gy = -x, -y
        lines.append(
            f"  - {{name: a{i + 1}, x0: [{x:.6f}, {y:.6f}, {heading:.6f}], "
            f"goal: {{center: [{gx:.6f}, {gy:.6f}, {heading:.6f}], radius: [0.3, 0.3, 0.8]}}}}"
        )
    return "\n".join(lines) + "\n"


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("agents", type=int, help="number of unicycles (2 or more)")
    p.add_argument("--radius", type=float, default=12.0, help="circle radius in m (default 12)")
    p.add_argument("--horizon", type=int, default=160, help="steps of tau = 0.1 s (default 160)")
    p.add_argument("--tracker", default="auto", help="tracker name (default auto)")
    p.add_argument("--guarantee", default="continuous", choices=["continuous", "sampled"])
    p.add_argument("--out", help="file to write (default: standard output)")
    a = p.parse_args()
    if a.agents < 2:
        p.error("at least 2 agents")
    # Neighbours' inf-norm distance against delta + 2 eps (the drones' 0.24 and 0.2).
    pts = [(a.radius * math.cos(2 * math.pi * i / a.agents), a.radius * math.sin(2 * math.pi * i / a.agents))
           for i in range(a.agents)]
    gap = min(max(abs(pts[i][0] - pts[i - 1][0]), abs(pts[i][1] - pts[i - 1][1])) for i in range(a.agents))
    if gap < 0.24 + 2 * 0.20:
        need = a.radius * (0.24 + 2 * 0.20) / gap
        print(f"circle_swap.py: warning: neighbours start {gap:.3f} apart, less than delta + 2 eps = 0.64: "
              f"no eps-robust plan exists (a radius of {math.ceil(need * 10) / 10} or more would do)", file=sys.stderr)
    text = problem(a.agents, a.radius, a.horizon, a.tracker, a.guarantee)
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
