#!/usr/bin/env python3
"""Writes a unicycle-field problem: N unicycles on a grid, shuffled within blocks of 5 x 5.

The robots stand 2 m apart on a square grid (a fixed density, whatever N). The grid is cut into
blocks of 5 x 5 robots (8 m x 8 m, blocks 10 m apart centre to centre, so neighbours across a
block boundary are 2 m apart too); each block shuffles its robots: every robot's goal is another
robot's start in the same block (a random derangement, --seed), so every robot moves and every
goal is left free by the robot that started there. Small square pillars (0.4 m) stand between the
blocks, on the block boundaries (where four blocks meet and halfway along the edge between two
blocks): off every robot's straight path from start to goal (a path stays inside its block) and
at least 0.6 m from every start and goal (0.8 m: the script checks it). The blocks are laid out
in a square-ish grid, row by row; a last partial block (N not a multiple of 25) fills its rows
in order and is shuffled like the others (a block of one robot keeps it in place).

Everything else as in scripts/circle_swap.py (examples/multi_drone.yaml's parameters): tau 0.1,
delta 0.24 (inf-norm), W (0, 0.025, 0.025), U [-2.4, 2.4]^2, eps (0.20, 0.20, 0.24), eta_x
(0.025, 0.025, 0.03), eta_u (0.3, 0.3), planner altro, the `unicycle` plugin; goals of half-width
(0.3, 0.3, 0.8) with the heading of the straight path.

    python3 scripts/unicycle_field.py 100 > /tmp/field100.yaml
    python3 scripts/unicycle_field.py 400 --seed 7 --out /tmp/field400.yaml
    python3 scripts/unicycle_field.py 60 --horizon 150 --tracker abcd --out /tmp/field60.yaml

Default horizon: the longest move inside a block (its diagonal, 8 sqrt 2 = 11.3 m) at half the
speed bound (1.2 of 2.4 m/s), times 1.3 (docs/parameters.md: 1.2 to 1.5 times the distance over
a comfortable speed), divided by tau: 123 steps.
"""
import argparse
import math
import random
import sys

SPACING = 2.0          # m between neighbouring robots
BLOCK = 5              # robots per block side
BLOCK_PITCH = BLOCK * SPACING   # 10 m: a block and the boundary strip after it
PILLAR_HALF = 0.2      # pillars 0.4 m square
MIN_CLEAR = 0.6        # pillar edge to any start or goal, at least
V_MAX = 2.4            # the unicycle's speed bound (U)
TAU = 0.1


def default_horizon():
    diag = math.hypot((BLOCK - 1) * SPACING, (BLOCK - 1) * SPACING)
    return math.ceil(1.3 * diag / (0.5 * V_MAX) / TAU)


def layout(n):
    """Blocks (row, col) -> list of grid points (x, y), and the block grid's shape."""
    nblocks = math.ceil(n / (BLOCK * BLOCK))
    cols = math.ceil(math.sqrt(nblocks))
    rows = math.ceil(nblocks / cols)
    blocks = {}
    left = n
    for b in range(nblocks):
        bi, bj = divmod(b, cols)
        k = min(left, BLOCK * BLOCK)
        left -= k
        pts = []
        for r in range(BLOCK):
            for c in range(BLOCK):
                if len(pts) < k:
                    pts.append((bj * BLOCK_PITCH + c * SPACING, bi * BLOCK_PITCH + r * SPACING))
        blocks[(bi, bj)] = pts
    return blocks, rows, cols


def derangement(k, rng):
    """A permutation of range(k) without fixed points (the identity for k = 1)."""
    if k < 2:
        return list(range(k))
    while True:
        p = list(range(k))
        rng.shuffle(p)
        if all(p[i] != i for i in range(k)):
            return p


def pillars(blocks, rows, cols):
    """Pillar centres on the block boundaries, between blocks that are present."""
    present = set(blocks)
    edge = (BLOCK - 1) * SPACING + SPACING / 2      # 9 m: the boundary after a block
    mid = (BLOCK - 1) * SPACING / 2                 # 4 m: the middle of a block's side
    out = set()
    for (bi, bj) in present:
        x0, y0 = bj * BLOCK_PITCH, bi * BLOCK_PITCH
        if (bi, bj + 1) in present:                 # vertical boundary, halfway along
            out.add((x0 + edge, y0 + mid))
        if (bi + 1, bj) in present:                 # horizontal boundary, halfway along
            out.add((x0 + mid, y0 + edge))
        around = [(bi, bj), (bi, bj + 1), (bi + 1, bj), (bi + 1, bj + 1)]
        if sum(b in present for b in around) >= 2 and bi + 1 < rows and bj + 1 < cols:
            out.add((x0 + edge, y0 + edge))         # where four blocks meet
    return sorted(out, key=lambda p: (p[1], p[0]))


def problem(n, seed, horizon, tracker, guarantee):
    rng = random.Random(seed)
    blocks, rows, cols = layout(n)
    agents = []
    points = []
    for key in sorted(blocks):
        pts = blocks[key]
        perm = derangement(len(pts), rng)
        for i, (x, y) in enumerate(pts):
            gx, gy = pts[perm[i]]
            heading = math.atan2(gy - y, gx - x) if (gx, gy) != (x, y) else 0.0
            agents.append((x, y, gx, gy, heading))
            points.append((x, y))
    pils = pillars(blocks, rows, cols)
    for (px, py) in pils:   # clear of every start (= every goal) by MIN_CLEAR at least
        d = min(max(abs(px - x), abs(py - y)) for (x, y) in points) - PILLAR_HALF
        assert d >= MIN_CLEAR, (px, py, d)
    xmax = max(p[0] for p in points)
    ymax = max(p[1] for p in points)
    m = 1.5
    lines = [
        f"# {n} unicycles in a field of {len(blocks)} block(s) of up to 5 x 5, 2 m apart, each block shuffled "
        f"(seed {seed}); {len(pils)} pillars between the blocks (scripts/unicycle_field.py).",
        f"name: unicycle-field-{n}",
        f"tau: {TAU}",
        f"horizon: {horizon}",
        "delta: 0.24",
        "delta_norm: inf",
        "planner: altro",
        f"tracker: {tracker}",
        f"guarantee: {guarantee}",
        "",
        "defaults:",
        "  dynamics: unicycle",
        f"  state_bounds: {{lo: [{-m}, {-m}, -7], hi: [{xmax + m}, {ymax + m}, 7]}}",
        f"  input_bounds: {{lo: [-{V_MAX}, -{V_MAX}], hi: [{V_MAX}, {V_MAX}]}}",
        "  disturbance: [0, 0.025, 0.025]",
        "  eps: [0.20, 0.20, 0.24]",
        "  eta_x: [0.025, 0.025, 0.03]",
        "  eta_u: [0.3, 0.3]",
        "  workspace: {position: [0, 1]}",
        "",
    ]
    if pils:
        lines.append("obstacles:")
        for k, (px, py) in enumerate(pils):
            lines.append(f"  - {{name: pillar{k + 1}, box: {{lo: [{px - PILLAR_HALF:g}, {py - PILLAR_HALF:g}], "
                         f"hi: [{px + PILLAR_HALF:g}, {py + PILLAR_HALF:g}]}}}}")
        lines.append("")
    lines.append("agents:")
    for i, (x, y, gx, gy, h) in enumerate(agents):
        lines.append(f"  - {{name: a{i + 1}, x0: [{x:g}, {y:g}, {h:.6f}], "
                     f"goal: {{center: [{gx:g}, {gy:g}, {h:.6f}], radius: [0.3, 0.3, 0.8]}}}}")
    return "\n".join(lines) + "\n"


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("agents", type=int, help="number of unicycles N (1 or more; a multiple of 25 fills every block)")
    p.add_argument("--seed", type=int, default=1, help="seed of the shuffles (default 1)")
    p.add_argument("--horizon", type=int, default=None,
                   help=f"steps of tau = 0.1 s (default {default_horizon()}: the block's diagonal at half the speed bound, x 1.3)")
    p.add_argument("--tracker", default="auto", help="tracker name (default auto)")
    p.add_argument("--guarantee", default="continuous", choices=["continuous", "sampled"])
    p.add_argument("--out", help="file to write (default: standard output)")
    a = p.parse_args()
    if a.agents < 1:
        p.error("at least 1 agent")
    if a.agents > 1000:
        p.error("at most 1000 agents (the problem format's limit)")
    if a.agents % (BLOCK * BLOCK):
        print(f"unicycle_field.py: note: {a.agents} is not a multiple of 25: the last block has "
              f"{a.agents % (BLOCK * BLOCK)} robots", file=sys.stderr)
    horizon = a.horizon if a.horizon is not None else default_horizon()
    text = problem(a.agents, a.seed, horizon, a.tracker, a.guarantee)
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
