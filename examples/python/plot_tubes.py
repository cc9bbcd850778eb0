"""Notebook-style tour of the marsyn Python module (docs/python.md): solve the pendulum swing-up,
look at the controller, replay the closed loop under disturbances and plot the tubes.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/plot_tubes.py [PROBLEM] [OUT_DIR]

Writes OUT_DIR/tubes.png with matplotlib when it is installed (Debian: python3-matplotlib), and
OUT_DIR/tubes.svg (drawn by hand, no dependency) in any case.
"""
import logging
import os
import sys

import numpy as np

import marsyn

here = os.path.dirname(os.path.abspath(__file__))
problem_file = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "pendulum.yaml")
out_dir = sys.argv[2] if len(sys.argv) > 2 else "marsyn-out/python-tour"
os.makedirs(out_dir, exist_ok=True)

# %% Load and validate: a bad file raises marsyn.ConfigError with the CLI's located message.
logging.basicConfig(level=logging.INFO, format="%(name)s: %(message)s")  # progress goes to the 'marsyn' logger
problem = marsyn.load(problem_file)
print(problem.summary())

# %% Solve: plan, track every agent, verify. The result is result.json as a dict, plus numpy
# arrays of the nominal trajectories and the controllers themselves.
result = marsyn.solve(problem, runs=50, out=out_dir)
print("status:", result["status"], "| plan horizon:", result["plan"]["horizon"])
agent = problem.agents[0]
name, eps = agent["name"], agent["eps"]
ctrl = result["controllers"][name]
nominal = result["nominal"][name]["x"]  # (T+1, n)
print(ctrl, "nominal states", nominal.shape)

# %% The controller on many states at once: C(x, k) over a grid around the start, at k = 0.
a, b = np.meshgrid(np.linspace(nominal[0, 0] - 2 * eps[0], nominal[0, 0] + 2 * eps[0], 201),
                   np.linspace(nominal[0, 1] - 2 * eps[1], nominal[0, 1] + 2 * eps[1], 201))
grid = np.column_stack([a.ravel(), b.ravel()] + [np.full(a.size, nominal[0, i]) for i in range(2, ctrl.state_dim)])
u, status = ctrl.input(grid, 0)
print("k = 0: %d of %d grid states have a verified input" % (np.sum(status == marsyn.OK), len(status)))

# %% Closed loop under three disturbance modes, each agent under its own controller.
runs = {mode: marsyn.simulate(problem, result["controllers"], result, disturbance=mode, seed=1)
        for mode in ("none", "switching", "uniform")}
for mode, sim in runs.items():
    print("%-9s satisfied %s, largest deviation %.2f of eps" % (mode, sim["satisfied"], sim["max_tube_excess"]))
open_loop = marsyn.simulate(problem, None, result, disturbance="switching", seed=1)
print("open loop: largest deviation %.2f of eps" % open_loop["max_tube_excess"])

# %% Plot: the eps-boxes around the nominal states (the tube), the nominal, the closed loops.
i, j = 0, 1  # the first two state coordinates
labels = agent["state_names"]
traces = [(runs[m]["agents"][name], c, m) for m, c in (("none", "#1f77b4"), ("switching", "#d62728"), ("uniform", "#2ca02c"))]
traces.append((open_loop["agents"][name], "#7f7f7f", "open loop, switching"))

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle

    fig, ax = plt.subplots(figsize=(8, 5))
    for x in nominal:
        ax.add_patch(Rectangle((x[i] - eps[i], x[j] - eps[j]), 2 * eps[i], 2 * eps[j], color="#ffbf00", alpha=0.15, lw=0))
    ax.plot(nominal[:, i], nominal[:, j], "k--", lw=1, label="nominal")
    for xs, colour, label in traces:
        ax.plot(xs[:, i], xs[:, j], color=colour, lw=1, label=label)
    ax.set_xlabel(labels[i])
    ax.set_ylabel(labels[j])
    ax.set_title("%s: tube of eps-boxes and closed loops" % problem.name)
    ax.legend()
    fig.savefig(os.path.join(out_dir, "tubes.png"), dpi=120)
    print("wrote", os.path.join(out_dir, "tubes.png"))
except ImportError:
    print("matplotlib not installed: only the SVG")

# The same picture as a hand-written SVG.
lo = np.min(nominal[:, [i, j]], axis=0) - 2 * np.array([eps[i], eps[j]])
hi = np.max(nominal[:, [i, j]], axis=0) + 2 * np.array([eps[i], eps[j]])
W, H = 800, 500


def px(p):
    return ((p[0] - lo[0]) / (hi[0] - lo[0]) * W, H - (p[1] - lo[1]) / (hi[1] - lo[1]) * H)


parts = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" viewBox="0 0 %d %d">' % (W, H, W, H),
         '<rect width="100%" height="100%" fill="white"/>']
for x in nominal:
    (x0, y1), (x1, y0) = px((x[i] - eps[i], x[j] - eps[j])), px((x[i] + eps[i], x[j] + eps[j]))
    parts.append('<rect x="%.1f" y="%.1f" width="%.1f" height="%.1f" fill="#ffbf00" fill-opacity="0.15"/>' % (x0, y0, x1 - x0, y1 - y0))


def polyline(xs, colour, dash=""):
    pts = " ".join("%.1f,%.1f" % px((x[i], x[j])) for x in xs)
    return '<polyline points="%s" fill="none" stroke="%s" stroke-width="1.2" %s/>' % (pts, colour, dash)


parts.append(polyline(nominal, "black", 'stroke-dasharray="4 3"'))
for n, (xs, colour, label) in enumerate(traces):
    parts.append(polyline(xs, colour))
    parts.append('<text x="10" y="%d" fill="%s" font-family="sans-serif" font-size="13">%s</text>' % (20 + 16 * n, colour, label))
parts.append('<text x="%d" y="%d" font-family="sans-serif" font-size="13">%s vs %s</text>' % (W - 160, H - 10, labels[j], labels[i]))
parts.append("</svg>")
with open(os.path.join(out_dir, "tubes.svg"), "w") as f:
    f.write("\n".join(parts))
print("wrote", os.path.join(out_dir, "tubes.svg"))
