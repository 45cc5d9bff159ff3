#!/usr/bin/env bash
# What a campaign's report costs (issue 37): `wogan report DIR --table` over 2,000 run files, wall
# time and peak memory (/usr/bin/time -v). The runs are real: a small campaign through the GNU
# parallel recipe (examples/cluster/, 10 seeds x random and WOGAN, TESTS tests each), each run then
# copied to make COPIES x 20 files in a folder tree, as a large campaign leaves them. Lines for
# docs/results.md (scripts/results/, section campaigns):
#
#   scripts/bench/campaign_bench.sh | tee target/bench-output/campaigns.txt
#   TESTS=300 BASELINE=/path/to/older/wogan BASELINE_LABEL="commit abc123" scripts/bench/campaign_bench.sh
#
# BASELINE, when set, is another wogan binary given the same files as arguments (one that reads no
# folders), for a before-and-after figure; BASELINE_LABEL says which it is.
set -euo pipefail
cd "$(dirname "$0")/../.."
wogan=$(realpath "${1:-target/release/wogan}")
tests=${TESTS:-30}
copies=${COPIES:-100}
work=target/campaign-bench
command -v parallel > /dev/null || { echo "campaign_bench.sh: needs GNU parallel" >&2; exit 2; }
# The campaign's runs are kept (and, the recipe being resumable, reused); the copies are made anew.
rm -rf "$work/big" && mkdir -p "$work"
printf 'small%s.random --algorithm random --max-tests %s\nsmall%s.wogan --max-tests %s\n' \
  "$tests" "$tests" "$tests" "$tests" > "$work/settings.txt"
SEEDS="$(seq 1 10)" examples/cluster/tasks.sh "$work/settings.txt" > "$work/tasks.txt"
start=$(date +%s.%N)
WOGAN=$wogan examples/cluster/parallel/campaign.sh "$work/tasks.txt" "$work/runs" 2> /dev/null
end=$(date +%s.%N)
runs=$(find "$work/runs" -name "*.small$tests.*.jsonl" | wc -l)
echo "wogan campaign through examples/cluster/parallel/campaign.sh: $runs runs of $tests tests (10 seeds x random and WOGAN, beamng-ai-proxy) in $(awk -v a="$start" -v b="$end" 'BEGIN {printf "%.1f", b - a}') s wall on $(nproc) cores (0 s when they were made before: a campaign resumes)"
# The folder a large campaign leaves: COPIES subfolders of the 20 runs.
for i in $(seq 1 "$copies"); do
  mkdir -p "$work/big/part$i"
  for run in "$work"/runs/*.small"$tests".*.jsonl; do
    cp "$run" "$work/big/part$i/$(basename "$run" .jsonl).copy$i.jsonl"
  done
done
files=$(find "$work/big" -name '*.jsonl' | wc -l)
bytes=$(du -sb "$work/big" | cut -f1)
measure() { # LABEL COMMAND...: one line of wall time and peak RSS
  local label=$1 log=$work/time.log
  shift
  /usr/bin/time -v "$@" > "$work/table.md" 2> "$log" || [ $? -eq 1 ]
  local wall rss
  wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {print $2}' "$log")
  rss=$(awk -F': ' '/Maximum resident set size/ {printf "%.0f", $2 / 1024}' "$log")
  echo "wogan report $label over $files run files ($tests tests each, $((bytes / 1024 / 1024)) MiB): $wall wall (m:ss), peak RSS $rss MiB"
}
measure "DIR --table" "$wogan" report "$work/big" --table
rows=$(grep -c '^| [rw]' "$work/table.md")
find "$work/big" -name '*.jsonl' | sort > "$work/list.txt"
measure "--from LIST --table" "$wogan" report --from "$work/list.txt" --table
if [ -n "${BASELINE:-}" ]; then
  # shellcheck disable=SC2046
  measure "FILE... --table (baseline: ${BASELINE_LABEL:-$BASELINE})" \
    "$BASELINE" report $(cat "$work/list.txt") --table
fi
echo "wogan report tables: $rows configuration rows, each of $((files / 2)) runs"
