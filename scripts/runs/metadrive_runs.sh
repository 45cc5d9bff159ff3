#!/usr/bin/env bash
# Searches against MetaDrive (examples/metadrive/, after its setup.sh) under the SBST
# competition's budgets: one run per policy x algorithm x seed, into
# target/metadrive/POLICY.ALGORITHM.SEED.jsonl, which scripts/results/ reads ("A real simulator:
# MetaDrive").
#
#   scripts/runs/metadrive_runs.sh [POLICY] [SEEDS] [GENERATION] [EXECUTION]
#   scripts/runs/metadrive_runs.sh idm "$(seq -s ' ' 1 10)" 1h 2h
#
# ALGORITHMS (default "random wogan preset-sbst"): random search, the paper's WOGAN, `--preset
# sbst`; "jobs2-ALGORITHM" runs ALGORITHM with `--jobs 2` (two MetaDrive executors),
# "distance-ALGORITHM" with `--fitness distance` (the lane distance the executor answers with).
# The driver's conditions are wogan's defaults (0.85 tolerance, 70 km/h), sent to the executor in
# `hello`; SPEED_LIMIT=46 drives at 46 km/h instead, where IDM is calibrated (fails 8-20% of the
# SBST 2022 entries' roads: examples/metadrive/README.md). A run
# whose file ends with its summary is kept (delete it to make it again), unless a signal cut it
# short. WOGAN=path uses another binary (default target/release/wogan, built here). OUT=folder
# writes there instead (the `--jobs 2` speed-up is measured in target/metadrive-speed/, with
# nothing else running).
set -euo pipefail
cd "$(dirname "$0")/../.."
policy=${1:-idm}
seeds=${2:-1 2 3}
generation=${3:-1h}
execution=${4:-2h}
algorithms=${ALGORITHMS:-random wogan preset-sbst}
python=target/metadrive-venv/bin/python
[ -x "$python" ] || { echo "metadrive_runs.sh: no $python: run examples/metadrive/setup.sh" >&2; exit 2; }
if [ -z "${WOGAN:-}" ]; then
  cargo build --release -q -p wogan-cli
  WOGAN=target/release/wogan
fi
out=${OUT:-target/metadrive}
mkdir -p "$out"
for algorithm in $algorithms; do
  jobs=1 search=$algorithm fitness=()
  case "$search" in
    jobs2-*) jobs=2 search=${search#jobs2-} ;;
  esac
  case "$search" in
    distance-*) fitness=(--fitness distance) search=${search#distance-} ;;
  esac
  case "$search" in
    preset-*) options=(--algorithm wogan --preset "${search#preset-}" "${fitness[@]}") ;;
    *) options=(--algorithm "$search" "${fitness[@]}") ;;
  esac
  for seed in $seeds; do
    file="$out/$policy.$algorithm.$seed.jsonl"
    # A run that ended with its summary is kept, unless a signal cut it short.
    if [ -f "$file" ] && tail -n 1 "$file" | grep '"type":"summary"' | grep -vq '"interrupted":true'; then
      continue
    fi
    "$WOGAN" run --quiet "${options[@]}" ${SPEED_LIMIT:+--speed-limit "$SPEED_LIMIT"} --jobs "$jobs" --seed "$seed" \
      --generation-budget "$generation" --execution-budget "$execution" \
      --executor "cmd:$python examples/metadrive/executor.py --policy $policy" --out "$file" \
      2> "$file.stderr" || echo "metadrive_runs.sh: $file: wogan exited $? (see $file.stderr)" >&2
    echo "$policy $algorithm seed $seed: $(tail -n 1 "$file" | cut -c1-160)"
  done
done
