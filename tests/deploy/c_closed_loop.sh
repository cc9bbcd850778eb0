#!/bin/sh
# `marsyn export` as a user runs it (docs/deploy.md): track the pendulum, export it as C99, build
# examples/deploy_c/pendulum_closed_loop.c against it under -std=c99 -Wall -Wextra -Werror
# -pedantic, and run the closed loop written in C (it must reach the goal under disturbances);
# export SCOTS' format; every kind of bad input is one line on stderr and exit code 2.
# usage: c_closed_loop.sh MARSYN CC SOURCE_DIR SCRATCH_DIR
set -eu
marsyn=$1 cc=$2 src=$3 dir=$4
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

"$marsyn" track "$src/examples/pendulum.yaml" --agent pendulum --out "$dir" > "$dir/track.txt" 2>&1 || fail "track: $(tail -3 "$dir/track.txt")"
"$marsyn" export "$dir/pendulum.ctrl" --format c --out "$dir/c" > "$dir/export.txt" || fail "export --format c"
grep -q "const data (flash) [0-9]* bytes" "$dir/export.txt" || fail "no flash size reported: $(cat "$dir/export.txt")"
"$cc" -std=c99 -Wall -Wextra -Werror -pedantic -O2 -I "$dir/c" "$src/examples/deploy_c/pendulum_closed_loop.c" "$dir/c/pendulum.c" -lm \
  -o "$dir/closed_loop" || fail "the closed-loop example does not build"
for seed in 1 2 3; do
  "$dir/closed_loop" $seed > "$dir/trajectory$seed.csv" 2> "$dir/closed_loop$seed.txt" || fail "closed loop (seed $seed): $(cat "$dir/closed_loop$seed.txt")"
done
"$marsyn" export "$dir" --format scs --out "$dir/scs" > /dev/null || fail "export --format scs of a folder"
[ "$(head -n 1 "$dir/scs/pendulum.scs")" = "#SCOTS:v0.2" ] || fail "not a SCOTS v0.2 file"
"$marsyn" export "$dir/pendulum.ctrl" --format c --encoding dense --prefix ctl_1 --out "$dir/dense" > /dev/null || fail "--prefix/--encoding"
[ -f "$dir/dense/ctl_1.c" ] && grep -q "int ctl_1_input(const double \*x, int k, double \*u);" "$dir/dense/ctl_1.h" || fail "prefix not applied"

# Bad input: exit code 2, one line.
head -c 200 "$dir/pendulum.ctrl" > "$dir/corrupt.ctrl"
printf 'MARSYNCT-not-really' > "$dir/garbage.ctrl"
. "$src/tests/deploy/bad_input.sh"
bad "missing file" export "$dir/nope.ctrl" --format c --out "$dir/x"
bad "truncated controller" export "$dir/corrupt.ctrl" --format c --out "$dir/x"
bad "not a controller" export "$dir/garbage.ctrl" --format scs --out "$dir/x"
bad "bad prefix" export "$dir/pendulum.ctrl" --format c --prefix 2fast --out "$dir/x"
bad "bad prefix chars" export "$dir/pendulum.ctrl" --format c --prefix "a-b" --out "$dir/x"
bad "unknown format" export "$dir/pendulum.ctrl" --format matlab --out "$dir/x"
bad "unknown encoding" export "$dir/pendulum.ctrl" --format c --encoding zip --out "$dir/x"
bad "unknown tracker" export "$dir/pendulum.ctrl" --format c --tracker nope --out "$dir/x"
mkdir -p "$dir/empty"
bad "folder without controllers" export "$dir/empty" --format c --out "$dir/y"
[ ! -e "$dir/x" ] || [ -z "$(ls -A "$dir/x")" ] || fail "bad input wrote files"
echo "ok: $(cat "$dir/closed_loop1.txt")"
