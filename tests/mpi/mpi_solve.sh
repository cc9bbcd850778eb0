#!/bin/sh
# Solves CONFIG in one process and then under `mpirun -np R` for each R given; every run must be
# VERIFIED with controller files byte-identical (cmp) to the single process's and result.json
# identical except timings (compare_results.py). Ranks beyond the cores are oversubscribed.
# Usage: mpi_solve.sh MARSYN MPIRUN CONFIG WORKDIR RUNS R...   (exit 77: skipped, no mpirun)
set -eu
marsyn=$1 mpirun=$2 config=$3 work=$4 runs=$5
shift 5
here=$(dirname "$0")
command -v "$mpirun" >/dev/null 2>&1 || { echo "no $mpirun: skipped"; exit 77; }
rm -rf "$work" && mkdir -p "$work"
cores=$(nproc)
"$marsyn" solve "$config" --out "$work/np1" --runs "$runs" >"$work/np1.log" 2>&1 || { cat "$work/np1.log"; exit 1; }
grep -q '"status": "verified"' "$work/np1/result.json" || { echo "single process: not verified"; exit 1; }
for np in "$@"; do
  over=""
  [ "$np" -gt "$cores" ] && over="--oversubscribe"
  start=$(date +%s)
  # --allow-run-as-root: CI runs as root, which Open MPI refuses without it.
  if ! timeout 900 "$mpirun" --allow-run-as-root $over -np "$np" "$marsyn" solve "$config" --out "$work/np$np" \
      --runs "$runs" >"$work/np$np.log" 2>&1; then
    cat "$work/np$np.log"; echo "mpirun -np $np failed"; exit 1
  fi
  grep -q '"status": "verified"' "$work/np$np/result.json" || { cat "$work/np$np.log"; echo "-np $np: not verified"; exit 1; }
  grep -q "ranks: " "$work/np$np.log" || { cat "$work/np$np.log"; echo "-np $np: no rank assignment in the log"; exit 1; }
  n=0
  for c in "$work"/np1/*.ctrl; do
    cmp "$c" "$work/np$np/$(basename "$c")" || { echo "-np $np: $(basename "$c") differs"; exit 1; }
    n=$((n + 1))
  done
  python3 "$here/compare_results.py" "$work/np1/result.json" "$work/np$np/result.json"
  echo "-np $np: verified, $n controllers byte-identical, result.json identical except timings ($(($(date +%s) - start)) s)"
done
