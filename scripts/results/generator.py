"""Section `generator`: roads sampled from a saved generator against random roads
(made by scripts/runs/generator_figures.sh).
"""

import os

from common import ORACLES, SEEDS, out, report_table


# ---------------------------------------------------------------------------------------------
# The saved generator (issue 35): 50 tests chosen with the generator of a 300-test run against 50
# random tests of the same seed, per driver (scripts/runs/generator_figures.sh).
def generator_section():
    out()
    out("## Sampling from a saved generator")
    out()
    out("Per seed (1–20) and driver, a 300-test WOGAN run at the paper's settings saves its "
        "generator (`--save-generator`); 50 tests chosen with it (`wogan run --generator`, the "
        "roads `wogan sample` draws with the same seed, without training) are compared with 50 "
        "random tests of the same seed by `wogan report SAMPLED --vs RANDOM --table` (A: sampled, "
        "B: random). Runs: `scripts/runs/generator_figures.sh`.")
    for oracle in ORACLES:
        sampled = [f"target/generator/{oracle}.sampled.{s}.jsonl" for s in SEEDS]
        random = [f"target/generator/{oracle}.random.{s}.jsonl" for s in SEEDS]
        sampled = [p for p in sampled if os.path.exists(p)]
        random = [p for p in random if os.path.exists(p)]
        out()
        out(f"### {oracle}")
        out()
        if not sampled or not random:
            out(f"Runs missing: `ORACLES={oracle} scripts/runs/generator_figures.sh`.")
            continue
        rows = report_table(*sampled, "--vs", *random)
        keep = ("| failures per run ", "| diversity ", "| closest approach", "| first failing test")
        for line in rows:
            if not line.startswith("| ") or line.startswith(("| measure ",) + keep):
                out(line)
