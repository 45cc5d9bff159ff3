#!/usr/bin/env bash
# How often a driver fails on the road families it is calibrated on: WOGAN's 75 m random roads
# (the 300 reference roads, and 1,500 more from our own sampler, seeds 1-5, for a rate that one
# road does not move by 0.3 points), the SBST 2022 entries' long roads (the 900-road dev set:
# FreneticV, AmbieGen and the pipeline's random generator) and long random roads of our own (the
# paper's sampler with 12 curvature values, 180 m, seeds 1-2, 300 roads each).
#
#   scripts/runs/driver_rates.sh                                  # beamng-ai-proxy at its defaults
#   scripts/runs/driver_rates.sh dave2-proxy
#   scripts/runs/driver_rates.sh beamng-ai-proxy candidate.json   # a `--config` file: {"driver": {...}}
#   scripts/runs/driver_rates.sh dave2-proxy "" student.bin       # weights from `wogan train-driver`
#
# Prints one line per road family: failures / roads and the rate. beamng-ai-proxy takes about
# 10 s on two cores, dave2-proxy about 10 minutes; to screen a candidate faster, DEV_ROADS=N
# drives the first N roads of the dev set only, LONG_SEEDS="1" one set of long random roads and
# SHORT_SEEDS="" none of our own 75 m roads.
set -euo pipefail
cd "$(dirname "$0")/../.."
oracle=${1:-beamng-ai-proxy}
config=${2:-}
weights=${3:-}
wogan=${WOGAN:-target/release/wogan}
[ -n "${WOGAN:-}" ] || cargo build --release -q -p wogan-cli
dev=tests/reference/peer_roads_dev.jsonl
options=(--oracle "$oracle" ${config:+--config "$config"} ${weights:+--driver-weights "$weights"})
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
rate() { # LABEL FAILED TOTAL
  awk -v l="$1" -v f="$2" -v n="$3" 'BEGIN { printf "%-36s %4d / %4d  %5.1f%%\n", l, f, n, 100 * f / n }'
}
"$wogan" simulate "${options[@]}" --jobs 2 tests/reference/roads.jsonl >"$work/wogan75"
rate "WOGAN 75 m random roads (300)" "$(grep -c '"outcome":"FAIL"' "$work/wogan75" || true)" 300
random_runs() { # LABEL CURVATURE-POINTS SEEDS: `wogan run --algorithm random`, 300 roads a seed
  local seed failed roads
  [ -n "$3" ] || return 0
  roads=$(( 300 * $(echo "$3" | wc -w) ))
  for seed in $3; do
    "$wogan" run --quiet "${options[@]}" --algorithm random --curvature-points "$2" \
      --max-tests 300 --seed "$seed" --jobs 2 --out "$work/random.$2.$seed"
  done
  failed=$(cat "$work"/random."$2".* | grep '"type":"summary"' | grep -o '"failed":[0-9]*' |
    cut -d: -f2 | paste -sd+ | bc)
  rate "$1 ($roads)" "$failed" "$roads"
}
random_runs "WOGAN 75 m random roads, own" 5 "${SHORT_SEEDS-1 2 3 4 5}"
head -n "${DEV_ROADS:-900}" "$dev" >"$work/dev_roads"
"$wogan" simulate "${options[@]}" --jobs 2 "$work/dev_roads" >"$work/dev"
grep -o '"generator": *"[a-z_]*"' "$work/dev_roads" | cut -d'"' -f4 >"$work/generators"
grep -o '"outcome":"[A-Z]*"' "$work/dev" | cut -d'"' -f4 | paste "$work/generators" - |
  awk '{ n[$1]++; if ($2 == "FAIL") f[$1]++ }
       END { for (g in n) printf "%s %d %d\n", g, f[g], n[g] }' | sort |
  while read -r generator failed total; do rate "dev set, $generator" "$failed" "$total"; done
random_runs "long random roads, 180 m" 12 "${LONG_SEEDS:-1 2}"
