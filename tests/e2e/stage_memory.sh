#!/bin/sh
# Memory stage by stage (issue 50 item 4): on a field of 25 unicycles (scripts/unicycle_field.py,
# a problem family the verification's figure was fitted on at 25 to 400 robots), what the plan
# and the verification add to the process stays within check's prediction + 10 %, and the
# verification's prediction is no more than twice what it adds (a figure that says something).
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
print(f"plan {plan / 1e6:.1f} MB of {plan_p / 1e6:.1f} predicted; verification {ver / 1e6:.1f} MB of {ver_p / 1e6:.1f} predicted")
ok = plan <= 1.1 * plan_p and ver <= 1.1 * ver_p and ver_p <= 2 * ver
sys.exit(0 if ok else 1)
PY
