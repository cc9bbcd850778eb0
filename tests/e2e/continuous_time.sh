#!/bin/sh
# Issue 10: problems whose samples are safe while the motion between them is not. Under
# `guarantee: sampled` (the paper's semantics) each is VERIFIED and the dense closed-loop check
# sees the violation between the samples; under the default continuous guarantee each is refused
# (no plan, or no certificate), and simulate with the sampled controllers reports the violation.
# Usage: continuous_time.sh MARSYN_EXE SOURCE_DIR SCRATCH
set -u
exe="$1"; src="$2"; scratch="$3"
rm -rf "$scratch"; mkdir -p "$scratch"
for name in thin_wall narrow_swap; do
  problem="$src/tests/continuous/$name.yaml"
  sampled="$scratch/${name}_sampled.yaml"
  sed 's/^tau:/guarantee: sampled\ntau:/' "$problem" > "$sampled"
  "$exe" solve "$sampled" --out "$scratch/$name-sampled" --runs 200 > "$scratch/$name-sampled.txt" 2>&1
  code=$?
  [ "$code" -eq 0 ] || { echo "$name: sampled guarantee should verify (exit $code):"; cat "$scratch/$name-sampled.txt"; exit 1; }
  grep -q '"guarantee": "sampled"' "$scratch/$name-sampled/result.json" || { echo "$name: result.json lacks the guarantee"; exit 1; }
  # The dense check between the samples sees what the samples hide.
  grep -Eq "between them \(dense" "$scratch/$name-sampled.txt" || { cat "$scratch/$name-sampled.txt"; exit 1; }
  grep -Eq ", -[0-9.]+ between them \(dense" "$scratch/$name-sampled.txt" ||
    { echo "$name: the dense check found no violation between the samples:"; cat "$scratch/$name-sampled.txt"; exit 1; }
  # simulate with the problem's default guarantee and the sampled-semantics controllers: violated.
  "$exe" simulate "$problem" --controllers "$scratch/$name-sampled" --disturbance none > "$scratch/$name-sim.txt" 2>&1
  code=$?
  [ "$code" -eq 1 ] || { echo "$name: simulate should report the violation between samples (exit $code):"; cat "$scratch/$name-sim.txt"; exit 1; }
  grep -q "^between       VIOLATED" "$scratch/$name-sim.txt" || { cat "$scratch/$name-sim.txt"; exit 1; }
  "$exe" solve "$problem" --out "$scratch/$name-continuous" --runs 200 > "$scratch/$name-continuous.txt" 2>&1
  code=$?
  [ "$code" -eq 1 ] || { echo "$name: the continuous guarantee must refuse (exit $code):"; cat "$scratch/$name-continuous.txt"; exit 1; }
  grep -q '"status": "failed"' "$scratch/$name-continuous/result.json" || { echo "$name: result.json is not failed"; exit 1; }
  grep -q '"guarantee": "continuous"' "$scratch/$name-continuous/result.json" || { echo "$name: result.json lacks the guarantee"; exit 1; }
  echo "$name: sampled VERIFIED with a violation between samples; continuous refused"
done
# The same corridor with a door: VERIFIED in continuous time, and under the adversary that
# re-chooses its vertex of W at every integration substep toward the nearest wall, every margin
# between the samples stays non-negative.
door="$src/tests/continuous/door.yaml"
"$exe" solve "$door" --out "$scratch/door" --runs 200 > "$scratch/door.txt" 2>&1
code=$?
[ "$code" -eq 0 ] || { echo "door: should verify in continuous time (exit $code):"; cat "$scratch/door.txt"; exit 1; }
grep -q "^certification certified in continuous time" "$scratch/door.txt" || { cat "$scratch/door.txt"; exit 1; }
for seed in 1 2 3; do
  "$exe" simulate "$door" --controllers "$scratch/door" --disturbance adversarial --seed $seed > "$scratch/door-adv.txt" 2>&1
  code=$?
  [ "$code" -eq 0 ] || { echo "door: adversarial run $seed violates (exit $code):"; cat "$scratch/door-adv.txt"; exit 1; }
  grep -q "^between       satisfied" "$scratch/door-adv.txt" || { cat "$scratch/door-adv.txt"; exit 1; }
done
echo "door: continuous VERIFIED, adversarial closed loop satisfied between the samples"
