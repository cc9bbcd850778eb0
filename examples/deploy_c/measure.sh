#!/bin/sh
# Size and lookup time of exported controllers (docs/deploy.md, docs/benchmarks.md).
# usage: measure.sh MARSYN DIR AGENT SPREAD
#   DIR holds AGENT.ctrl (marsyn track/solve --out DIR) and AGENT.csv (marsyn plan --out DIR);
#   SPREAD: half-width of the uniform offsets around the nominal states of the timed queries.
# Prints one markdown row: agent, n, T, .ctrl bytes, then per encoding the const data bytes
# (exact, as `marsyn export` reports them), the object's size under gcc -Os (text: code + const
# tables) and the mean ns per call under gcc -O2; then per encoding the median, 99.9th percentile
# and worst of 1e6 calls timed one by one. A funnel controller has one table layout: one column.
set -eu
marsyn=$1 dir=$2 agent=$3 spread=$4
src=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
n=$(head -n 1 "$dir/$agent.csv" | tr ',' '\n' | wc -l)
n=$(( (n - 2) ))
# state columns: the CSV has k, t, states..., inputs...; the inputs are empty on the last line
m=$(tail -n 1 "$dir/$agent.csv" | tr ',' '\n' | grep -c '^$' || true)
n=$(( n - m ))
tail -n +2 "$dir/$agent.csv" | cut -d, -f3-$((n + 2)) > "$work/centres.csv"
ctrl_bytes=$(wc -c < "$dir/$agent.ctrl")
row="| $agent | $n | $(( $(wc -l < "$work/centres.csv") - 1 )) | $ctrl_bytes"
encodings="dense rle"
"$marsyn" export "$dir/$agent.ctrl" --format c --prefix ctl --out "$work/probe" | grep -q "funnel controller" && encodings=funnel
calls=""
for enc in $encodings; do
  [ $enc = funnel ] && flag="" || flag="--encoding $enc"
  out=$("$marsyn" export "$dir/$agent.ctrl" --format c $flag --prefix ctl --out "$work/$enc")
  bytes=$(echo "$out" | sed -n 's/.*const data \([0-9]*\) bytes.*/\1/p' | head -n 1)
  gcc -std=c99 -Os -c "$work/$enc/ctl.c" -o "$work/$enc.o"
  text=$(size "$work/$enc.o" | tail -n 1 | awk '{print $1}')
  gcc -std=c99 -O2 -I "$work/$enc" '-DCTRL_HEADER="ctl.h"' -DCTRL_INPUT=ctl_input -DN=$n -DM=$m \
    "$src/lookup_bench.c" "$work/$enc/ctl.c" -lm -o "$work/bench_$enc"
  "$work/bench_$enc" "$work/centres.csv" "$spread" > "$work/times_$enc.txt"
  ns=$(sed -n 's/^\([0-9.]*\) ns.*/\1/p' "$work/times_$enc.txt")
  row="$row | $bytes | $text | $ns"
  calls="$calls$enc: $(sed -n 's/^each of //p' "$work/times_$enc.txt")
"
done
echo "$row |"
printf '%s' "$calls"
