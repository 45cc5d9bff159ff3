"""What every section shares: the settings (from the command line, through the environment), the
Markdown being written, and reading run files and `wogan report` tables.
"""

import json
import os
import statistics
import subprocess
import sys


WOGAN = os.environ["WOGAN"]
SEEDS = os.environ["SEEDS"].split()
ORACLES = os.environ["ORACLES"].split()
# Every driver the page has sections for (ORACLES narrows which are regenerated).
ALL_ORACLES = ("beamng-ai-proxy", "dave2-proxy")
WORK = os.environ["WORK"]
# The search settings, as scripts/runs/search_figures.sh names and makes them: TAG ALGORITHM.
# (The options of each are read back from the run headers, so this list cannot drift silently.)
SETTINGS = [
    setting.split(":")
    for setting in (
        "paper:wogan distance:wogan distance-matched:wogan mutants:wogan decay995:wogan jobs2:wogan "
        "jobs4:wogan jobs2-continue:wogan jobs4-continue:wogan random:random"
    ).split()
]
lines = []  # the Markdown being written


def out(text=""):
    lines.append(text)


def sh(*cmd):
    """Output of a short command, '' when it fails: the stamp must not stop the script."""
    try:
        return subprocess.run(cmd, capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return ""


def median(values):
    return statistics.median(values) if values else None


def num(x, digits=1):
    """A figure as people write it: no trailing zeros, '–' when there is nothing to show."""
    if x is None:
        return "–"
    text = f"{x:,.{digits}f}"
    return text.rstrip("0").rstrip(".") if "." in text else text


def read_jsonl(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


# ---------------------------------------------------------------------------------------------
# The stamp: figures are only comparable on the same machine, and a busy machine is slower, so
# the load average goes with them.
def machine():
    cpu = "unknown CPU"
    mem = "unknown memory"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
        for line in open("/proc/meminfo"):
            if line.startswith("MemTotal"):
                mem = f"{int(line.split()[1]) / 1024 / 1024:.1f} GiB"
                break
        load = open("/proc/loadavg").read().split()[:3]
    except OSError:
        load = ["?"] * 3
    return {
        "date": sh("date", "-u", "+%Y-%m-%d %H:%M UTC"),
        "uname": sh("uname", "-srm"),
        "cores": sh("nproc"),
        "cpu": cpu,
        "mem": mem,
        "load": " / ".join(load),
        "commit": sh("git", "rev-parse", "--short", "HEAD") or "unknown",
        "dirty": bool(sh("git", "status", "--porcelain", "--untracked-files=no")),
        "wogan": sh(WOGAN, "--version"),
    }


# ---------------------------------------------------------------------------------------------
# The tables of run files are `wogan report --table`'s own: this page and a report cannot disagree.
def report_table(*args):
    """The Markdown tables `wogan report ARGS --table` prints; its stderr names bad run files."""
    done = subprocess.run([WOGAN, "report", *args, "--table"], capture_output=True, text=True)
    if done.returncode not in (0, 1):
        sys.exit(f"results: wogan report {' '.join(args)} --table failed: {done.stderr.strip()}")
    for line in done.stderr.splitlines():
        print(f"results: {line}", file=sys.stderr)
    return done.stdout.rstrip("\n").split("\n")


def run_files(oracle, tag, algorithm):
    if tag == "stgem":
        paths = [f"target/stgem/{oracle}.stgem.{s}.jsonl" for s in SEEDS]
    else:
        paths = [f"target/effectiveness/{oracle}.{tag}.{algorithm}.{s}.jsonl" for s in SEEDS]
    return [p for p in paths if os.path.exists(p)]


def split(text_lines, marker):
    """The lines before the first heading starting with `marker`, and each such heading's block."""
    head, blocks, current = [], [], None
    for line in text_lines:
        if line.startswith(marker):
            current = [line]
            blocks.append(current)
        elif current is None:
            head.append(line)
        else:
            current.append(line)
    return head, blocks
