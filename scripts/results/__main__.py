"""Writes docs/results.md: every measured figure the project quotes, regenerated from run files,
the reference roads and criterion's bench output, stamped with the date and the machine. The
README states no figures; it points here.

    python3 scripts/results                          # uses target/release/wogan
    python3 scripts/results --wogan /path/to/wogan
    python3 scripts/results --make-runs              # first make the missing search runs
    python3 scripts/results --allow-missing          # write what there is; name what is missing
    python3 scripts/results --only generator,ci      # regenerate those sections in place
    python3 scripts/results --oracles dave2-proxy --only field   # ... only that driver's parts

Each option may also be given by the environment variable of its name in capitals (WOGAN, SEEDS,
ORACLES, OUT, WORK, TRAIN_LOG, ONLY, MAKE_RUNS=1, ALLOW_MISSING=1). One module per section of
the page (page.py lists them); each module says what run files it reads and which script makes
them (nothing is measured twice: each source has its own script). It runs `wogan report ...
--table`, whose tables of run files it includes as they are, and `wogan simulate` / `wogan
validate` on the reference roads (about a minute: dave2-proxy renders and infers 300 drives).

Missing run files stop it with the list and the commands that make them, unless
--allow-missing. Python 3 standard library only.
"""

import argparse
import os
import subprocess
import sys

from missing import ALL_SEEDS, how_to_make, missing_runs

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def options():
    """The command line, with the environment's variables as defaults."""
    env = os.environ.get
    parser = argparse.ArgumentParser(prog="python3 scripts/results", description=__doc__.split("\n\n")[0])
    parser.add_argument("--wogan", default=env("WOGAN", "target/release/wogan"), help="the wogan binary")
    parser.add_argument("--seeds", default=env("SEEDS", ALL_SEEDS), help="seeds of the search runs (default 1-20)")
    parser.add_argument("--oracles", default=env("ORACLES", "beamng-ai-proxy dave2-proxy"), help="drivers, space-separated")
    parser.add_argument("--out", default=env("OUT", "docs/results.md"), help="the page written")
    parser.add_argument("--work", default=env("WORK", "target/results"), help="scratch folder")
    parser.add_argument("--train-log", default=env("TRAIN_LOG", "target/results/train-driver.json"))
    parser.add_argument("--only", default=env("ONLY", ""), help="sections to regenerate in place, comma-separated")
    parser.add_argument("--make-runs", action="store_true", default=env("MAKE_RUNS") == "1",
                        help="first make the missing search runs")
    parser.add_argument("--allow-missing", action="store_true", default=env("ALLOW_MISSING") == "1",
                        help="write the page without missing runs, naming them")
    return parser.parse_args()


def main():
    args = options()
    os.chdir(ROOT)
    if not (os.path.isfile(args.wogan) and os.access(args.wogan, os.X_OK)):
        print(f"results: no wogan binary at {args.wogan}: build it (cargo build --release -p wogan-cli) or pass --wogan",
              file=sys.stderr)
        sys.exit(2)
    seeds, oracles = args.seeds.split(), args.oracles.split()
    # The sections read their settings from the environment, as given here.
    os.environ.update(WOGAN=args.wogan, SEEDS=" ".join(seeds), ORACLES=" ".join(oracles), OUT=args.out,
                      WORK=args.work, TRAIN_LOG=args.train_log, ONLY=args.only)
    import common

    missing = missing_runs(oracles, seeds, common.SETTINGS)
    # Regenerating only other sections needs none of the search runs.
    only = [name for name in args.only.split(",") if name]
    if only and not {"search", "comparisons"} & set(only):
        missing = []
    if missing and args.make_runs:
        # search_figures.sh reuses every complete run (REUSE=1) and makes the rest; stgem's runs
        # need torch and a stgem checkout, so they are only named.
        for oracle in oracles:
            sets = " ".join(line.split()[1] for line in missing if line.split()[0] == oracle and line.split()[1] != "stgem")
            if sets:
                env = dict(os.environ, ORACLES=oracle, SETS=sets, SEEDS=" ".join(seeds))
                subprocess.run(["scripts/runs/search_figures.sh"], env=env, check=True)
        missing = missing_runs(oracles, seeds, common.SETTINGS)
    if missing:
        print("results: run files missing:", *(f"  {line}" for line in missing),
              "make them with (complete runs are reused):", *how_to_make(missing, seeds),
              "or --make-runs; --allow-missing writes the results without them.", sep="\n", file=sys.stderr)
        if not args.allow_missing:
            sys.exit(1)
    os.environ["MISSING"] = "\n".join(missing)
    os.makedirs(args.work, exist_ok=True)
    os.makedirs(os.path.dirname(args.out) or ".", exist_ok=True)
    write_page()


def write_page():
    """Writes the page, or the sections asked for into it."""
    from benches import criterion
    from common import ALL_ORACLES, ORACLES, WOGAN, lines, machine, out
    from page import LOG_HEADING, page_head, sections, splice

    m = machine()
    bench = criterion()
    only = [name for name in os.environ.get("ONLY", "").split(",") if name]
    chosen = sections(bench)
    unknown = [name for name in only if name not in dict(chosen)]
    if unknown:
        sys.exit(f"results: --only names no section: {', '.join(unknown)} (sections: {', '.join(n for n, _ in chosen)})")
    if only:
        for name, write in chosen:
            if name in only:
                write()
        narrowed = set(ORACLES) != set(ALL_ORACLES)
        oracles = f" --oracles {' '.join(ORACLES)}" if narrowed else ""
        stamp = (f"- sections {', '.join(only)} regenerated on {m['date']} (commit {m['commit']}"
                 f"{' with local changes' if m['dirty'] else ''}; `python3 scripts/results"
                 f"{oracles} --only {','.join(only)}`)")
        with open(os.environ["OUT"]) as f:
            text = splice(f.read(), lines, stamp, narrowed)
        with open(os.environ["OUT"], "w") as f:
            f.write(text)
        print(f"results: regenerated {', '.join(only)} in {os.environ['OUT']}", file=sys.stderr)
        return
    for line in page_head():
        out(line)
    if os.environ.get("MISSING"):
        out("**Run files missing** (the tables below leave them out; make them as "
            "`python3 scripts/results` prints):")
        out()
        for line in os.environ["MISSING"].splitlines():
            out(f"- {line}")
        out()
    for _, write in chosen:
        write()
    out(LOG_HEADING)
    out()
    out(f"- date: {m['date']}")
    out(f"- machine: {m['uname']}, {m['cores']} cores, {m['cpu']}, {m['mem']}; load average at the start {m['load']}")
    out(f"- code: commit {m['commit']}{' with local changes' if m['dirty'] else ''}; binary `{WOGAN}` ({m['wogan']})")
    out("- regenerate: `python3 scripts/results` (after `cargo build --release -p wogan-cli`; "
        "`--wogan PATH` chooses another binary); `python3 scripts/results --only generator,ci` "
        "regenerates those sections in place")
    with open(os.environ["OUT"], "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"results: wrote {os.environ['OUT']}", file=sys.stderr)


if __name__ == "__main__":
    main()
