#!/bin/sh
# Memory stage by stage (issue 50 item 4): on a field of 25 unicycles (scripts/unicycle_field.py,
# a problem family the verification's figure was fitted on at 25 to 400 robots), what the plan,
# the tracking and the verification add to the process stays within check's prediction + 10 %,
# and the verification's and tracking's predictions are no more than twice what they add (figures
# that say something). Then the plan of 400 robots: the `marsyn plan` process's peak stays within
# check's plan figure plus what check itself holds (the loaded problem and plugins), + 10 %.
# Usage: stage_memory.sh MARSYN_EXE SOURCE_DIR SCRATCH
set -u
exe="$1"; src="$2"; scratch="$3"
rm -rf "$scratch"; mkdir -p "$scratch"
python3 "$src/scripts/unicycle_field.py" 25 --seed 3 --out "$scratch/field25.yaml" > /dev/null || exit 1
"$exe" check "$scratch/field25.yaml" > "$scratch/check.txt" 2>&1 || { cat "$scratch/check.txt"; exit 1; }
grep -q "^          verification about " "$scratch/check.txt" ||
  { echo "check predicts no verification memory:"; cat "$scratch/check.txt"; exit 1; }
"$exe" solve "$scratch/field25.yaml" --runs 20 --global-budget 0 --out "$scratch/out" > "$scratch/solve.txt" 2>&1 ||
  { echo "the field was not verified:"; tail -30 "$scratch/solve.txt"; exit 1; }
python3 - "$scratch/out/result.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))["memory"]
plan, plan_p = m["plan"]["added_bytes"], m["plan_predicted_bytes"]
ver, ver_p = m["verification"]["added_bytes"], m["verification_predicted_bytes"]
trk, trk_p = m["tracking"]["added_bytes"], m["tracking_predicted_bytes"]
print(f"plan {plan / 1e6:.1f} MB of {plan_p / 1e6:.1f} predicted; tracking {trk / 1e6:.1f} MB of {trk_p / 1e6:.1f}; "
      f"verification {ver / 1e6:.1f} MB of {ver_p / 1e6:.1f} predicted")
ok = plan <= 1.1 * plan_p and ver <= 1.1 * ver_p and ver_p <= 2 * ver and trk <= 1.1 * trk_p and trk_p <= 2 * trk
sys.exit(0 if ok else 1)
PY
[ $? -eq 0 ] || exit 1
grep -q "^          tracking at most about " "$scratch/check.txt" ||
  { echo "check predicts no tracking memory:"; cat "$scratch/check.txt"; exit 1; }

python3 "$src/scripts/unicycle_field.py" 400 --seed 1 --out "$scratch/field400.yaml" > /dev/null || exit 1
python3 - "$exe" "$scratch" <<'PY'
import re, resource, subprocess, sys
exe, scratch = sys.argv[1], sys.argv[2]
UNITS = {"bytes": 1, "KiB": 2 ** 10, "MiB": 2 ** 20, "GiB": 2 ** 30}

def peak(args):
    # The child's peak resident size (ru_maxrss of the children waited for so far is the largest
    # of them: check runs first and holds less than the plan).
    r = subprocess.run([exe] + args, capture_output=True, text=True)
    return r, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024.0

c, check_peak = peak(["check", f"{scratch}/field400.yaml"])
m = re.search(r"^memory\s+planning about ([0-9.e+]+) (bytes|KiB|MiB|GiB)", c.stdout, re.M)
if c.returncode != 0 or not m:
    sys.exit("check of field400 gave no plan figure:\n" + c.stdout + c.stderr)
predicted = float(m.group(1)) * UNITS[m.group(2)]
p, plan_peak = peak(["plan", f"{scratch}/field400.yaml", "--out", f"{scratch}/plan400"])
if p.returncode != 0:
    sys.exit("the field of 400 was not planned:\n" + p.stdout[-3000:] + p.stderr[-3000:])
bound = 1.1 * (predicted + check_peak)
print(f"plan of 400 robots: peak {plan_peak / 1e6:.0f} MB; bound {bound / 1e6:.0f} MB "
      f"(1.1 x (planner's {predicted / 1e6:.0f} MB + check's own {check_peak / 1e6:.0f} MB))")
sys.exit(0 if plan_peak <= bound else 1)
PY
