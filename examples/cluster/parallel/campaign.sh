#!/usr/bin/env bash
# A wogan campaign with GNU parallel: each unfinished task of a task list (../tasks.sh, ../task.sh)
# as one `wogan run`, on this machine or on ssh hosts, then resumable by running it again.
#
#   campaign.sh TASKS DIR [parallel options...]
#   campaign.sh tasks.txt results --jobs 2                         # here, two runs at a time
#   campaign.sh tasks.txt /shared/results --sshloginfile hosts     # hosts that share DIR
#   TRANSFER=1 campaign.sh tasks.txt results --sshloginfile hosts  # hosts that share nothing
#
# Each task writes DIR/NAME.SEED.jsonl (through a .part file, renamed when the run ends well).
# parallel's --jobs is runs at once per host (default: one per core); with settings of
# `wogan run --jobs N`, give it a core count over N (--jobs 50% for N = 2).
# Tasks whose run is finished are left out before parallel starts, so running the same command
# again resumes the campaign: failed, stopped and never-started tasks run, nothing else (a joblog
# keyed by job number could not follow a list that shrinks, so --resume-failed is not used).
# DIR/joblog records the last submission's tasks: host, start, run time, exit status, command.
#
# Over ssh, every host needs bash as its login shell and `wogan` on its PATH (or WOGAN set to
# the same path everywhere), of one version: run files record theirs. The task code travels with
# each job (parallel --env), so nothing else is installed. With a shared file system, DIR is
# the same path on every host. With TRANSFER=1, DIR is relative: each job runs in its own
# temporary folder on its host, and parallel's --return brings DIR/NAME.SEED.jsonl (or .part)
# back and --cleanup removes the folder. hosts: one ssh login a line, `N/host` for N job slots
# (parallel's --sshloginfile; `:` is this machine).
set -euo pipefail
if [ $# -lt 2 ]; then
  echo "usage: campaign.sh TASKS DIR [parallel options...]" >&2
  exit 2
fi
tasks=$1 dir=$2
shift 2
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=../task.sh
source "$here/../task.sh"
command -v parallel > /dev/null || { echo "campaign.sh: GNU parallel is not installed" >&2; exit 2; }
[ -f "$tasks" ] || { echo "campaign.sh: no task list $tasks" >&2; exit 2; }
total=$(task_lines "$tasks" | wc -l)
mkdir -p "$dir"
todo=$(pending "$tasks" "$dir")
left=$(printf '%s' "$todo" | grep -c '' || true)
echo "campaign.sh: $left of $total tasks to run into $dir" >&2
transfer=()
if [ "${TRANSFER:-0}" = 1 ]; then
  case $dir in
    /*) echo "campaign.sh: with TRANSFER=1, DIR is relative (it is made on each host)" >&2; exit 2 ;;
  esac
  transfer=(--workdir ... --return "$dir" --cleanup)
fi
status=0
if [ "$left" -gt 0 ]; then
  # The functions and settings the jobs need travel with them; bash runs them.
  export -f finished output_of run_task
  export WOGAN=${WOGAN:-wogan}
  printf '%s\n' "$todo" | SHELL=$(command -v bash) parallel --will-cite \
    --env finished,output_of,run_task,WOGAN --joblog "$dir/joblog" \
    "${transfer[@]}" "$@" run_task "$dir" '{}' || status=$?
fi
left=$(pending "$tasks" "$dir" | grep -c '' || true)
echo "campaign.sh: $((total - left)) of $total tasks finished in $dir" >&2
if [ "$left" -gt 0 ]; then
  echo "campaign.sh: $left left (failed or stopped: see $dir/joblog); run the same command again to resume" >&2
  exit 1
fi
exit "$status"
