#!/bin/sh
# A rank that fails ends the whole run with exit != 0 and that rank's message within seconds,
# never a hang: (1) rank 1 cannot write the controller file it passes to rank 0 (its TMPDIR does
# not exist); (2) rank 0 cannot write the output folder.
# Usage: failing_rank.sh MARSYN MPIRUN CONFIG WORKDIR   (exit 77: skipped, no mpirun)
set -eu
marsyn=$1 mpirun=$2 config=$3 work=$4
command -v "$mpirun" >/dev/null 2>&1 || { echo "no $mpirun: skipped"; exit 77; }
rm -rf "$work" && mkdir -p "$work"
expect_failure() {  # name, message pattern, command...
  name=$1 pattern=$2
  shift 2
  start=$(date +%s)
  rc=0
  timeout 300 "$@" >"$work/$name.log" 2>&1 || rc=$?
  took=$(($(date +%s) - start))
  cat "$work/$name.log"
  [ "$rc" -ne 0 ] || { echo "$name: exit 0"; exit 1; }
  [ "$rc" -ne 124 ] || { echo "$name: hung (killed by timeout after $took s)"; exit 1; }
  grep -q "$pattern" "$work/$name.log" || { echo "$name: no '$pattern' in the output"; exit 1; }
  echo "$name: exit $rc after $took s with the rank's message"
}
# MPMD launch: rank 0 as usual, rank 1 with a TMPDIR it cannot write.
expect_failure rank1_tmpdir "rank 1: cannot pass the controller" \
  "$mpirun" --allow-run-as-root -np 1 "$marsyn" solve "$config" --out "$work/out1" --runs 5 \
  : -np 1 env TMPDIR="$work/no-such-dir" "$marsyn" solve "$config" --out "$work/out1" --runs 5
touch "$work/a-file"
expect_failure rank0_output "a-file" \
  "$mpirun" --allow-run-as-root -np 2 "$marsyn" solve "$config" --out "$work/a-file/out" --runs 5
