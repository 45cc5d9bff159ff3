#!/usr/bin/env bash
# The CI commands' costs (issue 35's numbers), each the median of 5 repetitions, printed as lines
# that scripts/results/ keeps (save them: scripts/bench/ci_bench.sh | tee target/bench-output/ci.txt):
# - a 50-test seeded smoke run on beamng-ai-proxy: CPU seconds (user + system), bar 5 s of one core,
#   and whether its records and JUnit report are the same each time but for timings;
# - replaying a 100-road suite on dave2-proxy with --jobs 2: wall seconds, bar 10 s on this machine.
#
#   scripts/bench/ci_bench.sh [WOGAN]
set -euo pipefail
cd "$(dirname "$0")/../.."
wogan=$(realpath "${1:-target/release/wogan}")
work=target/ci-bench
rm -rf "$work" && mkdir -p "$work"
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
mask='walk(if type == "object" then with_entries(if (.key | IN("generation_ms","execution_ms","wall_s","generation_s","training_s","simulation_s","train_ms","sbst_generation_ms","sbst_generation_s")) then .value = "masked" else . end) else . end)'

cpu=()
for i in 1 2 3 4 5; do
  /usr/bin/time -f "%U %S" -o "$work/time.$i" \
    "$wogan" run --max-tests 50 --seed 1 --quiet --fail-on failure \
    --junit "$work/smoke.$i.xml" --out "$work/smoke.$i.jsonl" || [ $? -eq 1 ]
  cpu+=("$(awk '{print $1 + $2}' "$work/time.$i")")
  jq -c "$mask" "$work/smoke.$i.jsonl" > "$work/smoke.$i.masked"
  sed -E 's/ time="[^"]*"//; s/smoke\.[0-9]\.jsonl/smoke.jsonl/' "$work/smoke.$i.xml" > "$work/smoke.$i.xml.masked"
done
same=yes
for i in 2 3 4 5; do
  cmp -s "$work/smoke.1.masked" "$work/smoke.$i.masked" || same=no
  cmp -s "$work/smoke.1.xml.masked" "$work/smoke.$i.xml.masked" || same=no
done
echo "wogan run --max-tests 50 --seed 1 (beamng-ai-proxy, --junit): $(printf '%s\n' "${cpu[@]}" | median) s of CPU, median of 5 (bar 5 s of one core); records and JUnit identical but for timings: $same"

# A 100-road suite: the most different failing roads of three seeded runs.
for seed in 1 2 3; do
  "$wogan" run --max-tests 300 --seed "$seed" --quiet --out "$work/train.$seed.jsonl"
done
"$wogan" suite add "$work"/train.*.jsonl --to "$work/suite.jsonl" --max 100 2>/dev/null
roads=$(grep -c '"type":"road"' "$work/suite.jsonl")
wall=()
for i in 1 2 3 4 5; do
  start=$(date +%s.%N)
  "$wogan" replay "$work/suite.jsonl" --oracle dave2-proxy --jobs 2 --junit "$work/replay.xml" \
    > /dev/null 2>&1 || true
  wall+=("$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN {print b - a}')")
done
echo "wogan replay of a $roads-road suite --oracle dave2-proxy --jobs 2: $(printf '%.2f\n' "${wall[@]}" | median) s wall, median of 5 (bar 10 s), $(nproc) cores"
