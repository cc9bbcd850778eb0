#!/bin/sh
# A team whose joint solve loses its way is started again from each agent's own plan alone, side
# by side (docs/planning.md "Agents alone first"): four bicycles turning through a junction
# (tests/problems/users3/intersection.yaml at T = 247) are short by about 10 at a goal from the
# straight ways; from the agents' own plans the joint solve is eps-robust at the same horizon.
# Usage: agents_alone.sh MARSYN_EXE SOURCE_DIR SCRATCH
set -u
exe="$1"; src="$2"; scratch="$3"
rm -rf "$scratch"; mkdir -p "$scratch"
sed 's/^horizon: 100 .*/horizon: 247/' "$src/tests/problems/users3/intersection.yaml" > "$scratch/junction.yaml"
grep -q '^horizon: 247' "$scratch/junction.yaml" || { echo "the horizon was not set"; exit 1; }
"$exe" plan "$scratch/junction.yaml" --out "$scratch/out" > "$scratch/plan.txt" 2>&1
code=$?
grep -q "from each agent's own plan alone, side by side" "$scratch/plan.txt" ||
  { echo "the agents' own plans were not tried:"; cat "$scratch/plan.txt"; exit 1; }
[ "$code" -eq 0 ] && grep -q "^FEASIBLE: horizon 247" "$scratch/plan.txt" ||
  { echo "no eps-robust plan at T = 247 (exit $code):"; cat "$scratch/plan.txt"; exit 1; }
echo "ok: eps-robust at T = 247 from the agents' own plans"
