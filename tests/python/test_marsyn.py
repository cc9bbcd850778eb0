"""The marsyn Python module against the CLI (ctest python.pendulum; docs/python.md).

usage: test_marsyn.py MARSYN_EXE SOURCE_DIR SCRATCH_DIR  (with PYTHONPATH at the built module)

Solves the pendulum example with `marsyn solve` and from Python, then checks that
- a bad problem file raises marsyn.ConfigError with exactly the CLI's located message,
- Python's result agrees with the CLI's result.json (verdict, horizon, tube cells, N_l),
- the controller Python synthesized, evaluated vectorised on numpy arrays over 1e5 (x, k)
  including outside-domain and outside-horizon cases, answers exactly as the CLI's controller
  file, and as scalar evaluation,
- plan() and track() from Python give the same controller, simulate() keeps the closed loop in
  the tube and reports the disturbance mode, progress reaches the callback, plugins are listed.
"""
import json
import os
import subprocess
import sys

import numpy as np

import marsyn
from checks import check, finish, fresh

exe, source, scratch = sys.argv[1:4]
example = os.path.join(source, "examples", "pendulum.yaml")
fresh(scratch)


# --- errors: the same located message as the CLI ------------------------------------------------
bad = os.path.join(scratch, "bad.yaml")
with open(example) as f:
    text = f.read()
with open(bad, "w") as f:
    f.write(text.replace("eps: [0.2, 0.2]", "eps: [0.2, fast]"))
cli = subprocess.run([exe, "check", bad], capture_output=True, text=True)
check(cli.returncode == 2, "marsyn check on a bad file exits with 2")
cli_message = cli.stderr.strip()
try:
    marsyn.load(bad)
    check(False, "marsyn.load raises on a bad file")
except marsyn.ConfigError as e:
    check(isinstance(e, ValueError), "ConfigError is a ValueError")
    check(cli_message == "error: " + str(e), "same message as the CLI: %r vs %r" % (cli_message, str(e)))
    check(e.line > 0 and e.file == bad and "eps" in e.path, "located: %s:%d %s" % (e.file, e.line, e.path))

# The memory budget is the caller's, as --memory-budget is the CLI's: the same located refusal.
cli = subprocess.run([exe, "--memory-budget", "1K", "check", example], capture_output=True, text=True)
try:
    marsyn.load(example, memory_budget="1K")
    check(False, "marsyn.load(memory_budget='1K') refuses the pendulum")
except marsyn.ConfigError as e:
    same = cli.stderr.strip().replace("(--memory-budget)", "(memory_budget)") == "error: " + str(e)
    check(same, "the CLI's budget message, with Python's name for the source: %r vs %r" % (cli.stderr, str(e)))
    check("(memory_budget)" in str(e), "the message names the budget's source: %s" % e)
try:
    marsyn.load(example, memory_budget="lots")
    check(False, "marsyn.load(memory_budget='lots') raises")
except ValueError as e:
    check("memory_budget: expected a positive number of bytes" in str(e), "a bad budget says what was expected: %s" % e)

# A robot of several bodies (examples/tractor_trailer.yaml): its radius and its further bodies.
rig = marsyn.load(os.path.join(source, "examples", "tractor_trailer.yaml")).agents[0]
check(rig["radius"] == 0.8 and rig["bodies"] == [{"name": "tractor", "radius": 0.8}, {"name": "cart", "radius": 0.8}],
      "agent dict radius and bodies: %s" % rig)

kinds = {(p["kind"], p["name"]) for p in marsyn.plugins()}
check(("tracker", "abcd") in kinds and ("planner", "altro") in kinds, "plugins() lists abcd and altro: %s" % kinds)

# --- the CLI's answer ----------------------------------------------------------------------------
cli_dir = os.path.join(scratch, "cli")
r = subprocess.run([exe, "solve", example, "--out", cli_dir, "--runs", "20"], capture_output=True, text=True)
check(r.returncode == 0, "marsyn solve verifies the pendulum: " + r.stdout[-400:] + r.stderr[-400:])
with open(os.path.join(cli_dir, "result.json")) as f:
    cli_result = json.load(f)
cli_ctrl = marsyn.read_controller(os.path.join(cli_dir, "pendulum.ctrl"))

# --- Python ----------------------------------------------------------------------------------------
problem = marsyn.load(example)
check(problem.name == "pendulum-swing-up" and len(problem.agents) == 1, "problem loaded: %r" % problem)
lines = []
result = marsyn.solve(problem, runs=20, out=os.path.join(scratch, "py"), log=lines.append)
check(result["verified"], "Python solve verifies")
check(any("[track" in l for l in lines), "progress lines reached the callback (%d lines)" % len(lines))
check(os.path.exists(os.path.join(scratch, "py", "result.json")), "solve(out=...) writes result.json")
for key in ("status", "verified"):
    if key in cli_result:
        check(result[key] == cli_result[key], "result[%r]: %r vs CLI %r" % (key, result[key], cli_result[key]))


def find(d, *path):
    for p in path:
        if isinstance(d, dict) and p in d:
            d = d[p]
        else:
            return None
    return d


# The plan's horizon and the tracker's figures as result.json records them.
for path in (("plan", "horizon"), ("plan", "status"), ("verification", "violations"), ("verification", "tube_violations")):
    check(find(result, *path) == find(cli_result, *path), "result%s: %r vs CLI %r" % (path, find(result, *path), find(cli_result, *path)))
py_agents = {a["name"]: a for a in result.get("agents", [])} if isinstance(result.get("agents"), list) else {}
cli_agents = {a["name"]: a for a in cli_result.get("agents", [])} if isinstance(cli_result.get("agents"), list) else {}
check(py_agents.keys() == cli_agents.keys() and py_agents, "the same agents in result.json")
for name in py_agents:
    for key in ("tube_cells", "state_input_pairs", "boxes_computed", "status"):
        a, b = find(py_agents[name], "tracker", key), find(cli_agents[name], "tracker", key)
        check(a is not None and a == b, "%s.tracker.%s: %r vs CLI %r" % (name, key, a, b))

ctrl = result["controllers"]["pendulum"]
nominal = result["nominal"]["pendulum"]
X_nom = nominal["x"]
T = ctrl.horizon
check(isinstance(X_nom, np.ndarray) and X_nom.shape == (T + 1, 2), "nominal states as a (T+1, 2) array: %s" % (X_nom.shape,))
check(cli_ctrl.horizon == T, "same horizon as the CLI's controller")

# --- vectorised evaluation against the CLI's controller and scalar evaluation ----------------------
rng = np.random.default_rng(7)
N = 100000
k = rng.integers(-2, T + 3, size=N)
centre = X_nom[np.clip(k, 0, T)]
X = centre + rng.uniform(-0.3, 0.3, size=(N, 2))  # eps is 0.2: inside and outside the tube
X[::997, 0] = np.nan
X[::1013, 1] = np.inf
u_py, s_py = ctrl.input(X, k)
u_cli, s_cli = cli_ctrl.input(X, k)
check(u_py.shape == (N, 1) and s_py.shape == (N,), "shapes of the vectorised answer")
check(np.array_equal(s_py, s_cli), "statuses equal to the CLI controller's")
check(np.array_equal(u_py, u_cli, equal_nan=True), "inputs equal to the CLI controller's")
counts = {s: int(np.sum(s_py == s)) for s in (marsyn.OK, marsyn.OUTSIDE_DOMAIN, marsyn.OUTSIDE_HORIZON)}
check(counts[marsyn.OK] > 10000 and counts[marsyn.OUTSIDE_DOMAIN] > 10000 and counts[marsyn.OUTSIDE_HORIZON] > 2000,
      "all three statuses are sampled: %s" % counts)
check(bool(np.all(np.isnan(u_py[s_py != marsyn.OK]))), "no input where there is none")
for i in range(0, N, 97):
    u1, s1 = ctrl.input(X[i], int(k[i]))
    if s1 != s_py[i] or (s1 == marsyn.OK and u1[0] != u_py[i, 0]):
        check(False, "scalar evaluation differs at %d" % i)
        break
u_same_k, _ = ctrl.input(X[:100], 3)
check(u_same_k.shape == (100, 1), "k as one int for all states")

# --- plan, track and simulate ---------------------------------------------------------------------
plan = marsyn.plan(problem, log=lines.append)
check(plan["feasible"] and plan["horizon"] == T, "plan(): feasible with horizon %s" % plan["horizon"])
check(np.array_equal(plan["agents"]["pendulum"]["x"], X_nom), "plan() gives solve()'s nominal states")
tr = marsyn.track(problem, "pendulum", plan=plan)
check(tr["status"] == "controller" and tr["controller"] is not None, "track(): " + tr["status"])
if tr["controller"] is not None:
    u_tr, s_tr = tr["controller"].input(X, k)
    check(np.array_equal(s_tr, s_cli) and np.array_equal(u_tr, u_cli, equal_nan=True), "track()'s controller answers as the CLI's")
    check(tr["stats"]["tube_cells"] == find(py_agents, "pendulum", "tracker", "tube_cells"), "track(): the same tube as solve()")
try:
    marsyn.track(problem, "nobody", plan=plan)
    check(False, "track() with an unknown agent raises")
except marsyn.ConfigError as e:
    check("nobody" in str(e), "unknown agent named in the error")

for mode in ("none", "switching", "uniform"):
    sim = marsyn.simulate(problem, {"pendulum": ctrl}, plan, disturbance=mode, seed=3)
    check(sim["states"].shape == (T + 1, 2), "simulate(): states (T+1, 2)")
    check(sim["satisfied"] and sim["max_tube_excess"] <= 1.0 and sim["outside_domain_agent"] is None,
          "closed loop under %s stays in the tube and meets the spec: %s" % (mode, {k_: sim[k_] for k_ in ("satisfied", "max_tube_excess", "worst")}))
    # The sampled closed loop lies in the period enclosures starting at its sampling instants.
    enc = ctrl.period_enclosures
    starts = np.isclose(enc["t0"], enc["step"] * problem.tau, rtol=0, atol=1e-12)
    xs = sim["agents"]["pendulum"][enc["step"][starts]]
    check(enc["t0"].size > 0 and bool(np.all((xs >= enc["state_lo"][starts]) & (xs <= enc["state_hi"][starts]))),
          "closed loop (%s) inside the period enclosures at the samples" % mode)
sim_dir = marsyn.simulate(problem, cli_dir, disturbance="switching", seed=3)
sim_obj = marsyn.simulate(problem, [cli_ctrl], plan, disturbance="switching", seed=3)
check(np.array_equal(sim_dir["states"], sim_obj["states"]), "simulate() from a solve folder = with Controller objects")
try:
    marsyn.simulate(problem, [ctrl], plan, disturbance="sideways")
    check(False, "unknown disturbance mode raises")
except ValueError:
    pass

# --- export from Python ----------------------------------------------------------------------------
ex = ctrl.export("c", out=os.path.join(scratch, "c"), prefix="pend")
check(ex["const_data_bytes"] > 0 and all(os.path.exists(f) for f in ex["files"]), "Controller.export('c')")

finish("ok: %d progress lines, statuses %s" % (len(lines), counts))
