#!/usr/bin/env bash
# Submits the unfinished tasks of a task list as one Slurm job array of campaign.sbatch.
#
#   submit.sh TASKS DIR [sbatch options...]     # MAX_RUNNING (default 20): array tasks at once
#
# The unfinished tasks are written to DIR/pending.HASH.txt (named by its content, so a
# resubmission while an earlier array still runs never changes the list that array reads) and
# the array is 1-N%MAX_RUNNING. Run it again to resume: finished runs are not in the new list.
set -euo pipefail
if [ $# -lt 2 ]; then
  echo "usage: submit.sh TASKS DIR [sbatch options...]" >&2
  exit 2
fi
tasks=$1 dir=$2
shift 2
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$dir"
dir=$(cd "$dir" && pwd) # the array's tasks run from the checkout's root
todo=$("$here/../task.sh" pending "$tasks" "$dir")
if [ -z "$todo" ]; then
  echo "submit.sh: every task of $tasks is finished in $dir" >&2
  exit 0
fi
hash=$(printf '%s\n' "$todo" | sha1sum | cut -c1-12)
pending="$dir/pending.$hash.txt"
printf '%s\n' "$todo" > "$pending"
count=$(grep -c '' "$pending")
# Submitted from the checkout's root, where campaign.sbatch finds task.sh.
cd "$here/../../.."
exec sbatch --array="1-$count%${MAX_RUNNING:-20}" "$@" \
  examples/cluster/slurm/campaign.sbatch "$pending" "$dir"
