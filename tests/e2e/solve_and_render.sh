#!/bin/sh
# End to end as a user runs it: `marsyn solve` on an example, then the report rendered by a
# headless Chromium: the screenshot must not be blank and the page's script must have filled in
# the verdict and the tables.
# Usage: solve_and_render.sh MARSYN_EXE EXAMPLE SCRATCH [RUNS]
set -eu
exe="$1"; example="$2"; scratch="$3"; runs="${4:-200}"
rm -rf "$scratch"; mkdir -p "$scratch"
"$exe" solve "$example" --out "$scratch/out" --runs "$runs" > "$scratch/solve.txt" 2> "$scratch/solve.log" || {
  echo "marsyn solve failed:"; cat "$scratch/solve.txt" "$scratch/solve.log"; exit 1; }
grep -q '"status": "verified"' "$scratch/out/result.json" || { echo "not verified:"; cat "$scratch/out/result.json"; exit 1; }
grep -q '"violations": 0' "$scratch/out/result.json" || { echo "violations in verification"; exit 1; }
for f in report.html plan.json result.json; do test -s "$scratch/out/$f" || { echo "missing $f"; exit 1; }; done
ls "$scratch/out"/*.ctrl > /dev/null || { echo "no controller files"; exit 1; }
# The controllers replay from their files alone (no tracker state): `marsyn simulate`.
"$exe" simulate "$example" --controllers "$scratch/out" --disturbance switching --seed 3 > "$scratch/sim.txt" 2>&1 || {
  echo "marsyn simulate failed:"; cat "$scratch/sim.txt"; exit 1; }
grep -q "specification satisfied" "$scratch/sim.txt" && grep -q "(inside)" "$scratch/sim.txt" || { cat "$scratch/sim.txt"; exit 1; }

browser=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$browser" ]; then echo "chromium is not installed (scripts/install-deps.sh installs it)"; exit 1; fi
flags="--headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking \
--disable-component-update --disable-sync --user-data-dir=$scratch/profile"
# shellcheck disable=SC2086
timeout 120 "$browser" $flags --window-size=1400,1100 --virtual-time-budget=3000 \
  --screenshot="$scratch/report.png" "file://$scratch/out/report.html" > "$scratch/chromium.log" 2>&1 || true
test -s "$scratch/report.png" || { echo "no screenshot"; cat "$scratch/chromium.log"; exit 1; }
size=$(wc -c < "$scratch/report.png")
# A blank 1400x1100 page compresses to a few kB; the report with canvas, tables and plot is far larger.
[ "$size" -gt 40000 ] || { echo "screenshot looks blank ($size bytes)"; exit 1; }
# shellcheck disable=SC2086
timeout 120 "$browser" $flags --virtual-time-budget=3000 --dump-dom "file://$scratch/out/report.html" \
  > "$scratch/dom.html" 2>> "$scratch/chromium.log" || true
grep -q 'class="badge ok">VERIFIED' "$scratch/dom.html" || { echo "the page did not show the verdict"; exit 1; }
grep -q '<polyline' "$scratch/dom.html" || grep -q 'no obstacle, collision or formation' "$scratch/dom.html" || {
  echo "the margin plot is missing"; exit 1; }
grep -q '<td>+W for all agents</td>' "$scratch/dom.html" || { echo "the open-loop table per run is missing"; exit 1; }
echo "solved, verified, and the report renders ($size-byte screenshot)"
