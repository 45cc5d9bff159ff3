"""Section `metadrive`: searches against MetaDrive through examples/metadrive/'s executor
(target/metadrive/, made by scripts/runs/metadrive_runs.sh), the field in MetaDrive
(target/peers/metadrive-*), and the `--jobs 2` speed-up (target/metadrive-speed/); and section
`metadrive-idm46`: the field on MetaDrive's calibrated IDM (target/metadrive-idm46/,
target/peers/metadrive-idm@46.*).
"""

import glob
import os
import statistics

import field
from common import num, out, read_jsonl
from field import FIELD_COMPARED, PEERS, compared, mean_cells, peer_runs, runs_of


# ---------------------------------------------------------------------------------------------
# A real simulator (issue 59): searches against MetaDrive through examples/metadrive/'s executor
# (scripts/runs/metadrive_runs.sh), per policy. The section lists what is on the machine.
METADRIVE_ALGORITHMS = [("random", "random search"), ("wogan", "the paper's WOGAN"),
                        ("preset-sbst", "`--preset sbst`")]
METADRIVE_COMPARED = ("failures per run", "distinct failures per run", "diversity")
# The measures of each row of its tables (`wogan report`'s names, by their start).
METADRIVE_ROWS = ("tests executed", "failures", "distinct failures (", "diversity (")
# The same searches climbing the lane distance (`--fitness distance`: the executor's
# `min_lane_distance_m`), made where BOLP is flat; listed when their runs exist, each compared
# with random search on the same fitness.
METADRIVE_DISTANCE = [("distance-random", "random search, `--fitness distance`"),
                      ("distance-wogan", "the paper's WOGAN, `--fitness distance`")]


def closest_approach(paths):
    """Mean over runs of the smallest lane distance any of its tests reached, metres, and the
    smallest of all (None when the runs carry no lane distance)."""
    per_run = []
    for path in paths:
        distances = [r["min_lane_distance_m"] for r in read_jsonl(path)
                     if r.get("type") == "test" and isinstance(r.get("min_lane_distance_m"), (int, float))]
        if distances:
            per_run.append(min(distances))
    return (statistics.mean(per_run), min(per_run)) if per_run else None


def tests_per_wall_minute(paths):
    """Mean over runs of executed tests per wall minute (the run's own summary)."""
    rates = []
    for path in paths:
        summary = read_jsonl(path)[-1]
        if summary.get("type") == "summary" and summary.get("wall_s"):
            rates.append(60.0 * summary["executed"] / summary["wall_s"])
    return statistics.mean(rates) if rates else None


def finished(paths):
    """The runs among `paths` that ended with their summary and were not interrupted (a campaign
    still running, or stopped, leaves one that has not)."""
    def ends_with_summary(path):
        with open(path, "rb") as f:
            f.seek(0, os.SEEK_END)
            f.seek(max(f.tell() - 4096, 0))
            last = f.read().decode("utf-8", "replace").rstrip("\n").rsplit("\n", 1)[-1]
        return '"type":"summary"' in last and '"interrupted":true' not in last
    return [p for p in paths if ends_with_summary(p)]


def metadrive_section():
    out()
    out("## A real simulator: MetaDrive")
    out()
    out("Searches whose every road is driven in MetaDrive 0.4.3 (Bullet physics, headless) by "
        "`examples/metadrive/executor.py` (`wogan run --executor`), under the competition's "
        "budgets (`--generation-budget 1h --execution-budget 2h`), at wogan's default conditions "
        "(0.85 tolerance, 70 km/h): `scripts/runs/metadrive_runs.sh POLICY SEEDS 1h 2h`. Figures are "
        "`wogan report`'s, means per run, and each search against random search by Mann–Whitney "
        "(`wogan report A --vs B`); tests per wall minute from each run's summary (the machine's "
        "load at the time counts: these runs shared its 2 cores with others).")
    out()
    out("**At 70 km/h, uncalibrated.** At 70 km/h `--policy idm` fails nearly every bend (74% of 300 of "
        "the SBST 2022 entries' roads, where BeamNG.AI fails about 10–13%), so its figures below count "
        "the variety of a search's roads more than what the search finds; `--policy expert` fails "
        "none. The subjects calibrated as wogan's own drivers were: \"MetaDrive's subjects "
        "calibrated\" below.")
    policies = sorted({os.path.basename(p).split(".")[0] for p in glob.glob("target/metadrive/*.jsonl")})
    if not policies:
        out()
        out("No runs on this machine.")
    for policy in policies:
        groups = [(name, finished(runs_of(f"target/metadrive/{policy}.{tag}"))) for tag, name in METADRIVE_ALGORITHMS]
        out()
        out(f"### `--policy {policy}`")
        out()
        out("| search | runs | tests | failures | distinct failures | diversity | tests per wall minute |")
        out("|---|---|---|---|---|---|---|")
        for name, paths in groups:
            if not paths:
                out(f"| {name} | 0 | – | – | – | – | – |")
                continue
            cells = mean_cells(paths, METADRIVE_ROWS)
            rate = tests_per_wall_minute(paths)
            out(f"| {name} | {len(paths)} | " + " | ".join(cells) + f" | {num(rate) if rate else '–'} |")
        distance = [(name, finished(runs_of(f"target/metadrive/{policy}.{tag}"))) for tag, name in METADRIVE_DISTANCE]
        distance = distance if all(paths for _, paths in distance) else []
        for name, paths in distance:
            cells = mean_cells(paths, METADRIVE_ROWS)
            rate = tests_per_wall_minute(paths)
            out(f"| {name} | {len(paths)} | " + " | ".join(cells) + f" | {num(rate) if rate else '–'} |")
        comparisons = [(groups[0], groups[1:])]
        if distance:
            comparisons.append((distance[0], distance[1:]))
        for (random_name, random_runs), rest in comparisons:
            for name, paths in rest:
                if random_runs and paths:
                    rows = compared(paths, random_runs, METADRIVE_COMPARED)
                    out()
                    out(f"{name} (A) against {random_name} (B): " + "; ".join(
                        f"{m} {rows.get(m, '–')}" for m in METADRIVE_COMPARED) + ".")
        for name, paths in distance:
            approach = closest_approach(paths)
            if approach:
                out()
                out(f"{name}: the closest any test came to leaving its lane, per run: "
                    f"{num(approach[0], 2)} m on average, {num(approach[1], 2)} m at the least "
                    "(the car centre's smallest distance to its lane's edges; 0 is the edge).")
        metadrive_field(policy, groups)
    metadrive_speedup()
    out()
    out("Whether wogan's presets carry over to MetaDrive, and why the field finds more distinct "
        "failures on `--policy idm` (the road family, measured by pooling runs): "
        "docs/experiments/2026-11-28-metadrive-searches-and-field.md, \"2026-11-29\".")


def metadrive_field(policy, groups):
    """The SBST 2022 field on MetaDrive (scripts/peers/campaign.sh metadrive-POLICY): each tool's
    means, and wogan's searches against it."""
    peers = [(name, peer_runs(f"metadrive-{policy}", tool)) for tool, name in PEERS]
    peers = [(name, paths) for name, paths in peers if paths]
    if not peers:
        return
    out()
    out(f"The SBST 2022 field on MetaDrive with `--policy {policy}`, in the competition's pipeline "
        f"(`PEERS_HOME=... scripts/peers/campaign.sh metadrive-{policy} SEEDS TOOLS`: MetaDrive's "
        "executor answering with the pipeline's execution data, the same budgets and conditions):")
    out()
    out("| tool | runs | tests | failures | distinct failures | diversity |")
    out("|---|---|---|---|---|---|")
    for name, paths in peers:
        cells = mean_cells(paths, METADRIVE_ROWS)
        out(f"| {name} | {len(paths)} | " + " | ".join(cells) + " |")
    for ours, mine in groups[1:]:
        if not mine:
            continue
        out()
        out(f"{ours} (A, {len(mine)} runs) against each tool (B), means and Mann–Whitney p "
            "(`wogan report A --vs B --table`):")
        out()
        out("| B | " + " | ".join(f"{m}: A / B, p" for m in METADRIVE_COMPARED) + " |")
        out("|---|" + "---|" * len(METADRIVE_COMPARED))
        for name, paths in peers:
            rows = compared(mine, paths, METADRIVE_COMPARED)
            out(f"| {name} ({len(paths)} runs) | " + " | ".join(rows.get(m, "–") for m in METADRIVE_COMPARED) + " |")


def metadrive_speedup():
    """`--jobs 2` against one executor on the same seeds, from runs made alone on the machine
    (target/metadrive-speed/: `OUT=target/metadrive-speed ALGORITHMS="random jobs2-random"
    scripts/runs/metadrive_runs.sh idm 2 1h 2h` with nothing else running)."""
    for policy in sorted({os.path.basename(p).split(".")[0] for p in glob.glob("target/metadrive-speed/*.jsonl")}):
        for tag, name in METADRIVE_ALGORITHMS:
            two = runs_of(f"target/metadrive-speed/{policy}.jobs2-{tag}")
            seeds = {p.rsplit(".", 2)[-2] for p in two}
            one = [p for p in runs_of(f"target/metadrive-speed/{policy}.{tag}") if p.rsplit(".", 2)[-2] in seeds]
            if one and two:
                r1, r2 = tests_per_wall_minute(one), tests_per_wall_minute(two)
                out()
                out(f"`--jobs 2` (`--policy {policy}`, {name}, {len(two)} runs, made with nothing "
                    f"else running): {num(r2)} tests per wall minute against {num(r1)} with one "
                    f"executor on the same seeds, {num(r2 / r1, 2)}x (two MetaDrive executors on a "
                    "2-core machine).")


# ---------------------------------------------------------------------------------------------
# The field on MetaDrive's calibrated IDM (issue 70, part 3): wogan's searches
# (`SPEED_LIMIT=46 OUT=target/metadrive-idm46 scripts/runs/metadrive_runs.sh idm SEEDS 1h 2h`) and
# every peer (`SPEED_LIMIT=46 scripts/peers/campaign.sh metadrive-idm`, folders
# target/peers/metadrive-idm@46.TOOL.SEED) on the same subject, tabled as the field on our
# simulator is.
CALIBRATED_RUNS = "target/metadrive-idm46"
CALIBRATED_PEERS = "metadrive-idm@46"
CALIBRATED_ROWS = [("tests executed", "tests"), ("failures", "failures"),
                   ("distinct failures (", "distinct failures"), ("diversity (", "diversity"),
                   ("angle diversity (", "angle diversity")]
CALIBRATED_HEADING = "The field on MetaDrive's calibrated IDM"


def calibrated_idm_section():
    out()
    out(f"## {CALIBRATED_HEADING}")
    out()
    out("MetaDrive's IDM at 46 km/h, where it fails 10.6% of the SBST 2022 entries' roads (\"MetaDrive's "
        "subjects calibrated\" above), under the competition's budgets (`--generation-budget 1h "
        "--execution-budget 2h`), tolerance 0.85, one MetaDrive executor per run. wogan's searches: "
        "`SPEED_LIMIT=46 OUT=target/metadrive-idm46 scripts/runs/metadrive_runs.sh idm SEEDS 1h 2h`; "
        "the peers, unchanged, in the competition's pipeline with MetaDrive's executor answering "
        "with the pipeline's execution data: `SPEED_LIMIT=46 PEERS_HOME=... scripts/peers/campaign.sh "
        "metadrive-idm SEEDS TOOLS`. Figures are `wogan report`'s, computed the same way for every "
        "run, means over runs (their number beside them); measures as in \"The SBST 2022 field on "
        "our simulator\". A row with 0 runs was not run on the machine that made this page. The "
        "campaign's log: docs/experiments/2026-12-07-field-on-calibrated-idm-first-look.md.")
    page = field.page_tables(CALIBRATED_HEADING, "`--policy idm` at 46 km/h")
    ours = dict(field.OURS)
    groups = [(ours[tag], finished(runs_of(f"{CALIBRATED_RUNS}/idm.{tag}")))
              for tag in ("preset-sbst", "wogan", "random")]
    groups += [(name, peer_runs(CALIBRATED_PEERS, tool)) for tool, name in PEERS]
    out()
    out("### `--policy idm` at 46 km/h")
    out()
    kept = field.means_table(page, groups, CALIBRATED_ROWS, "search")
    preset = groups[0][1]
    if preset:
        out()
        out("`--preset sbst` (A) against each other row (B), Mann–Whitney U, two-sided "
            "(`wogan report A --vs B --table`):")
        out()
        behind, missing, kept_compared = field.comparison_table(page, groups)
        if kept or kept_compared:
            out()
            out(field.kept_note(field.page_commit()))
        # The bar for the peers on this subject: 5 runs each, AmbieGen 3.
        few = [f"{name} ({len(paths)})" for name, paths in groups[3:]
               if 0 < len(paths) < (3 if name == "AmbieGen" else 5)]
        caveats = ([f"not compared, no runs: {', '.join(missing)}"] if missing else []) + (
            [f"too few runs yet to judge (5 needed, AmbieGen 3): {', '.join(few)}"] if few else [])
        out()
        if behind:
            out("Where `--preset sbst` is behind (A below B, p < 0.05): " + "; ".join(behind)
                + "".join(f"; {c}" for c in caveats) + ".")
        else:
            out("`--preset sbst` is behind no row on these figures (A below B, p < 0.05)"
                + "".join(f"; {c}" for c in caveats) + ".")
    wogan_runs, random_runs = groups[1][1], groups[2][1]
    if wogan_runs and random_runs:
        rows = compared(wogan_runs, random_runs, FIELD_COMPARED)
        out()
        out("The paper's WOGAN (A) against random search (B): " + "; ".join(
            f"{m} {rows.get(m, '–')}" for m in FIELD_COMPARED) + ".")
