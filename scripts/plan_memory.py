#!/usr/bin/env python3
"""The plan stage's memory against the figure `marsyn check` predicts for it (issue 50 item 4):
unicycle fields of N robots (scripts/unicycle_field.py, a fixed density), each checked (the
loader's estimate: the planner's own, Planner::memory) and planned until SIGINT after the time
limit (the plan then ends after the solve in progress; the peak is reached in the first solve);
prints N, the predicted figure, the measured peaks of `plan` and of `check` (the loaded process
alone) and the ratio of their difference to the prediction (at most 1.1 is the target).

    python3 scripts/plan_memory.py --marsyn build/bin/marsyn --agents 100 400 --time-limit 60
"""
import argparse
import os
import re
import resource
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
UNITS = {"bytes": 1, "KiB": 1024, "MiB": 1024 ** 2, "GiB": 1024 ** 3, "TiB": 1024 ** 4}


def predicted(marsyn, problem):
    out = subprocess.run([marsyn, "check", problem], capture_output=True, text=True, check=True).stdout
    m = re.search(r"^memory\s+planning about ([0-9.e+]+) (bytes|KiB|MiB|GiB|TiB)", out, re.M)
    if not m:
        sys.exit("no 'memory planning about' line in marsyn check's summary")
    return float(m.group(1)) * UNITS[m.group(2)]


def peak_of(cmd):
    """The maximum resident set of one command, in bytes (run in a fresh child: RUSAGE_CHILDREN's
    maximum is over all children so far)."""
    code = ("import resource, subprocess, sys; subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, "
            "stderr=subprocess.DEVNULL); print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)")
    r = subprocess.run([sys.executable, "-c", code] + cmd, capture_output=True, text=True, check=True)
    return float(r.stdout.strip()) * 1024


def measured_peak(marsyn, problem, out_dir, time_limit):
    """Peak resident set of one `marsyn plan` (a fresh child each time: RUSAGE_CHILDREN's maximum
    is over all children so far, so each run is measured in its own process)."""
    # SIGINT after the time limit: `marsyn plan` ends after the solve in progress.
    return peak_of(["timeout", "-s", "INT", str(time_limit), marsyn, "plan", problem, "--out", out_dir])


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--marsyn", default=os.path.join(HERE, "..", "build", "bin", "marsyn"))
    p.add_argument("--agents", type=int, nargs="+", default=[100, 400])
    p.add_argument("--time-limit", type=float, default=60, help="seconds per plan (default 60)")
    a = p.parse_args()
    # The plan's own memory: the peak of `marsyn plan` less that of `marsyn check` (the process with
    # the problem loaded and the plugins open, which the estimate leaves out).
    print(f"{'robots':>7} {'predicted MB':>13} {'plan peak MB':>13} {'check peak MB':>14} {'(plan - check)/predicted':>25}")
    with tempfile.TemporaryDirectory() as tmp:
        for n in a.agents:
            problem = os.path.join(tmp, f"field{n}.yaml")
            subprocess.run([sys.executable, os.path.join(HERE, "unicycle_field.py"), str(n), "--out", problem], check=True)
            pred = predicted(a.marsyn, problem)
            base = peak_of([a.marsyn, "check", problem])
            peak = measured_peak(a.marsyn, problem, os.path.join(tmp, f"plan{n}"), a.time_limit)
            print(f"{n:>7} {pred / 1e6:>13.0f} {peak / 1e6:>13.0f} {base / 1e6:>14.0f} {(peak - base) / pred:>25.2f}", flush=True)


if __name__ == "__main__":
    main()
