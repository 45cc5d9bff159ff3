"""Section `sbst`: wogan under the SBST 2022 competition's budgets (target/sbst/, made by
scripts/runs/sbst_budget_runs.sh).
"""

import os

from common import ORACLES, SEEDS, out, report_table


# ---------------------------------------------------------------------------------------------
# Under the SBST 2022 competition's budgets (scripts/runs/sbst_budget_runs.sh: 1 h generation, 2 h
# simulated execution), with the competition's measures as `wogan report` computes them.
def sbst_section():
    out()
    out("## Under the SBST competition's budgets")
    out()
    out("WOGAN (the paper's settings, A) and random search (B) with `--generation-budget 1h "
        "--execution-budget 2h`, seeds 1–20 (fewer where a table says so), as "
        "`wogan report WOGAN --vs RANDOM --table` gives them: every measure, the competition's as "
        "its pipeline computes them, mean (SD) over runs and the Mann–Whitney p-value. "
        "Effectiveness (valid / generated) is 1 in every run: wogan validates before it proposes, "
        "and the invalid candidates it rejected itself are counted instead. The pipeline's "
        "`OOBAnalyzer` fails a whole run when one OOB lies where its resampled road has no point "
        "within 0.5 m; its rows count only the runs it completes, and the last row gives the "
        "sparseness over the OOBs it can place in every run. Runs: "
        "`scripts/runs/sbst_budget_runs.sh ORACLE \"$(seq -s ' ' 1 20)\" 1h 2h`.")
    for oracle in ORACLES:
        out()
        out(f"### {oracle}")
        out()
        wogan = [f"target/sbst/{oracle}.wogan.{s}.jsonl" for s in SEEDS]
        random = [f"target/sbst/{oracle}.random.{s}.jsonl" for s in SEEDS]
        wogan = [p for p in wogan if os.path.exists(p)]
        random = [p for p in random if os.path.exists(p)]
        if not wogan or not random:
            out(f"Runs missing: `scripts/runs/sbst_budget_runs.sh {oracle} \"$(seq -s ' ' 1 20)\" 1h 2h`.")
            continue
        out(f"{len(wogan)} WOGAN runs, {len(random)} random runs.")
        out()
        for line in report_table(*wogan, "--vs", *random):
            out(line)
