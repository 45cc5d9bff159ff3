#!/usr/bin/env bash
# What a plug point costs (issue 36): the same 300-test search (beamng-ai-proxy, seed 1) with
# wogan's own simulator and with `wogan simulate` as its external executor (the protocol's whole
# round trip: a JSON line out, the drive, a JSON line back), wall seconds, medians of 3, and the
# round trip's cost per road. Lines for docs/results.md:
#
#   scripts/plug_points_bench.sh | tee target/bench-output/plug-points.txt
set -euo pipefail
cd "$(dirname "$0")/.."
wogan=$(realpath "${1:-target/release/wogan}")
work=target/plug-points-bench
rm -rf "$work" && mkdir -p "$work"
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
wall() { # COMMAND...: wall seconds
  local start end
  start=$(date +%s.%N)
  "$@" > /dev/null
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN {print b - a}'
}
own=() outside=()
for i in 1 2 3; do
  own+=("$(wall "$wogan" run --max-tests 300 --seed 1 --quiet --out "$work/own.$i.jsonl")")
  outside+=("$(wall "$wogan" run --max-tests 300 --seed 1 --quiet --out "$work/executor.$i.jsonl" \
    --executor "cmd:$wogan simulate")")
done
a=$(printf '%s\n' "${own[@]}" | median)
b=$(printf '%s\n' "${outside[@]}" | median)
same=$(cmp -s <(jq -c 'select(.type=="test") | [.outcome,.max_bolp]' "$work/own.1.jsonl") \
  <(jq -c 'select(.type=="test") | [.outcome,.max_bolp]' "$work/executor.1.jsonl") && echo yes || echo no)
echo "wogan run --max-tests 300 (beamng-ai-proxy): $a s wall with its own simulator, $b s with --executor cmd:\"wogan simulate\" ($(awk -v a="$a" -v b="$b" 'BEGIN {printf "%.2f", (b - a) / 300 * 1000}') ms more per road: the executor protocol's round trip); the same tests and outcomes: $same"
