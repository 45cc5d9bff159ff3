#!/usr/bin/env bash
# The saved generator's figure (issue 35): per driver and seed, a 300-test WOGAN run saves its
# generator; 50 tests chosen with that generator (`wogan run --generator`, the roads `wogan sample`
# draws with the same seed) are compared with 50 random tests of the same seed, by
# `wogan report SAMPLED --vs RANDOM --table` (failures, diversity, Mann–Whitney).
#
#   scripts/runs/generator_figures.sh                       # both drivers, seeds 1-20
#   ORACLES=dave2-proxy SEEDS="1 2 3" scripts/runs/generator_figures.sh
#
# Files: target/generator/ORACLE.{train,sampled,random}.SEED.jsonl, ORACLE.train.SEED.json (the
# generator); complete files are reused. Tables: target/generator/ORACLE.table.md.
set -euo pipefail
cd "$(dirname "$0")/../.."
wogan=${WOGAN:-target/release/wogan}
seeds=${SEEDS:-$(seq -s ' ' 1 20)}
oracles=${ORACLES:-beamng-ai-proxy dave2-proxy}
dir=target/generator
mkdir -p "$dir"
complete() { [ -s "$1" ] && tail -n 1 "$1" | grep -q '"type":"summary"'; }
for oracle in $oracles; do
  for seed in $seeds; do
    train=$dir/$oracle.train.$seed
    if ! complete "$train.jsonl" || [ ! -s "$train.json" ]; then
      "$wogan" run --oracle "$oracle" --seed "$seed" --max-tests 300 --quiet \
        --out "$train.jsonl" --save-generator "$train.json"
    fi
    complete "$dir/$oracle.sampled.$seed.jsonl" ||
      "$wogan" run --oracle "$oracle" --seed "$seed" --max-tests 50 --quiet \
        --generator "$train.json" --out "$dir/$oracle.sampled.$seed.jsonl"
    complete "$dir/$oracle.random.$seed.jsonl" ||
      "$wogan" run --oracle "$oracle" --seed "$seed" --max-tests 50 --quiet \
        --algorithm random --out "$dir/$oracle.random.$seed.jsonl"
  done
  sampled=() random=()
  for seed in $seeds; do
    sampled+=("$dir/$oracle.sampled.$seed.jsonl")
    random+=("$dir/$oracle.random.$seed.jsonl")
  done
  "$wogan" report "${sampled[@]}" --vs "${random[@]}" --table > "$dir/$oracle.table.md"
  echo "== $oracle: 50 tests from the saved generator (A) against 50 random tests (B)"
  grep -E '^\| (measure|failures per run|diversity) ' "$dir/$oracle.table.md"
done
