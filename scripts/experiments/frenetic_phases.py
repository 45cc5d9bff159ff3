"""Where Frenetic (2021)'s failures come from: its random phase, each mutation, its crossover.

Dev-time (docs/experiments/2026-11-28-frenetic-2021-whole-budget.md). Frenetic logs what made
each test before the pipeline logs the test's outcome (run.log: "Random generation", "Mutation
function: NAME", "Entering crossover phase."; crossover children have no line of their own), so
each test.NNNN.json of a run (scripts/peers/campaign.sh) is labelled by the operator that made
it. The distinct failures of a subset of a run are `wogan report`'s: the subset's test files are
linked into a scratch folder with the run's summary, and the subset reported as a run.

    python3 scripts/experiments/frenetic_phases.py [--wogan target/release/wogan] target/peers/beamng-ai-proxy.frenetic2021.*

Prints, per operator, the mean tests and failures per run, and the mean distinct failures of the
random phase alone, of the random phase with each operator's tests added, and of the whole run.
"""
import argparse
import glob
import os
import re
import shutil
import statistics
import subprocess
import tempfile

RANDOM = "random"
CROSSOVER = "crossover"


def operators(run_log):
    """The operator of each test, in test order, from a Frenetic run.log."""
    labels, pending, crossing = [], None, False
    with open(run_log) as f:
        for line in f:
            if "Random generation." in line or "There is no good candidate" in line:
                pending, crossing = RANDOM, False
            elif "Mutation function: " in line:
                pending, crossing = line.split("Mutation function: ", 1)[1].strip(), False
            elif "Entering crossover phase." in line:
                pending, crossing = None, True
            elif re.search(r"INFO\s+test_outcome ", line):
                labels.append(pending or (CROSSOVER if crossing else "?"))
                pending = None
    return labels


def outcome(test_file):
    with open(test_file) as f:
        text = f.read()
    match = re.search(r'"test_outcome":\s*"(\w+)"', text)
    return match.group(1) if match else "INVALID"


def distinct(wogan, run, tests, scratch):
    """`wogan report`'s distinct failures of the run's `tests` (test files)."""
    folder = os.path.join(scratch, f"subset{len(os.listdir(scratch))}")
    os.makedirs(folder)
    shutil.copy(os.path.join(run, "summary.json"), folder)
    for test in tests:
        os.symlink(os.path.abspath(test), os.path.join(folder, os.path.basename(test)))
    done = subprocess.run([wogan, "report", folder, "--table"], capture_output=True, text=True)
    row = next(line for line in done.stdout.splitlines() if line.startswith("| sbst:"))
    cell = row.strip("|").split("|")[3].strip()  # "median (mean)" of one run
    return float(cell.split(" ")[0])


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--wogan", default="target/release/wogan")
    p.add_argument("runs", nargs="+", help="result folders of Frenetic (2021) runs")
    args = p.parse_args()
    per_run = []
    with tempfile.TemporaryDirectory() as scratch:
        for run in filter(os.path.isdir, args.runs):  # a glob also names the campaign's .log files
            tests = sorted(glob.glob(os.path.join(run, "test.*.json")))
            labels = operators(os.path.join(run, "run.log"))
            if len(labels) != len(tests):
                raise SystemExit(f"{run}: {len(labels)} outcomes in run.log, {len(tests)} test files")
            by = {}
            for test, label in zip(tests, labels):
                by.setdefault(label, []).append(test)
            random_tests = by.get(RANDOM, [])
            figures = {"whole": distinct(args.wogan, run, tests, scratch),
                       "random phase": distinct(args.wogan, run, random_tests, scratch)}
            for label, chosen in by.items():
                if label != RANDOM:
                    chosen_set = set(chosen) | set(random_tests)
                    figures[f"random + {label}"] = distinct(
                        args.wogan, run, [t for t in tests if t in chosen_set], scratch)
            outcomes = {t: outcome(t) for t in tests}  # each test file read once
            counts = {label: (sum(outcomes[t] != "INVALID" for t in chosen),
                              sum(outcomes[t] == "FAIL" for t in chosen))
                      for label, chosen in by.items()}
            per_run.append((figures, counts))
    n = len(per_run)
    if not n:
        raise SystemExit("frenetic_phases.py: no result folder given")
    labels = sorted({label for _, counts in per_run for label in counts})
    print(f"{n} runs; means per run")
    print()
    print("| operator | valid tests | failures |")
    print("|---|---|---|")
    for label in labels:
        valid = statistics.mean(c.get(label, (0, 0))[0] for _, c in per_run)
        failed = statistics.mean(c.get(label, (0, 0))[1] for _, c in per_run)
        print(f"| {label} | {valid:.1f} | {failed:.1f} |")
    print()
    print("| tests | distinct failures |")
    print("|---|---|")
    names = ["random phase"] + [f"random + {label}" for label in labels if label != RANDOM] + ["whole"]
    for name in names:
        values = [f.get(name, f["random phase"]) for f, _ in per_run]
        print(f"| {name} | {statistics.mean(values):.1f} |")


if __name__ == "__main__":
    main()
