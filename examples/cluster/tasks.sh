#!/usr/bin/env bash
# A campaign's task list: every setting x driver x seed, one task line each (NAME SEED options),
# for task.sh, parallel/campaign.sh and slurm/campaign.sbatch.
#
#   SEEDS="$(seq 1 20)" ORACLES="beamng-ai-proxy dave2-proxy" tasks.sh settings.txt > tasks.txt
#
# settings.txt holds one setting a line: its name and its `wogan run` options, e.g.
#   paper.wogan   --fitness bolp --target-decay 0.95 --mutation-share 0 --max-tests 300
#   random.random --algorithm random --max-tests 300
# (blank lines and lines starting with # are skipped). Each task is named ORACLE.SETTING and
# writes DIR/ORACLE.SETTING.SEED.jsonl, so `wogan report DIR` groups the runs by their headers and
# file names say which task made which run. SEEDS defaults to 1-10, ORACLES to beamng-ai-proxy.
set -euo pipefail
if [ $# -ne 1 ]; then
  echo "usage: SEEDS=\"1 2 3\" ORACLES=\"beamng-ai-proxy dave2-proxy\" tasks.sh SETTINGS_FILE" >&2
  exit 2
fi
seeds=${SEEDS:-$(seq 1 10)}
oracles=${ORACLES:-beamng-ai-proxy}
lines=0
while read -r name options; do
  case $name in '' | '#'*) continue ;; esac
  for oracle in $oracles; do
    for seed in $seeds; do
      printf '%s.%s %s --oracle %s %s\n' "$oracle" "$name" "$seed" "$oracle" "$options"
      lines=$((lines + 1))
    done
  done
done < "$1"
[ "$lines" -gt 0 ] || { echo "tasks.sh: $1 holds no setting" >&2; exit 2; }
