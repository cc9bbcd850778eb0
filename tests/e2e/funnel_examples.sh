#!/bin/sh
# Issue 11: agents with 5 and 6 states get verified controllers from the funnel tracker, chosen by
# `tracker: auto` (and issue 23: 12-state quadrotors in a 3-D workspace); the adversarial closed loop stays safe between the samples; and on a unicycle
# example both trackers verify.
# Usage: funnel_examples.sh MARSYN_EXE SOURCE_DIR SCRATCH
set -u
exe="$1"; src="$2"; scratch="$3"
rm -rf "$scratch"; mkdir -p "$scratch"
fail() { echo "$1"; [ -f "$2" ] && cat "$2"; exit 1; }
for name in bicycles planar_quadrotors quadrotors; do
  out="$scratch/$name"
  "$exe" solve "$src/examples/$name.yaml" --out "$out" --runs 200 --global-budget 0 > "$out.txt" 2>&1
  code=$?
  [ "$code" -eq 0 ] || fail "$name: should verify (exit $code)" "$out.txt"
  grep -q "^status        VERIFIED" "$out.txt" || fail "$name: not VERIFIED" "$out.txt"
  grep -q "^certification certified in continuous time" "$out.txt" || fail "$name: not certified" "$out.txt"
  # Every agent's tracker was chosen by auto, and it is the funnel.
  agents=$(grep -c '"chosen": "auto"' "$out/result.json")
  funnels=$(grep -c '"assessment": "LQR funnel' "$out/result.json")
  [ "$agents" -eq 4 ] && [ "$funnels" -eq 4 ] || fail "$name: expected 4 agents on funnel by auto ($agents, $funnels)" "$out/result.json"
  for seed in 1 2; do
    "$exe" simulate "$src/examples/$name.yaml" --controllers "$out" --disturbance adversarial --seed $seed > "$out-adv.txt" 2>&1
    code=$?
    [ "$code" -eq 0 ] || fail "$name: adversarial run $seed violates (exit $code)" "$out-adv.txt"
    grep -q "^between       satisfied" "$out-adv.txt" || fail "$name: not satisfied between samples" "$out-adv.txt"
  done
  echo "$name: VERIFIED with funnel controllers; adversarial closed loop satisfied"
done
# The quadrotors fly in a 3-D workspace: the report draws a side view (x-z) and a front view (y-z).
grep -q '"side":' "$scratch/quadrotors/report.html" || fail "quadrotors: report.html has no side view" "$scratch/quadrotors.txt"
grep -q '"front":' "$scratch/quadrotors/report.html" || fail "quadrotors: report.html has no front view" "$scratch/quadrotors.txt"
# The multi-drone example with each tracker.
for tracker in abcd funnel; do
  problem="$scratch/multi_drone_$tracker.yaml"
  sed "s/^tracker: abcd/tracker: $tracker/" "$src/examples/multi_drone.yaml" > "$problem"
  out="$scratch/multi_drone_$tracker"
  "$exe" solve "$problem" --out "$out" --runs 200 --global-budget 0 > "$out.txt" 2>&1
  code=$?
  [ "$code" -eq 0 ] || fail "multi_drone with $tracker: should verify (exit $code)" "$out.txt"
  grep -q "^status        VERIFIED" "$out.txt" || fail "multi_drone with $tracker: not VERIFIED" "$out.txt"
  grep -q "(${tracker}): controller" "$out.txt" || fail "multi_drone: $tracker was not used" "$out.txt"
  echo "multi_drone: VERIFIED with $tracker"
done
# Bodies of their own size (issue 51): two ground robots and a drone with their radii and delta
# by kind verify, the adversarial closed loop keeps the bodies apart, and check names the bodies.
out="$scratch/air_ground"
"$exe" check "$src/examples/air_ground.yaml" > "$out-check.txt" 2>&1 || fail "air_ground: check failed" "$out-check.txt"
grep -q "^bodies    robot1, robot2: radius 0.25; drone: radius 0.15" "$out-check.txt" || fail "air_ground: no bodies line" "$out-check.txt"
"$exe" solve "$src/examples/air_ground.yaml" --out "$out" --runs 200 --global-budget 0 > "$out.txt" 2>&1
code=$?
[ "$code" -eq 0 ] || fail "air_ground: should verify (exit $code)" "$out.txt"
grep -q "^status        VERIFIED" "$out.txt" || fail "air_ground: not VERIFIED" "$out.txt"
"$exe" simulate "$src/examples/air_ground.yaml" --controllers "$out" --disturbance adversarial --seed 1 > "$out-adv.txt" 2>&1
[ "$?" -eq 0 ] || fail "air_ground: adversarial run violates" "$out-adv.txt"
grep -q "^between       satisfied" "$out-adv.txt" || fail "air_ground: not satisfied between samples" "$out-adv.txt"
echo "air_ground: VERIFIED with bodies; adversarial closed loop satisfied"
# Several bodies (issue 51): the tractor and its cart verify, and the adversarial closed loop keeps
# both clear of the wall.
out="$scratch/tractor_trailer"
"$exe" solve "$src/examples/tractor_trailer.yaml" --out "$out" --runs 200 --global-budget 0 > "$out.txt" 2>&1
[ "$?" -eq 0 ] || fail "tractor_trailer: should verify" "$out.txt"
grep -q "^status        VERIFIED" "$out.txt" || fail "tractor_trailer: not VERIFIED" "$out.txt"
grep -q '"name": "cart"' "$out/result.json" || fail "tractor_trailer: result.json lists no cart" "$out/result.json"
"$exe" simulate "$src/examples/tractor_trailer.yaml" --controllers "$out" --disturbance adversarial --seed 1 > "$out-adv.txt" 2>&1
[ "$?" -eq 0 ] || fail "tractor_trailer: adversarial run violates" "$out-adv.txt"
grep -q "^between       satisfied" "$out-adv.txt" || fail "tractor_trailer: not satisfied between samples" "$out-adv.txt"
echo "tractor_trailer: VERIFIED with two bodies; adversarial closed loop satisfied"
