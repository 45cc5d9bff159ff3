#!/usr/bin/env bash
# What `--jobs` buys (issue 37), on this machine's cores. Lines for docs/results.md:
# - tests per wall second of a 300-test WOGAN run (the paper's settings) at jobs 1 and 2 on both
#   drivers, medians over seeds 1-3, and the speed-up;
# - failing roads per wall minute of a `--budget` run (default 1m) at jobs 1 and 2, medians over
#   BUDGET_SEEDS (default 1 2 3);
# - a model of N cores from the jobs-1 run's own split of time (below).
# Quality per test (20 seeds, `wogan report --vs`) is made by scripts/runs/search_figures.sh (sets
# jobs2, jobs4, jobs4-restart). Run it on an otherwise idle machine:
#
#   scripts/bench/parallel_bench.sh | tee target/bench-output/parallel.txt
set -euo pipefail
cd "$(dirname "$0")/../.."
wogan=$(realpath "${1:-target/release/wogan}")
budget=${BUDGET:-1m}
seeds=${SEEDS:-1 2 3}
budget_seeds=${BUDGET_SEEDS:-$seeds}
work=target/parallel-bench
rm -rf "$work" && mkdir -p "$work"
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
summary() { jq -r "select(.type == \"summary\") | .$2" "$1"; }

for oracle in beamng-ai-proxy dave2-proxy; do
  declare -A rate=() per_minute=()
  for jobs in 1 2; do
    rates=() minutes=()
    for seed in $seeds; do
      f="$work/$oracle.tests.$jobs.$seed.jsonl"
      "$wogan" run --quiet --oracle "$oracle" --max-tests 300 --seed "$seed" --jobs "$jobs" --out "$f"
      rates+=("$(awk -v w="$(summary "$f" wall_s)" 'BEGIN {print 300 / w}')")
    done
    for seed in $budget_seeds; do
      g="$work/$oracle.budget.$jobs.$seed.jsonl"
      "$wogan" run --quiet --oracle "$oracle" --budget "$budget" --seed "$seed" --jobs "$jobs" --out "$g"
      minutes+=("$(awk -v f="$(summary "$g" failed)" -v w="$(summary "$g" wall_s)" 'BEGIN {print f / (w / 60)}')")
    done
    rate[$jobs]=$(printf '%s\n' "${rates[@]}" | median)
    per_minute[$jobs]=$(printf '%s\n' "${minutes[@]}" | median)
  done
  echo "wogan run --max-tests 300 --oracle $oracle: ${rate[1]} tests per wall second at --jobs 1, ${rate[2]} at --jobs 2 ($(awk -v a="${rate[1]}" -v b="${rate[2]}" 'BEGIN {printf "%.2f", b / a}')x; seeds $seeds, medians)"
  echo "wogan run --budget $budget --oracle $oracle: ${per_minute[1]} failing roads per wall minute at --jobs 1, ${per_minute[2]} at --jobs 2 ($(awk -v a="${per_minute[1]}" -v b="${per_minute[2]}" 'BEGIN {printf "%.2f", b / a}')x; seeds $budget_seeds, medians)"
  # A model of N cores from the first jobs-1 run's split of time: its drives spread over N cores;
  # training once a round of N (every 3 tests up to N = 3), with the analyzer (ANALYZER_SHARE of
  # a round, from the iteration_parts bench) beside the WGAN; the rest (choosing tests, sampling,
  # writing) serial.
  f="$work/$oracle.tests.1.1.jsonl"
  share=${ANALYZER_SHARE:-0.37}
  for n in 2 4 8 16; do
    awk -v w="$(summary "$f" wall_s)" -v s="$(summary "$f" simulation_s)" -v t="$(summary "$f" training_s)" \
      -v a="$share" -v n="$n" -v o="$oracle" 'BEGIN {
        rest = w - s - t
        train = t * (a > 1 - a ? a : 1 - a) * 3 / (n > 3 ? n : 3)
        printf "wogan model of --jobs %d (%s, 300 tests): %.1fx the tests per second of one job (one job: simulation %.0f%%, training %.0f%%, the rest %.0f%%)\n", n, o, w / (rest + train + s / n), 100 * s / w, 100 * t / w, 100 * rest / w }'
  done
done
