#!/usr/bin/env bash
# The search figures: each configuration over seeds 1-20 on both drivers (300 tests each), then
# the comparisons that decide the defaults, each with `wogan report --vs` (Mann–Whitney).
#
#   scripts/runs/search_figures.sh            # everything (about 2.5 h on one core; dave2-proxy dominates)
#   ORACLES=dave2-proxy SETS="paper distance" scripts/runs/search_figures.sh
#
# Runs are kept (and reused when complete) in target/effectiveness/; each comparison's report in
# target/figures/NAME/report.md. stgem's own runs, when present (scripts/reference/stgem_search.py
# writes target/stgem/ORACLE.stgem.SEED.jsonl), are compared with the paper's settings.
set -euo pipefail
cd "$(dirname "$0")/../.."
export REUSE=1
seeds=${SEEDS:-$(seq -s ' ' 1 20)}
oracles=${ORACLES:-beamng-ai-proxy dave2-proxy}
runs=target/effectiveness
figures=target/figures
paper=(--fitness bolp --target-decay 0.95 --mutation-share 0)

configure() { # TAG ORACLE ALGORITHM OPTIONS...
  local tag=$1 oracle=$2 algorithm=$3
  shift 3
  echo "== $oracle / $tag"
  ALGORITHMS=$algorithm TAG=$tag scripts/runs/effectiveness.sh "$oracle" 300 "$seeds" "$@" | tail -n 1
}
files() { for s in $seeds; do echo "$runs/$1.$s.jsonl"; done; }
compare() { # NAME GROUP_A GROUP_B (file stems: ORACLE.TAG.ALGORITHM)
  local dir="$figures/$1"
  mkdir -p "$dir"
  # shellcheck disable=SC2046
  ./target/release/wogan report $(files "$2") --vs $(files "$3") --out "$dir" >/dev/null
  echo "== $1: $2 vs $3"
  comparison "$dir/report.md"
}
comparison() { # the Mann–Whitney rows of a report's comparison
  awk '/^## / {on = /^## Comparison/} on && /^\| (failures per run|diversity) \|/' "$1"
}

# Each set: a tag, the algorithm, its options; SETS picks some (default all, in this order).
declare -A options=(
  [paper]="wogan ${paper[*]}"
  [distance]="wogan --fitness distance --target-decay 0.95 --mutation-share 0"
  [distance-matched]="wogan --fitness distance --mutation-share 0"
  [random]="random"
  [mutants]="wogan --fitness bolp --target-decay 0.95 --mutation-share 0.25"
  [decay995]="wogan --fitness bolp --target-decay 0.995 --mutation-share 0"
  [jobs2]="wogan ${paper[*]} --jobs 2"
  [jobs4]="wogan ${paper[*]} --jobs 4"
  [jobs2-continue]="wogan ${paper[*]} --jobs 2 --round-acceptance continue"
  [jobs4-continue]="wogan ${paper[*]} --jobs 4 --round-acceptance continue"
)
sets=${SETS:-paper distance distance-matched random mutants decay995 jobs2 jobs4 jobs2-continue jobs4-continue}
comparisons=(
  "paper-vs-random paper.wogan random.random"
  "distance-vs-bolp distance.wogan paper.wogan"
  "matched-vs-distance distance-matched.wogan distance.wogan"
  "mutants-vs-paper mutants.wogan paper.wogan"
  "decay995-vs-paper decay995.wogan paper.wogan"
  "jobs2-vs-paper jobs2.wogan paper.wogan"
  "jobs4-vs-paper jobs4.wogan paper.wogan"
  "jobs2continue-vs-paper jobs2-continue.wogan paper.wogan"
  "jobs4continue-vs-paper jobs4-continue.wogan paper.wogan"
)
done_set() { [ -f "$runs/$1.$(echo "$seeds" | awk '{print $NF}').jsonl" ]; }

for oracle in $oracles; do
  for set in $sets; do
    # shellcheck disable=SC2086
    configure "$set" "$oracle" ${options[$set]}
  done
  for c in "${comparisons[@]}"; do
    read -r name a b <<<"$c"
    if done_set "$oracle.$a" && done_set "$oracle.$b"; then
      compare "$oracle-$name" "$oracle.$a" "$oracle.$b"
    fi
  done
  if [ -f "target/stgem/$oracle.stgem.1.jsonl" ]; then
    mkdir -p "$figures/$oracle-paper-vs-stgem"
    # shellcheck disable=SC2046
    ./target/release/wogan report $(files "$oracle.paper.wogan") \
      --vs $(for s in $seeds; do echo "target/stgem/$oracle.stgem.$s.jsonl"; done) \
      --out "$figures/$oracle-paper-vs-stgem" >/dev/null
    echo "== $oracle-paper-vs-stgem"
    comparison "$figures/$oracle-paper-vs-stgem/report.md"
  fi
done
