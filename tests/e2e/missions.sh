#!/bin/sh
# Issue 26: missions end to end. examples/warehouse.yaml (four robots, pickup -> drop-off ->
# dock) and examples/rendezvous.yaml (a team stage) must verify; result.json lists every stage
# with its visit step inside its window, after the previous stage's dwell, team stages at one
# step, and non-negative plan and certified margins. examples/door_and_walkway.yaml (obstacles
# of one stage) must verify with each staged obstacle binding its agent from the right knots, and
# r2's plan crossing the walkway outside its window (else the scope would not matter). The visit
# knots are the plan's: plan.json lists the knots result.json reports, and `marsyn verify` on the
# saved plan reads them (door_and_walkway verifies at the saved knots and not at knots moved after
# the fact).
# Usage: missions.sh MARSYN_EXE SOURCE_DIR SCRATCH
set -u
exe="$1"; src="$2"; scratch="$3"
rm -rf "$scratch"; mkdir -p "$scratch"
for name in warehouse rendezvous door_and_walkway; do
  "$exe" solve "$src/examples/$name.yaml" --out "$scratch/$name" > "$scratch/$name.txt" 2>&1
  code=$?
  [ "$code" -eq 0 ] || { echo "$name: should verify (exit $code):"; cat "$scratch/$name.txt"; exit 1; }
  python3 - "$scratch/$name/result.json" <<'PY' || exit 1
import json, sys
r = json.load(open(sys.argv[1]))
assert r["status"] == "verified", r["status"]
stages = r["mission"]["stages"]
assert stages, "no stages in result.json"
last, team = {}, {}
for s in stages:
    if s["team"] is not None:
        assert team.setdefault(s["team"], s["visit_step"]) == s["visit_step"], (s, team)
    a = s["agent"]
    assert s["plan_margin"] >= 0, s
    assert s["certified"] is None or s["certified"]["margin"] >= 0, s
    if r["guarantee"] == "continuous":
        assert s["certified"] is not None, s
    assert s["visit_step"] >= s["not_before"], s
    assert s["by"] is None or s["visit_step"] <= s["by"], s
    if a in last:
        assert s["visit_step"] > last[a], (s, last[a])
    last[a] = s["visit_step"] + s["dwell"]
    assert last[a] < r["plan"]["horizon"], s
staged = {(w["obstacle"], w["agent"]): w["steps"] for w in r["mission"]["staged_obstacles"]}
visit = {(s["agent"], s["stage"]): s["visit_step"] + s["dwell"] for s in stages}
saved = json.load(open(sys.argv[1].replace("result.json", "plan.json")))
knots = {(a["name"], v["stage"]): v["step"] for a in saved["agents"] for v in a.get("visits", [])}
assert knots == {(s["agent"], s["stage"]): s["visit_step"] for s in stages}, (knots, stages)
T = r["plan"]["horizon"]
# One solve to a plan robust in continuous time: the clearance between the samples follows each
# agent's fastest leg (b crosses the room after the meeting); later attempts re-time the knots.
assert saved["attempts"][0]["robust"], saved["attempts"][0]
if r["problem"] == "door-and-walkway":
    assert staged == {("door", "r1"): "steps %d-%d" % (visit[("r1", "through")], T),
                      ("walkway", "r2"): "steps %d-%d" % (visit[("r2", "pickup")], visit[("r2", "dropoff")])}, staged
    plan = json.load(open(sys.argv[1].replace("result.json", "plan.json")))
    r2 = next(a for a in plan["agents"] if a["name"] == "r2")
    on = [k for k, x in enumerate(r2["states"]) if 2.0 <= x[0] <= 2.6]  # on the walkway itself
    assert on and all(k < visit[("r2", "pickup")] or k > visit[("r2", "dropoff")] for k in on), on
    assert any(k < visit[("r2", "pickup")] for k in on) and any(k > visit[("r2", "dropoff")] for k in on), on
    print("staged obstacles bind", staged)
print(len(stages), "stages in order, in their windows, certified")
PY
  grep -q "Mission: stages in order" "$scratch/$name/report.html" || { echo "$name: report.html lacks the mission table"; exit 1; }
  echo "$name: VERIFIED"
done
# The saved plan's knots are what `marsyn verify` judges: as saved it passes; with r2's drop-off
# knot moved 25 steps earlier (still in order and in its window) the runs find r2 outside it.
door="$scratch/door_and_walkway"
"$exe" verify "$src/examples/door_and_walkway.yaml" --controllers "$door" --runs 20 > "$scratch/door_verify.txt" 2>&1 ||
  { echo "verify on the saved plan should pass:"; cat "$scratch/door_verify.txt"; exit 1; }
python3 - "$door/plan.json" "$scratch/moved.json" <<'PY' || exit 1
import json, sys
p = json.load(open(sys.argv[1]))
r2 = next(a for a in p["agents"] if a["name"] == "r2")
drop = next(v for v in r2["visits"] if v["stage"] == "dropoff")
drop["step"] -= 25
json.dump(p, open(sys.argv[2], "w"))
PY
if "$exe" verify "$src/examples/door_and_walkway.yaml" --controllers "$door" --plan "$scratch/moved.json" --runs 20 \
     > "$scratch/moved_verify.txt" 2>&1; then
  echo "verify at knots moved after the fact should find violations:"; cat "$scratch/moved_verify.txt"; exit 1
fi
grep -q "stage dropoff of r2" "$scratch/moved_verify.txt" ||
  { echo "the moved knot's stage should be the violation:"; cat "$scratch/moved_verify.txt"; exit 1; }
echo "verify reads the saved plan's knots"
