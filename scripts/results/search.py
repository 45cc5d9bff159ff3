"""Sections `search`, `comparisons` and `rounds`: the 20-seed search figures per driver and
setting (target/effectiveness/, made by scripts/runs/search_figures.sh) and their Mann–Whitney
comparisons.
"""

from common import ORACLES, SEEDS, SETTINGS, out, report_table, run_files


# ---------------------------------------------------------------------------------------------
# The search figures: per oracle, one row per setting, over the seeds present.
def search_section():
    out("## Search: failing roads in 300 tests")
    out()
    out("Each row: one setting (its configuration as the run headers give it; stgem's WOGAN is "
        "`stgem-wogan`), seeds " + f"{SEEDS[0]}–{SEEDS[-1]}" + ", 300 executed tests per run, as "
        "`wogan report RUN... --table` tabulates them. Failing roads and first failing test: "
        "median (mean). Distinct failures: failing roads ≥ 0.1 rad apart in the 60 m around the "
        "lane exit (docs/reference.md), median (mean). Diversity: median of the runs with ≥ 2 "
        "failing roads (the paper's measure). First failing test: its position in the run, executed + 1 when there is none; "
        "a seed's 60 random tests are the same in every setting, so it often falls among them. "
        "Closest approach: median of each run's largest `fitness_distance`. µs per candidate: "
        "generation time after the random phase over the candidates drawn there (valid and "
        "invalid), all runs pooled; stgem's includes a `wogan validate` process per candidate. "
        "Runs that ended early are listed under the table.")
    out()
    out("Runs: `scripts/runs/search_figures.sh` (ours, in target/effectiveness/), "
        "`python3 scripts/reference/stgem_search.py --oracle ORACLE --seeds 1-20` (stgem's, in target/stgem/).")
    for oracle in ORACLES:
        files = [f for tag, algorithm in SETTINGS + [["stgem", "stgem"]]
                 for f in run_files(oracle, tag, algorithm)]
        out()
        out(f"### {oracle}")
        out()
        if not files:
            out("No runs.")
            continue
        for line in report_table(*files):
            out(line)


# ---------------------------------------------------------------------------------------------
# The comparisons that decided the defaults, each by `wogan report A --vs B --table`: the binary's
# own Mann–Whitney test.
COMPARISONS = [
    ("paper.wogan", "random.random", "the paper's settings against random search"),
    ("paper.wogan", "stgem.stgem", "ours at the paper's settings against stgem's WOGAN"),
    ("distance.wogan", "paper.wogan", "distance fitness at 0.95 against BOLP"),
    ("distance-matched.wogan", "paper.wogan", "distance at its matched decay against BOLP"),
    ("distance-matched.wogan", "distance.wogan", "distance: matched decay against 0.95"),
    ("mutants.wogan", "paper.wogan", "`--mutation-share 0.25` against the paper's settings"),
    ("decay995.wogan", "paper.wogan", "`--target-decay 0.995` against the paper's settings"),
]
# Rounds of tests chosen at once (`--jobs`, issue 37) against one test at a time: their own
# section, so that it can be regenerated alone (ONLY=rounds).
ROUNDS_COMPARISONS = [
    ("jobs2.wogan", "paper.wogan", "`--jobs 2` (rounds of 2 tests) against one test at a time"),
    ("jobs4.wogan", "paper.wogan", "`--jobs 4` (rounds of 4 tests) against one test at a time"),
    ("jobs2-continue.wogan", "paper.wogan",
     "`--jobs 2 --round-acceptance continue` against one test at a time"),
    ("jobs4-continue.wogan", "paper.wogan",
     "`--jobs 4 --round-acceptance continue` against one test at a time"),
]
# The rows of each comparison shown here (the full table has every measure of the report).
MEASURES = ("| failures per run ", "| diversity ", "| distinct failures per run ",
            "| first failing test", "| closest approach")


def comparisons_section():
    out()
    out("## Comparisons (Mann–Whitney U, two-sided)")
    out()
    out("A against B, as `wogan report A --vs B --table` gives them (exact up to 20 runs a "
        "group), five of its rows: failing roads per run, the paper's diversity, distinct failures "
        "per run, the first failing test and the closest approach (a run's largest `fitness_distance`, 1 at the lane's edge).")
    comparison_tables(COMPARISONS)


def rounds_section():
    out()
    out("## Rounds of tests (`--jobs`): quality per test")
    out()
    out("WOGAN choosing rounds of N tests at once (A) against one test at a time (B), the paper's "
        "settings otherwise, 300 tests, seeds 1–20, as `wogan report A --vs B --table` gives "
        "them (the same rows as above); runs: `ORACLES=ORACLE SETS=\"paper jobs2 jobs4 "
        "jobs2-continue jobs4-continue\" scripts/runs/search_figures.sh`. Their speed: \"Every core\".")
    comparison_tables(ROUNDS_COMPARISONS)


def comparison_tables(comparisons):
    for oracle in ORACLES:
        out()
        out(f"### {oracle}")
        for a, b, what in comparisons:
            group_a = run_files(oracle, *a.split("."))
            group_b = run_files(oracle, *b.split("."))
            out()
            out(f"#### {what}")
            out()
            if not group_a or not group_b:
                out("Runs missing.")
                continue
            for line in report_table(*group_a, "--vs", *group_b):
                if not line.startswith("| ") or line.startswith(("| measure ",) + MEASURES):
                    out(line)
