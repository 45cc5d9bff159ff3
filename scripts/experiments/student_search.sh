#!/usr/bin/env bash
# Trains one dave2-proxy student per seed with the same training settings and screens each on the
# reference roads (scripts/experiments/screen_driver.sh), one summary line per seed: students are a steep,
# erratic function of their training, so a profile is found by trying many seeds.
#
#   scripts/experiments/student_search.sh [CONFIG.json] [SEEDS] [OUTDIR]
#   scripts/experiments/student_search.sh noise.json "4 5 6 7" target/students   # noise.json: {"noise_max_rad": 0.2}
#
# JOBS (default 2) students train at once, about 8 minutes each on this 2-core machine. Weights,
# training logs and screens stay in OUTDIR (default target/students).
set -euo pipefail
cd "$(dirname "$0")/../.."
config=${1:-}
seeds=${2:-1 2}
out=${3:-target/students}
jobs=${JOBS:-2}
cargo build --release -q -p wogan-cli
mkdir -p "$out"
tag=$(basename "${config:-defaults}" .json)
student() {
  local seed=$1 name="$out/$tag.seed$1"
  ./target/release/wogan train-driver --seed "$seed" ${config:+--config "$config"} \
    --out "$name.bin" >"$name.train.log" 2>&1
  scripts/experiments/screen_driver.sh "$name.bin" >"$name.screen"
}
running=0
for seed in $seeds; do
  student "$seed" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then
    wait -n
    running=$((running - 1))
  fi
done
wait
for seed in $seeds; do
  name="$out/$tag.seed$seed"
  printf 'seed %-4s %s | near the edge untouched %s | %s\n' "$seed" "$(head -1 "$name.screen")" \
    "$(grep 'untouched' "$name.screen" | awk '{print $(NF-1), $NF}')" \
    "$(grep -o 'deciles:.*' "$name.screen" | awk '{print "fitness_distance p90 " $(NF-1) ", max " $NF}')"
done
