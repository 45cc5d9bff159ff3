#!/usr/bin/env bash
# Runs under the SBST 2022 competition's budgets (1 h generation, 2 h simulated execution by
# default), exports each the competition's way, and reports the groups with the competition's
# measures.
#
#   scripts/runs/sbst_budget_runs.sh [ORACLE] [SEEDS] [GENERATION] [EXECUTION]
#   scripts/runs/sbst_budget_runs.sh beamng-ai-proxy "$(seq -s ' ' 1 20)" 1h 2h
#
# ALGORITHMS chooses the algorithms (default "wogan random"; "preset-sbst" is WOGAN with
# `--preset sbst`, "preset-sbst-any-road" the same with `--min-road-turn 0`, "preset-sbst-remakes"
# the same with failures' remakes, scripts/runs/configs/remakes.json). Runs go to target/sbst/ as
# ORACLE.ALGORITHM.SEED.jsonl, exports to target/sbst/export/ORACLE.ALGORITHM.SEED/, the report to
# target/sbst/report-ORACLE/. With REUSE=1 a run whose file ends with its summary is kept. With
# EXPORT=0 the runs are not exported (scripts/results/ reads only the run files; a long run's
# export can take longer than the run).
# WOGAN=path uses another binary (default target/release/wogan, built here).
set -euo pipefail
cd "$(dirname "$0")/../.."
oracle=${1:-beamng-ai-proxy}
seeds=${2:-1 2 3 4 5}
generation=${3:-1h}
execution=${4:-2h}
algorithms=${ALGORITHMS:-wogan random}
if [ -z "${WOGAN:-}" ]; then
  cargo build --release -q -p wogan-cli
  WOGAN=target/release/wogan
fi
out=target/sbst
mkdir -p "$out/export"
for algorithm in $algorithms; do
  for seed in $seeds; do
    file="$out/$oracle.$algorithm.$seed.jsonl"
    if [ "${REUSE:-0}" = 1 ] && [ -f "$file" ] && tail -n 1 "$file" | grep -q '"type":"summary"'; then
      continue
    fi
    case "$algorithm" in
      preset-sbst-any-road) search=(--algorithm wogan --preset sbst --min-road-turn 0) ;;
      preset-sbst-remakes) search=(--algorithm wogan --preset sbst --config scripts/runs/configs/remakes.json) ;;
      preset-*) search=(--algorithm wogan --preset "${algorithm#preset-}") ;;
      *) search=(--algorithm "$algorithm") ;;
    esac
    "$WOGAN" run --quiet --oracle "$oracle" "${search[@]}" --seed "$seed" \
      --generation-budget "$generation" --execution-budget "$execution" --out "$file"
    if [ "${EXPORT:-1}" != 0 ]; then
      "$WOGAN" export --force --format sbst "$file" "$out/export/$oracle.$algorithm.$seed" \
        2> >(grep -v '^wogan export: wrote' >&2)
    fi
    echo "$oracle $algorithm seed $seed: $(tail -n 1 "$file" | cut -c1-160)"
  done
done
set -- $algorithms
if [ $# -ge 2 ]; then
  "$WOGAN" report "$out/$oracle.$1".*.jsonl --vs "$out/$oracle.$2".*.jsonl --out "$out/report-$oracle"
else
  "$WOGAN" report "$out/$oracle.$1".*.jsonl --out "$out/report-$oracle"
fi
