#!/bin/sh
# fuzz.problem_loader: build the clang fuzzing tree (the loader's files of core with coverage +
# ASan/UBSan, see fuzz/CMakeLists.txt; the four dynamics plugins) and run problem_loader_fuzzer
# for SECONDS from the examples and the bad-input suite. Fails on any crash, sanitizer report,
# leak or non-ConfigError exception (libFuzzer exits non-zero and writes crash-*/leak-*/timeout-*
# into the artifact folder named in the log).
# usage: run_fuzz.sh SOURCE_DIR TREE CLANGXX SECONDS
set -eu
src=$1; tree=$2; cxx=$3; seconds=$4
launcher=""
command -v ccache >/dev/null 2>&1 && launcher="-DCMAKE_CXX_COMPILER_LAUNCHER=ccache"
cmake -S "$src" -B "$tree" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMARSYN_FUZZ=ON \
  -DMARSYN_BUILD_TESTS=OFF -DMARSYN_SKIP_PLUGINS="tracker_abcd;planner_altro;planner_ipopt;planner_nlopt;planner_ompl;collision_fcl" \
  $launcher >"$tree.configure.log" 2>&1 || { cat "$tree.configure.log"; exit 1; }
cmake --build "$tree" -j2 --target problem_loader_fuzzer marsyn_dynamics_unicycle marsyn_dynamics_cartpole \
  marsyn_dynamics_double_integrator marsyn_dynamics_pendulum >"$tree.build.log" 2>&1 || { tail -50 "$tree.build.log"; exit 1; }
corpus="$tree/corpus"; artifacts="$tree/artifacts"
mkdir -p "$corpus" "$artifacts"
seeds="$tree/seeds"; rm -rf "$seeds"; mkdir -p "$seeds"
cp "$src"/examples/*.yaml "$src"/tests/bad_inputs/*.yaml "$seeds"/
# The RSS limit and per-input timeout catch runaway allocation and hangs in the loader.
exec "$tree/bin/problem_loader_fuzzer" "$corpus" "$seeds" -dict="$src/fuzz/yaml.dict" -max_len=16384 \
  -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -artifact_prefix="$artifacts/" -print_final_stats=1
