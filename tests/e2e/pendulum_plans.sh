#!/bin/sh
# Paper Sec. 3.5: the dynamics-aware plan of the pendulum swing-up is trackable; the straight
# line from (0, 0) to (pi, 0), which ignores the dynamics, is not.
# Usage: pendulum_plans.sh MARSYN_EXE EXAMPLE SCRATCH
set -u
exe="$1"; example="$2"; scratch="$3"
rm -rf "$scratch"; mkdir -p "$scratch"
"$exe" track "$example" --agent pendulum --out "$scratch/dynamic" > "$scratch/dynamic.txt" 2>&1
code=$?
[ "$code" -eq 0 ] || { echo "the dynamics-aware plan was not tracked (exit $code):"; cat "$scratch/dynamic.txt"; exit 1; }
grep -q "x0's cell winning   yes" "$scratch/dynamic.txt" || { cat "$scratch/dynamic.txt"; exit 1; }
test -s "$scratch/dynamic/pendulum.ctrl" || { echo "no controller file"; exit 1; }
"$exe" track "$example" --agent pendulum --plan straight-line --out "$scratch/line" > "$scratch/line.txt" 2>&1
code=$?
[ "$code" -eq 1 ] || { echo "the straight line should have no controller (exit $code):"; cat "$scratch/line.txt"; exit 1; }
grep -q "status              no controller" "$scratch/line.txt" || { cat "$scratch/line.txt"; exit 1; }
test ! -e "$scratch/line/pendulum.ctrl" || { echo "a controller file was written for an untrackable plan"; exit 1; }
echo "dynamic plan: controller; straight line: no controller"
