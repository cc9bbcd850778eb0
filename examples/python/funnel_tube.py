"""Notebook-style example (cells marked `# %%`, docs/python.md): a funnel controller's tube
against simulated runs.

Needs the built module, numpy and matplotlib (Debian: `apt-get install python3-matplotlib`):

    PYTHONPATH=build/python /usr/bin/python3 examples/python/funnel_tube.py [PROBLEM] [AGENT] [OUT_DIR]

Defaults: examples/bicycles.yaml (four bicycles, `tracker: auto` gives each a funnel controller),
agent `south`, OUT_DIR marsyn-out/python-funnel. Solves the problem, replays the closed loop of
every agent under random disturbances, and draws for one agent (OUT_DIR/funnel_tube.png):
left, the workspace with the obstacles and every agent's eps-boxes, period enclosures (where the
funnel guarantees the agent is between the samples) and runs; right, the agent's state
coordinate over time in the same tube and enclosures, and below it the specification's margin
over time for feedback and open loop from solve()'s kept runs.
"""
import os
import sys

import numpy as np

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Polygon, Rectangle
except ImportError:
    sys.exit("funnel_tube.py draws with matplotlib, which is not installed (Debian: apt-get install python3-matplotlib)")

import marsyn

here = os.path.dirname(os.path.abspath(__file__))
problem_file = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "bicycles.yaml")
agent_name = sys.argv[2] if len(sys.argv) > 2 else "south"
out_dir = sys.argv[3] if len(sys.argv) > 3 else "marsyn-out/python-funnel"
os.makedirs(out_dir, exist_ok=True)

# %% Load: each agent's tracker is resolved by `tracker: auto` (the cheapest tracker that accepts it).
problem = marsyn.load(problem_file)
agents = {a["name"]: a for a in problem.agents}
if agent_name not in agents:
    sys.exit("no agent '%s' in %s; agents: %s" % (agent_name, problem_file, ", ".join(agents)))
agent = agents[agent_name]
print(problem, "| trackers:", {a["name"]: a["tracker"] for a in problem.agents})

# %% Solve. Besides result.json's fields, the result carries numpy arrays: the tubes (eps-boxes
# around the nominal, and the controller's period enclosures), the margins of the runs the
# verification kept, and what the search changed against the file.
result = marsyn.solve(problem, runs=100, log=lambda line: None)
print("status:", result["status"], "| certification:", result["certification"]["message"])
print("the search changed:", result["changes"] or "nothing")
for a in result["attempts"]:
    print("  %-16s %-60s %s" % (a["stage"], a["parameters"][:60], a["outcome"][:60]))
tube = result["tubes"][agent_name]
enc = tube["enclosures"]
print("%s: tracker %s, %d samples, %d period enclosures" %
      (agent_name, result["agents"][[a["name"] for a in result["agents"]].index(agent_name)]["tracker"]["name"],
       len(tube["t"]), len(enc["t0"])))

# %% Simulated runs: every agent under its own controller, random disturbances in W (a new seed
# each), and the nominal inputs open loop for comparison.
runs = [marsyn.simulate(problem, result["controllers"], result, disturbance=mode, seed=seed)
        for seed in range(1, 11) for mode in ("uniform", "switching")]
open_loop = marsyn.simulate(problem, None, result, disturbance="switching", seed=1)
print("closed loop: %d runs, all satisfied: %s, largest deviation %.2f of eps" %
      (len(runs), all(r["satisfied"] for r in runs), max(r["max_tube_excess"] for r in runs)))
print("open loop: satisfied %s, largest deviation %.2f of eps" % (open_loop["satisfied"], open_loop["max_tube_excess"]))

# At each sample the run lies in the enclosure of the period starting there (the guarantee).
starts = np.isclose(enc["t0"], enc["step"] * problem.tau, rtol=0, atol=1e-12)
inside = all(np.all((r["agents"][agent_name][enc["step"][starts]] >= enc["state_lo"][starts]) &
                    (r["agents"][agent_name][enc["step"][starts]] <= enc["state_hi"][starts])) for r in runs)
print("every run inside the period enclosures at the samples:", inside)

# %% Plot.
names = agent["state_names"]
coord = 2 if len(names) > 2 else len(names) - 1  # the bicycle's heading
fig = plt.figure(figsize=(13, 6))
ws = fig.add_subplot(1, 2, 1)
st = fig.add_subplot(2, 2, 2)
mg = fig.add_subplot(2, 2, 4, sharex=st)

for o in problem.obstacles:
    ws.add_patch(Polygon(o["vertices"], closed=True, color="#444444", alpha=0.6))
    ws.text(*o["vertices"].mean(axis=0), o["name"], ha="center", va="center", color="white")
# Every agent in the workspace (the chosen one drawn on top), each in its own tube and enclosures.
pos = [i for i, n in enumerate(names) if n in ("x", "y")][:2] or [0, 1]  # the state coordinates drawn as the plane
for name in sorted(result["tubes"], key=lambda n: n == agent_name):
    tb = result["tubes"][name]
    for lo, hi in zip(tb["enclosures"]["workspace_lo"], tb["enclosures"]["workspace_hi"]):
        ws.add_patch(Rectangle(lo, *(hi - lo), color="#1f77b4", alpha=0.15, lw=0))
    e = tb["eps"]
    for x in tb["nominal"]:
        ws.add_patch(Rectangle((x[pos[0]] - e[pos[0]], x[pos[1]] - e[pos[1]]), 2 * e[pos[0]],
                               2 * e[pos[1]], fill=False, ec="#ffbf00", lw=0.4))
    first = name == agent_name
    ws.plot(tb["nominal"][:, pos[0]], tb["nominal"][:, pos[1]], "k--", lw=0.8, label="nominal" if first else None)
    for n, r in enumerate(runs):
        xs = r["agents"][name]
        ws.plot(xs[:, pos[0]], xs[:, pos[1]], color="#2ca02c", lw=0.5, alpha=0.7,
                label="closed loop" if first and n == 0 else None)
    xs = open_loop["agents"][name]
    ws.plot(xs[:, pos[0]], xs[:, pos[1]], color="#d62728", lw=0.8, label="open loop" if first else None)
    ws.annotate(name, tb["nominal"][0, pos], fontsize=9, weight="bold" if first else "normal")
ws.set_aspect("equal")
ws.autoscale_view()
ws.set_xlabel(names[pos[0]])
ws.set_ylabel(names[pos[1]])
ws.set_title("workspace: eps-boxes (yellow), period enclosures (blue)")
ws.legend(loc="best", fontsize=8)

st.fill_between(tube["t"], tube["lo"][:, coord], tube["hi"][:, coord], color="#ffbf00", alpha=0.25, label="eps tube")
for t0, t1, lo, hi in zip(enc["t0"], enc["t1"], enc["state_lo"][:, coord], enc["state_hi"][:, coord]):
    st.fill_between([t0, t1], [lo, lo], [hi, hi], color="#1f77b4", alpha=0.35, lw=0)
st.plot(tube["t"], tube["nominal"][:, coord], "k--", lw=1)
for r in runs:
    st.plot(tube["t"], r["agents"][agent_name][:, coord], color="#2ca02c", lw=0.5, alpha=0.7)
st.plot(tube["t"], open_loop["agents"][agent_name][:, coord], color="#d62728", lw=1)
st.set_ylabel(names[coord])
st.set_title("%s over time: eps tube, funnel enclosures, runs" % names[coord])

for m in result["margins"]:
    feedback = m["label"].startswith("feedback")
    if not (feedback or m["label"].startswith("open loop")):
        continue
    margin = np.minimum(m["dense"]["min"], 1e3)  # inf: nothing to keep apart from at that instant
    mg.plot(m["dense_t"], margin, color="#2ca02c" if feedback else "#d62728", lw=0.7, alpha=0.8)
mg.axhline(0, color="black", lw=0.8)
mg.set_xlabel("t [s]")
mg.set_ylabel("margin (green: feedback, red: open loop)")
mg.set_title("obstacle / collision / formation margin, all agents (dense)")

fig.tight_layout()
path = os.path.join(out_dir, "funnel_tube.png")
fig.savefig(path, dpi=110)
print("wrote", path)
