#!/bin/sh
# The outer search over MPI ranks makes the rounds one process makes (docs/mpi.md): every rank
# runs the search in lock step and picks its levers from each failed agent's reason
# (TrackFailure), so the reason must cross the ranks with the agent's result. Two agents of the
# test tracker `never` (tests/fixtures/never_tracker.cpp: a small miss, its coordinate 0 at the
# tube's edge), dealt one to each rank, fail every round; the run over two ranks must end like
# the single process: same rounds, same changes, same result.json except timings.
# Usage: mpi_search.sh MARSYN MPIRUN NEVER_TRACKER_DIR WORKDIR   (exit 77: skipped, no mpirun)
set -eu
marsyn=$1 mpirun=$2 never=$3 work=$4
here=$(dirname "$0")
command -v "$mpirun" >/dev/null 2>&1 || { echo "no $mpirun: skipped"; exit 77; }
rm -rf "$work" && mkdir -p "$work"
agent() {
  cat <<AGENT
  - name: $1
    dynamics: {type: pendulum, params: {input_gain: 0.2}}
    x0: [0, 0]
    goal: {center: [3.141592653589793, 0], radius: [0.5, 2.0]}
    state_bounds: {lo: [-2.5, -3], hi: [4.5, 3]}
    input_bounds: {lo: [-3], hi: [3]}
    disturbance: [0, 0.01]
    eps: [0.2, 0.25]
AGENT
}
{
  printf 'name: mpi-search\ntau: 0.1\nhorizon: 100\npairwise_collision: false\nplanner: altro\n'
  printf 'tracker: never\nplugin_paths: [%s]\nagents:\n' "$never"
  agent missedge_a
  agent missedge_b
} >"$work/never.yaml"
run() {  # FAILED (exit 1) is the expected end; anything else (a hang, a crash) is not
  code=0
  timeout 300 "$@" || code=$?
  [ "$code" -eq 1 ] || { echo "exit $code: $*"; return 1; }
}
run "$marsyn" solve "$work/never.yaml" --out "$work/np1" --runs 5 --time-limit 60 >"$work/np1.log" 2>&1 || { cat "$work/np1.log"; exit 1; }
cores=$(nproc)
over=""
[ 2 -gt "$cores" ] && over="--oversubscribe"
run "$mpirun" --allow-run-as-root $over -np 2 "$marsyn" solve "$work/never.yaml" --out "$work/np2" --runs 5 --time-limit 60 \
  >"$work/np2.log" 2>&1 || { cat "$work/np2.log"; exit 1; }
grep -q "missedge_a on rank 0, missedge_b on rank 1" "$work/np2.log" || { cat "$work/np2.log"; echo "-np 2: the agents were not dealt one to each rank"; exit 1; }
grep -q '"action": "widen eps by the small miss' "$work/np1/result.json" || { echo "single process: no small-miss round"; exit 1; }
python3 "$here/compare_results.py" "$work/np1/result.json" "$work/np2/result.json"
echo "-np 2: the same rounds and result as one process"
