#!/bin/sh
# The crane + vehicle case study as paper Fig. 2 tells it (delta = 0.35): the feedback
# controllers verify while the nominal inputs run open loop under the paper's constant
# disturbances make the load hit the vehicle (a negative collision margin in some run).
# Usage: crane_swing.sh MARSYN_EXE EXAMPLE SCRATCH
set -eu
exe="$1"; example="$2"; scratch="$3"
rm -rf "$scratch"; mkdir -p "$scratch"
"$exe" solve "$example" --out "$scratch/out" > "$scratch/solve.txt" 2> "$scratch/solve.log" || {
  echo "marsyn solve failed:"; cat "$scratch/solve.txt"; tail -20 "$scratch/solve.log"; exit 1; }
grep -q '"status": "verified"' "$scratch/out/result.json" || { echo "not verified:"; cat "$scratch/solve.txt"; exit 1; }
grep -q '^verification  1000 closed-loop runs, 0 violations' "$scratch/solve.txt" || {
  echo "verification found violations:"; cat "$scratch/solve.txt"; exit 1; }
grep -Eq '^  .*collision -[0-9.]+ \(step [0-9]+\).*VIOLATED$' "$scratch/solve.txt" || {
  echo "no open-loop run collides:"; cat "$scratch/solve.txt"; exit 1; }
grep -E 'collision -' "$scratch/solve.txt"
echo "verified with feedback; open loop collides"
