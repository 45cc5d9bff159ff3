#!/usr/bin/env bash
# WOGAN against random search, as the paper compares them: failing roads and their diversity
# after N executions, for several seeds, and the medians.
#
#   scripts/runs/effectiveness.sh [ORACLE] [TESTS] [SEEDS] [extra wogan run options...]
#   scripts/runs/effectiveness.sh beamng-ai-proxy 300 "1 2 3 4 5"
#   ALGORITHMS=wogan TAG=bolp scripts/runs/effectiveness.sh dave2-proxy 300 "1 2 3 4 5" --fitness bolp
#
# ALGORITHMS chooses the algorithms (default "random wogan"); TAG names the set of runs. Runs are
# kept in target/effectiveness/ for `wogan report`; with REUSE=1 a run whose file already ends
# with its summary is not run again (so an interrupted set of runs can be resumed).
set -euo pipefail
cd "$(dirname "$0")/../.."
oracle=${1:-beamng-ai-proxy}
tests=${2:-300}
seeds=${3:-1 2 3 4 5}
shift $(( $# < 3 ? $# : 3 ))
cargo build --release -q -p wogan-cli
out=target/effectiveness
algorithms=${ALGORITHMS:-random wogan}
tag=${TAG:+.$TAG}
mkdir -p "$out"
field() { grep '"type":"summary"' "$1" | grep -o "\"$2\":[^,}]*" | cut -d: -f2; }
# A run without failures has no diversity (null); it counts as 0.
diversity_of() { field "$1" diversity | sed 's/null/0/'; }
# Median and mean: outcomes are bimodal (a run that reaches the failure boundary early exploits
# it), so the two can tell different stories.
median() { sort -g | awk '{v[NR]=$1; s+=$1} END {m = NR%2 ? v[(NR+1)/2] : (v[NR/2]+v[NR/2+1])/2; print m " (mean " s/NR ")"}'; }
printf '%-6s %-8s %8s %10s %8s\n' seed algo failed diversity wall_s
for algorithm in $algorithms; do
  for seed in $seeds; do
    file="$out/$oracle$tag.$algorithm.$seed.jsonl"
    if [ "${REUSE:-0}" = 1 ] && [ -f "$file" ] && tail -n 1 "$file" | grep -q '"type":"summary"'; then
      :
    else
      ./target/release/wogan run --quiet --oracle "$oracle" --algorithm "$algorithm" \
        --max-tests "$tests" --seed "$seed" "$@" --out "$file"
    fi
    printf '%-6s %-8s %8s %10.3f %8.1f\n' "$seed" "$algorithm" "$(field "$file" failed)" \
      "$(diversity_of "$file")" "$(field "$file" wall_s)"
  done
done
for algorithm in $algorithms; do
  failed=$(for seed in $seeds; do field "$out/$oracle$tag.$algorithm.$seed.jsonl" failed; done | median)
  diversity=$(for seed in $seeds; do diversity_of "$out/$oracle$tag.$algorithm.$seed.jsonl"; done | median)
  echo "median failures, $algorithm: $failed; median diversity: $diversity"
done
