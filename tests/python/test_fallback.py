"""Python's track() and solve() against `marsyn track` and `marsyn solve` under `tracker: auto`
(ctest python.fallback; docs/python.md).

usage: test_fallback.py MARSYN_EXE SOURCE_DIR SCRATCH_DIR NEVER_TRACKER_DIR

The pendulum example with `tracker: auto` and the test tracker `never` on plugin_paths
(tests/fixtures/never_tracker.cpp: accepted at zero cost, so auto chooses it first, and never
finds a controller). Checks that
- track() falls back from never to the same tracker as `marsyn track`, with the same progress
  lines, and its controller file is byte for byte the CLI's;
- a tracker named in the file (`tracker: never`) is not replaced, by either;
- solve() takes the file's search.time_limit (and time_limit=, as --time-limit), records the same
  tracker and search rounds and writes the same controller bytes as
  `marsyn solve`, and returns the search's change (never -> the fallback), the tubes and the margins as numpy arrays.
"""
import json
import os
import re
import subprocess
import sys

import numpy as np

import marsyn
from checks import check, finish, fresh

exe, source, scratch, never_dir = sys.argv[1:5]
fresh(scratch)


def variant(name, tracker_line):
    with open(os.path.join(source, "examples", "pendulum.yaml")) as f:
        text = f.read()
    assert "tracker: abcd\n" in text
    path = os.path.join(scratch, name + ".yaml")
    with open(path, "w") as f:
        f.write(text.replace("tracker: abcd\n", "%s\nplugin_paths: [%s]\nsearch: {time_limit: 77}\n" % (tracker_line, never_dir)))
    return path


def read(path):
    with open(path, "rb") as f:
        return f.read()


def cli_track(config, out):
    r = subprocess.run([exe, "track", config, "--agent", "pendulum", "--plan", plan_json, "--out", out],
                       capture_output=True, text=True)
    used = re.search(r"^tracker\s+(\S+)", r.stdout, re.M)
    # The tracker lines of the log, without the timestamps.
    lines = [re.sub(r"^\[\s*[0-9.]+ s\] ", "", l) for l in r.stderr.splitlines() if "[track] " in l and " s] " in l]
    return r.returncode, used.group(1) if used else None, [l for l in lines if "tracker: auto" in l or " with " in l]


auto = variant("auto", "tracker: auto")
named = variant("named", "tracker: never")

# One plan for every tracking run, so that only the trackers can differ.
plan_dir = os.path.join(scratch, "plan")
r = subprocess.run([exe, "plan", auto, "--out", plan_dir], capture_output=True, text=True)
check(r.returncode == 0, "marsyn plan: " + r.stderr[-300:])
plan_json = os.path.join(plan_dir, "plan.json")

# --- track: tracker: auto falls back from never ----------------------------------------------------
code, cli_used, cli_lines = cli_track(auto, os.path.join(scratch, "cli"))
check(code == 0 and cli_used not in (None, "never"), "marsyn track falls back from never: exit %d, tracker %s" % (code, cli_used))
problem = marsyn.load(auto)
check(problem.agents[0]["tracker"] == "never", "auto chose never first: %s" % problem.agents[0]["tracker"])
lines = []
tr = marsyn.track(problem, "pendulum", plan=plan_json, log=lines.append)
check(tr["tracker"] == cli_used, "track() ends with the CLI's tracker: %s vs %s" % (tr["tracker"], cli_used))
check(tr["automatic"] and tr["tried"] == ["never", cli_used], "track() tried never, then %s: %s" % (cli_used, tr["tried"]))
check(tr["status"] == "controller" and tr["controller"] is not None, "track() found a controller: " + tr["status"])
py_lines = [l for l in lines if l.startswith("[track] ")]
check(py_lines == cli_lines and len(py_lines) == 3, "the same fallback lines as the CLI:\n%s\nvs\n%s" % (py_lines, cli_lines))
if tr["controller"] is not None:
    tr["controller"].write(os.path.join(scratch, "py_track.ctrl"))
    check(read(os.path.join(scratch, "py_track.ctrl")) == read(os.path.join(scratch, "cli", "pendulum.ctrl")),
          "track()'s controller file is byte for byte marsyn track's")

# --- a named tracker is never replaced ------------------------------------------------------------
code, used, _ = cli_track(named, os.path.join(scratch, "cli_named"))
tn = marsyn.track(marsyn.load(named), "pendulum", plan=plan_json, log=lambda s: None)
check(code == 1 and used == "never", "marsyn track keeps a named tracker: exit %d, %s" % (code, used))
check(tn["tracker"] == "never" and tn["tried"] == ["never"] and not tn["automatic"] and tn["status"] == "no controller"
      and tn["controller"] is None, "track() keeps a named tracker: %s" % {k: tn[k] for k in ("tracker", "tried", "status")})

# --- solve: the same choice and bytes as marsyn solve; the arrays ----------------------------------
cli_dir, py_dir = os.path.join(scratch, "cli_solve"), os.path.join(scratch, "py_solve")
r = subprocess.run([exe, "solve", auto, "--out", cli_dir, "--runs", "5", "--global-budget", "0"], capture_output=True, text=True)
check(r.returncode == 0, "marsyn solve verifies: " + r.stdout[-300:] + r.stderr[-300:])
with open(os.path.join(cli_dir, "result.json")) as f:
    cli_result = json.load(f)
res = marsyn.solve(problem, runs=5, global_budget=0, out=py_dir, log=lambda s: None)
check(res["verified"], "solve() verifies")
check(res["agents"][0]["tracker"]["name"] == cli_result["agents"][0]["tracker"]["name"] == cli_used,
      "solve() and marsyn solve record %s: %s, %s" % (cli_used, res["agents"][0]["tracker"]["name"],
                                                       cli_result["agents"][0]["tracker"]["name"]))
check(read(os.path.join(py_dir, "pendulum.ctrl")) == read(os.path.join(cli_dir, "pendulum.ctrl")),
      "solve()'s controller file is byte for byte marsyn solve's")


def rounds(result):
    """The search's rounds as result.json records them, without the times."""
    return [{k: v for k, v in r.items() if not k.endswith("time_s")} for r in result["search"]["rounds"]]


check(rounds(res) == rounds(cli_result) and len(rounds(res)) == 2,
      "the same search rounds as marsyn solve (first attempt, then the fallback):\n%s\nvs\n%s" % (rounds(res), rounds(cli_result)))
check(res["search"]["time_limit_s"] == cli_result["search"]["time_limit_s"] == 77,
      "the file's search.time_limit is the budget of both: %s, %s" % (res["search"]["time_limit_s"], cli_result["search"]["time_limit_s"]))
short = marsyn.solve(problem, runs=5, global_budget=0, time_limit=55, log=lambda s: None)
check(short["search"]["time_limit_s"] == 55, "time_limit= wins over the file, as --time-limit: %s" % short["search"]["time_limit_s"])
try:
    marsyn.solve(problem, time_limit=0)
    check(False, "solve(time_limit=0) raises")
except ValueError as e:
    check("time_limit: expected a positive number of seconds" in str(e), "a bad time_limit says what was expected: %s" % e)
check(res["changes"] == [{"agent": "pendulum", "what": "tracker", "given": "never", "used": cli_used}],
      "the search's change is the fallback: %s" % res["changes"])

tube = res["tubes"]["pendulum"]
x_nom = res["nominal"]["pendulum"]["x"]
T = res["plan"]["horizon"]
eps = np.array(res["agents"][0]["eps"])
check(tube["nominal"].shape == (T + 1, 2) and np.array_equal(tube["nominal"], x_nom), "tube around solve()'s nominal")
check(np.array_equal(tube["lo"], x_nom - eps) and np.array_equal(tube["hi"], x_nom + eps), "tube = nominal -+ eps")
check(np.allclose(tube["t"], np.arange(T + 1) * problem.tau), "tube times k tau")
enc = tube["enclosures"]
check(enc is not None and enc["state_lo"].shape[1] == 2 and enc["t0"].size == enc["state_lo"].shape[0] > 0,
      "the tube carries the controller's period enclosures")
runs = res["margins"]
check(len(runs) > 0, "margins of the kept runs")
for m in runs:
    check(m["t"].shape == (T + 1,) and m["samples"]["min"].shape == (T + 1,) and m["dense"]["min"].shape == m["dense_t"].shape,
          "margin arrays of %s: %s %s" % (m["label"], m["t"].shape, m["dense_t"].shape))
    # The pendulum has no obstacle, pair or formation: every such margin is unconstrained.
    check(bool(np.all(np.isposinf(m["samples"]["min"]))), "no requirement between states: inf margins (%s)" % m["label"])

finish("ok: auto fell back from never to %s in track() and solve(), as the CLI" % cli_used)
