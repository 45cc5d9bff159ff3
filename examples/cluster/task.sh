#!/usr/bin/env bash
# One task of a wogan campaign, and which tasks are left. The GNU parallel and Slurm recipes
# (parallel/campaign.sh, slurm/campaign.sbatch) both run tasks through it.
#
#   task.sh run DIR 'NAME SEED [wogan run options...]'   # one task: DIR/NAME.SEED.jsonl
#   task.sh pending TASKS DIR                             # the task lines whose run is not finished
#   task.sh finished FILE                                 # exit 0 when FILE holds a finished run
#
# A task line is NAME, SEED and options of `wogan run`, split as the shell splits words (quotes
# keep a command together: --oracle cmd:"python3 keeper.py"); blank lines and lines starting
# with # are not tasks. tasks.sh writes such lines for seeds x drivers x settings.
#
# A run is finished when its file's last line is the summary of a run that was neither
# interrupted nor failed part-way. A task writes DIR/NAME.SEED.jsonl.part and renames it to
# DIR/NAME.SEED.jsonl only when `wogan run` exits 0, so a finished name always holds a finished
# run; a task whose run is finished does nothing, so a campaign is resumed by running it again.
# `wogan report DIR` names the .part files left by tasks that failed or were stopped.
#
# WOGAN names the binary (default: wogan on PATH). A run's --jobs is one of its settings (it may
# change which tests WOGAN chooses), so it is given in the task line, never added here; a
# --max-tests run at --jobs 1, the default, is reproducible from its seed.

usage() {
  sed -n '4,6p' "$0" | sed 's/^#  */usage: /' >&2
  exit 2
}

# The task lines of a task file, comments and blank lines left out.
task_lines() {
  grep -v -e '^[[:space:]]*#' -e '^[[:space:]]*$' "$1" || true
}

finished() { # FILE
  local last
  [ -s "$1" ] || return 1
  last=$(tail -n 1 "$1")
  case $last in
    *'"type":"summary"'*) ;;
    *) return 1 ;;
  esac
  case $last in
    *'"interrupted":true'* | *'"error":'*) return 1 ;;
  esac
}

# The output file of a task line: DIR/NAME.SEED.jsonl.
output_of() { # DIR LINE
  local words
  eval "words=($2)"
  if [ "${#words[@]}" -lt 2 ] || ! [[ ${words[1]} =~ ^[0-9]+$ ]]; then
    echo "task.sh: not a task line (NAME SEED [options...]): $2" >&2
    return 2
  fi
  echo "$1/${words[0]}.${words[1]}.jsonl"
}

run_task() { # DIR LINE
  # Also run as an exported function (parallel/campaign.sh), without `set -e`: every step checked.
  local dir=$1 line=$2 out words
  out=$(output_of "$dir" "$line") || return 2
  if finished "$out"; then
    echo "task.sh: $out is finished; skipped" >&2
    return 0
  fi
  eval "words=($line)" || return 2
  mkdir -p "$(dirname "$out")" || return 2
  # `wogan run` writes its records as it goes; the name says finished only once it exited 0.
  "${WOGAN:-wogan}" run --quiet "${words[@]:2}" --seed "${words[1]}" --out "$out.part" || return
  mv -f "$out.part" "$out"
}

pending() { # TASKS DIR
  local line
  while IFS= read -r line; do
    finished "$(output_of "$2" "$line")" || printf '%s\n' "$line"
  done < <(task_lines "$1")
}

# Sourced (by parallel/campaign.sh, for its functions), it stops here.
if [[ ${BASH_SOURCE[0]} == "$0" ]]; then
  set -euo pipefail
  [ $# -ge 1 ] || usage
  command=$1
  shift
  case $command in
    run) [ $# -eq 2 ] || usage; run_task "$@" ;;
    pending) [ $# -eq 2 ] || usage; pending "$@" ;;
    finished) [ $# -eq 1 ] || usage; finished "$1" ;;
    *) usage ;;
  esac
fi
