#!/usr/bin/env bash
# How a dave2-proxy student behaves on the 300 reference roads, before spending an
# effectiveness run on it: failure rate, how many roads show a graded BOLP (the slope the BOLP
# fitness can climb), how many come near the edge without touching it (where only the distance
# fitness has a slope: the car's centre within 0.2 m of where its 1.9 m wide body would touch the
# lane edge, BOLP <= 0.002), the spread of fitness_distance, and failures by the road's sharpness.
#
#   scripts/experiments/screen_driver.sh                 # the built-in student
#   scripts/experiments/screen_driver.sh student.bin     # weights written by `wogan train-driver`
#
# About 45 s on one core. Needs only bash, sort and awk.
set -euo pipefail
cd "$(dirname "$0")/../.."
weights=${1:-}
[ -n "${WOGAN:-}" ] || cargo build --release -q -p wogan-cli
results=$(mktemp)
trap 'rm -f "$results"' EXIT
"${WOGAN:-./target/release/wogan}" simulate --oracle dave2-proxy ${weights:+--driver-weights "$weights"} \
  tests/reference/roads.jsonl >"$results"
field() { grep -o "\"$1\":[^,}]*" "$results" | cut -d: -f2 | tr -d '"'; }
paste <(field outcome) <(field max_bolp) <(field MAX_CURV) <(field min_lane_distance_m) | awk '
  { n++; band = int($3 / 0.01); if (band > 6) band = 6; roads[band]++;
    if ($1 == "FAIL") { failed++; failed_in[band]++ }
    if ($2 > 0.002 && $2 <= 0.1) graded++
    if ($1 != "FAIL" && $2 <= 0.002 && $4 <= 1.15) near++ }
  END {
    printf "roads %d, FAIL %d (%.1f%%), graded BOLP (0.002 < max_bolp <= 0.1) on %d (%.1f%%)\n",
      n, failed, 100 * failed / n, graded, 100 * graded / n;
    printf "near the edge, untouched (min_lane_distance_m <= 1.15, max_bolp <= 0.002): %d (%.1f%%)\n",
      near, 100 * near / n;
    printf "failures by MAX_CURV band (1/m):";
    for (b = 0; b <= 6; b++) if (roads[b]) printf " %.2f+ %d/%d", b / 100, failed_in[b], roads[b];
    printf "\n" }'
field fitness_distance | sort -g | awk '
  { v[NR] = $1 }
  END { printf "fitness_distance deciles:";
        for (i = 0; i <= 10; i++) printf " %.3f", v[int(i * (NR - 1) / 10) + 1]; printf "\n" }'
