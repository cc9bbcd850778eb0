#!/bin/sh
# A funnel controller deployed as C (docs/deploy.md): solve examples/bicycles.yaml, compare the
# exported C of every agent with the C++ controller on 1e5 sampled (x, k) (funnel_export_check),
# build examples/deploy_c/bicycle_closed_loop.c against agent east's export under strict C99 and
# run it (it must reach the goal with the monitor accepting every sampled state, and the monitor
# must flag a push beyond W); SCOTS' format and a wrong --tracker are one line and exit code 2.
# usage: funnel_c.sh MARSYN CC SOURCE_DIR SCRATCH_DIR FUNNEL_EXPORT_CHECK
set -eu
marsyn=$1 cc=$2 src=$3 dir=$4 check=$5
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

"$marsyn" solve "$src/examples/bicycles.yaml" --out "$dir/bicycles" > "$dir/solve.txt" 2>&1 || fail "solve: $(tail -3 "$dir/solve.txt")"
"$check" "$dir"/bicycles/*.ctrl > "$dir/check.txt" || fail "C and C++ differ: $(cat "$dir/check.txt")"
"$marsyn" export "$dir/bicycles" --format c --out "$dir/c" > "$dir/export.txt" || fail "export --format c of a solve folder"
grep -q "const data (flash) [0-9]* bytes in 4 controllers" "$dir/export.txt" || fail "no flash size: $(cat "$dir/export.txt")"
"$marsyn" export "$dir/bicycles/east.ctrl" --format c --prefix bicycle --out "$dir/east" > /dev/null || fail "export --prefix"
# The header says what the monitor's 1 means (issue 52): the guarantee from x, from the step its
# sets are invariant; the bicycles' are invariant at every step.
grep -q "a 1 means the guarantee holds from x" "$dir/east/bicycle.h" || fail "the monitor's meaning is not in the header"
grep -q "^#define BICYCLE_INVARIANT_FROM 0 " "$dir/east/bicycle.h" || fail "the bicycle's sets are not invariant from step 0: $(grep INVARIANT_FROM "$dir/east/bicycle.h")"
"$cc" -std=c99 -Wall -Wextra -Werror -pedantic -Wconversion -O2 -I "$dir/east" "$src/examples/deploy_c/bicycle_closed_loop.c" \
  "$dir/east/bicycle.c" -lm -o "$dir/closed_loop" || fail "the closed-loop example does not build"
for seed in 1 2 3; do
  "$dir/closed_loop" $seed > "$dir/trajectory$seed.csv" 2> "$dir/closed_loop$seed.txt" || fail "closed loop (seed $seed): $(cat "$dir/closed_loop$seed.txt")"
done
"$dir/closed_loop" 1 0.5 > /dev/null 2> "$dir/kick.txt" || fail "monitor: $(cat "$dir/kick.txt")"
# gcc's GNU modes would fuse the multiply-adds where the target has FMA (changing inputs' last
# bits): the source must refuse that build and accept the ISO one.
if [ "$(uname -m)" = x86_64 ] && "$cc" --version | grep -q "Free Software Foundation"; then
  ! "$cc" -std=gnu99 -mfma -O2 -c "$dir/east/bicycle.c" -o "$dir/fused.o" 2> /dev/null || fail "a build that fuses multiply-adds was not refused"
  "$cc" -std=c99 -mfma -O2 -c "$dir/east/bicycle.c" -o "$dir/iso.o" || fail "-std=c99 -mfma does not build"
fi

# Written by `marsyn track` (no result.json beside it): the file itself names its tracker.
mkdir -p "$dir/alone"
cp "$dir/bicycles/west.ctrl" "$dir/alone/"
"$marsyn" export "$dir/alone/west.ctrl" --format c --out "$dir/alone" > /dev/null || fail "export without result.json"

. "$src/tests/deploy/bad_input.sh"
said() { grep -q "$1" "$dir/err.txt" || fail "not the reason: $(cat "$dir/err.txt")"; }
bad "scs of a funnel controller" export "$dir/bicycles/east.ctrl" --format scs --out "$dir/x"
said "funnel controller has no grid"
bad "scs of a solve folder" export "$dir/bicycles" --format scs --out "$dir/x"
said "funnel controller has no grid"
bad "funnel file read as abcd" export "$dir/bicycles/east.ctrl" --format c --tracker abcd --out "$dir/x"
said "east.ctrl"
[ ! -e "$dir/x" ] || [ -z "$(ls -A "$dir/x")" ] || fail "bad input wrote files"
echo "ok: $(cat "$dir/closed_loop1.txt"); $(cat "$dir/kick.txt")"
