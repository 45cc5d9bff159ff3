"""Section `field`: the SBST 2022 field in the competition's pipeline against wogan's simulator
(target/peers/, made by scripts/peers/campaign.sh) beside wogan's runs under the same budgets;
and the table helpers the later comparisons share.
"""

import glob
import json
import os
import re
import subprocess
import sys

from common import ORACLES, WOGAN, WORK, num, out, report_table, split

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "peers"))
import crashes  # noqa: E402  (scripts/peers/crashes.py: which peers' runs a crash ended, and whose crash it was)


# ---------------------------------------------------------------------------------------------
# The SBST 2022 field (issue 38): the peers' result folders (scripts/peers/campaign.sh) beside
# wogan's runs under the same budgets (scripts/runs/sbst_budget_runs.sh), with `wogan report`'s
# measures of each group, and the preset's comparison with every other row.
PEERS = [("random", "the pipeline's random generator"), ("freneticv", "FreneticV"),
         ("ambiegen", "AmbieGen"), ("adafrenetic", "AdaFrenetic"), ("frenetic2021", "Frenetic (2021)")]
OURS = [("preset-sbst", "wogan `--preset sbst`"),
        ("preset-sbst-no-niches", "wogan `--preset sbst-no-niches`"),
        ("wogan", "wogan, the paper's WOGAN"), ("random", "wogan, random search"),
        ("preset-sbst-any-road", "wogan `--preset sbst --min-road-turn 0`")]
FIELD_ROWS = [("tests executed", "tests"), ("failures", "failures"),
              ("failures per simulated hour", "failures / sim. h"),
              ("lane exits over the centre line (left)", "exits left"),
              ("lane exits over the road's edge (right)", "exits right"),
              ("sparseness mean over the OOBs it places", "sparseness"),
              ("diversity (", "diversity"), ("angle diversity (", "angle diversity"),
              ("distinct failures (", "distinct failures"),
              ("failing road length", "failing road length (m)")]
FIELD_COMPARED = ("failures per run", "diversity", "angle diversity", "distinct failures per run")


def rounded(text):
    """A figure of `wogan report` (three decimals) to one, as the page writes numbers."""
    try:
        return num(float(text.replace(",", "")))
    except ValueError:
        return text


def group_means(paths):
    """{measure name: (mean, runs)} of one group, from `wogan report PATHS --out DIR`."""
    folder = os.path.join(WORK, "field-report")
    done = subprocess.run([WOGAN, "report", *paths, "--out", folder], capture_output=True, text=True)
    if done.returncode not in (0, 1):
        sys.exit(f"results: wogan report of {paths[0]}...: {done.stderr.strip()}")
    figures = {}
    for line in open(os.path.join(folder, "report.md")):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 4 and cells[1] not in ("mean", "---", ""):
            figures.setdefault(cells[0], (cells[1], cells[3]))
    return figures


def mean_cells(paths, keys):
    """The group's mean of each measure whose name starts with a key in `keys`, rounded as the
    page writes numbers ("–" where the report has none)."""
    figures = group_means(paths)
    return [rounded(next((v for k, v in figures.items() if k.startswith(key)), ("–", ""))[0]) for key in keys]


def runs_of(prefix):
    """Every run file PREFIX.SEED.jsonl there is, in seed order (more seeds than SEEDS where a
    comparison needed them)."""
    seeded = [(re.fullmatch(r"\.(\d+)\.jsonl", p[len(prefix):]), p) for p in glob.glob(prefix + ".*.jsonl")]
    return [p for _, p in sorted((int(m.group(1)), p) for m, p in seeded if m)]


def peer_runs(oracle, tool):
    """The result folders of one peer's whole runs (scripts/peers/campaign.sh), in seed order:
    a run a signal cut short, whose summary names the signal, is left out (the campaign runs it
    again). A run a crash ended that its tool did not have in its competition stops the page:
    it measures the harness, not the tool (scripts/peers/crashes.py)."""
    def whole(summary_path):
        with open(summary_path) as f:
            return json.load(f).get("interrupted") is None
    found = glob.glob(f"target/peers/{oracle}.{tool}.*/summary.json")
    seeded = [(int(p.split("/")[-2].rsplit(".", 1)[-1]), p) for p in found]
    folders = [os.path.dirname(p) for _, p in sorted(seeded) if whole(p)]
    for folder in folders:
        verdict = crashes.classify(folder)
        if verdict and not verdict[0]:
            sys.exit(f"results: {folder}: {verdict[1]}; fix the harness and run it again")
    return folders


# A row whose runs are not on the machine that regenerates a section is kept as the page had it,
# marked KEPT, so that regenerating the rows whose runs changed does not drop the others (the
# runs are deterministic by seed, AmbieGen's excepted). The note under such a table says so.
KEPT = "‡"


def page_tables(heading, oracle):
    """The tables of the page as it is (OUT) under `## heading`, subsection `### oracle`: one
    {first cell without "(N runs)": row} per table, in order."""
    try:
        with open(os.environ["OUT"]) as f:
            text = f.read().split("\n")
    except FileNotFoundError:
        return []
    _, blocks = split(text, "## ")
    block = next((b for b in blocks if b[0] == f"## {heading}"), [])
    _, subsections = split(block, "### ")
    sub = next((b for b in subsections if b[0] == f"### {oracle}"), [])
    tables, current = [], None
    for line in sub:
        if line.startswith("|"):
            if current is None:
                current = {}
                tables.append(current)
            first = line.strip("|").split("|")[0].strip()
            if not set(first) <= set("-"):
                current[re.sub(r" \(\d+ runs\)$", "", first.replace(f" {KEPT}", ""))] = line
        else:
            current = None
    return tables


def kept_row(tables, index, name, column):
    """Row `name` of the page's table `index` (page_tables), its cell `column` marked KEPT; None
    when the page has no such row."""
    row = tables[index].get(name) if index < len(tables) else None
    if row is None or name in ("tool", "B"):
        return None
    cells = row.strip().strip("|").split("|")
    # A row the page had without runs has nothing to keep.
    if all(c.replace(KEPT, "").strip() in ("0", "–") for c in cells[1:]):
        return None
    if KEPT not in cells[column]:
        cells[column] = f"{cells[column].rstrip()} {KEPT} "
    return "|" + "|".join(cells) + "|"


def kept_note(commit):
    """The note under a table with kept rows."""
    return (f"{KEPT} kept as the page had it at commit {commit}: the row's run files are not on "
            "the machine that regenerated this section.")


def page_commit():
    """The commit of the page as it is (the last that changed OUT)."""
    done = subprocess.run(["git", "log", "-1", "--format=%h", "--", os.environ["OUT"]],
                          capture_output=True, text=True)
    return done.stdout.strip() or "?"


def behind_on(name, rows):
    """"NAME on MEASURE (A / B, p P)" for each measure of `rows` ("A / B, p P", higher is
    better for every compared measure) where A is below B at p < 0.05."""
    found = []
    for measure, text in rows.items():
        match = re.fullmatch(r"([\d.,]+) / ([\d.,]+), p (< )?([\d.]+)", text)
        if match and float(match[1].replace(",", "")) < float(match[2].replace(",", "")) \
                and float(match[4]) < 0.05:
            found.append(f"{name.replace(' ' + KEPT, '')} on {measure} ({text})")
    return found


def runs_cell(paths):
    """How many runs a row is of, and how many of them the tool's own crash ended."""
    crashed = sum(1 for p in paths if os.path.isdir(p) and crashes.classify(p))
    return f"{len(paths)} ({crashed} crashed)" if crashed else str(len(paths))


def compared(a_paths, b_paths, measures):
    """{measure: "A / B, p P"} of `wogan report A --vs B --table` for each of `measures`."""
    rows = {}
    for line in report_table(*a_paths, "--vs", *b_paths):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells and cells[0] in measures:
            a, b = (rounded(c.split(" (")[0]) for c in cells[1:3])
            p = "< 0.0001" if cells[4] == "0.0000" else cells[4]
            rows[cells[0]] = f"{a} / {b}, p {p}"
    return rows


def field_section():
    out()
    out("## The SBST 2022 field on our simulator")
    out()
    out("The public SBST 2022 generators, unchanged, in the competition's own pipeline with "
        "`wogan simulate` as its simulator (`scripts/peers/`: `PEERS_HOME=... "
        "scripts/peers/campaign.sh`), and wogan's runs under the same budgets (`--generation-budget "
        "1h --execution-budget 2h`: `scripts/runs/sbst_budget_runs.sh`; the preset's runs with "
        "`ALGORITHMS=preset-sbst`). Every figure is `wogan report`'s, computed the same way for "
        "every run: means over runs (their number in brackets). The diversity is the WOGAN authors' "
        "measure as their code computes it (docs/reference.md, \"Diversity\"; this page gave it "
        "with the headings unwrapped until 2026-11-27); the angle diversity is the same median with "
        "each direction difference taken as the angle between the two directions, so that roads "
        "heading back alike (angles near +π and near −π) count as near (docs/experiments/"
        "2026-11-27-wrap-and-shape.md). The peers' seeds seed Python's and "
        "numpy's generators; AmbieGen seeds pymoo from the clock and cannot be repeated, and a run "
        "of it takes 26–45 minutes against one or two of the other tools', so it has fewer runs. "
        "Each tool runs with the libraries of its competition's year (`scripts/peers/setup.sh`: "
        "Frenetic (2021) with the pandas of February 2021, under which it runs its whole budget); a "
        "run a crash ended counts with what it had and is counted in brackets beside the runs, and "
        "only a crash the tool had in its competition is tabled (`scripts/peers/crashes.py`; any "
        "other stops this page as the harness's defect).")
    for oracle in ORACLES:
        page = page_tables("The SBST 2022 field on our simulator", oracle)
        groups = []
        for tag, name in OURS:
            paths = runs_of(f"target/sbst/{oracle}.{tag}")
            # Only the DAVE-2 setup's preset has a least turn to leave out.
            if paths or tag != "preset-sbst-any-road" or kept_row(page, 0, name, 1):
                groups.append((name, paths))
        for tool, name in PEERS:
            groups.append((name, peer_runs(oracle, tool)))
        out()
        out(f"### {oracle}")
        out()
        kept = means_table(page, groups, FIELD_ROWS, "tool")
        preset = groups[0][1]
        if not preset:
            continue
        out()
        out("`--preset sbst` (A) against each other row (B), Mann–Whitney U, two-sided:")
        out()
        behind, _, kept_compared = comparison_table(page, groups)
        if kept or kept_compared:
            out()
            out(kept_note(page_commit()))
        out()
        if behind:
            out("Where `--preset sbst` is behind (A below B, p < 0.05): " + "; ".join(behind) + ".")
        else:
            out("`--preset sbst` is behind no row on these figures (A below B, p < 0.05).")


def means_table(page, groups, measures, first):
    """Writes the table of each group's means of `measures` (key, label), its first column headed
    `first`; a group without runs takes the page's row (page_tables table 0) when it has one.
    Returns whether a row was so kept."""
    kept = False
    out(f"| {first} | runs | " + " | ".join(label for _, label in measures) + " |")
    out("|---|---|" + "---|" * len(measures))
    for name, paths in groups:
        if not paths:
            row = kept_row(page, 0, name, 1)
            kept |= row is not None
            out(row or f"| {name} | 0 |" + " – |" * len(measures))
            continue
        cells = mean_cells(paths, [key for key, _ in measures])
        out(f"| {name} | {runs_cell(paths)} | " + " | ".join(cells) + " |")
    return kept


def comparison_table(page, groups):
    """Writes the first group (the preset) against each other on FIELD_COMPARED; a group without
    runs takes the page's row (table 1) when it has one. Returns the measures it is behind on
    (behind_on), the groups with neither runs nor a row, and whether a row was kept."""
    preset = groups[0][1]
    out("| B | " + " | ".join(f"{m}: A / B, p" for m in FIELD_COMPARED) + " |")
    out("|---|" + "---|" * len(FIELD_COMPARED))
    behind, missing, kept = [], [], False
    for name, paths in groups[1:]:
        if not paths:
            row = kept_row(page, 1, name, 0)
            kept |= row is not None
            if row:
                out(row)
                cells = [c.strip() for c in row.strip().strip("|").split("|")][1:]
                behind += behind_on(name, dict(zip(FIELD_COMPARED, cells)))
            else:
                missing.append(name)
            continue
        rows = compared(preset, paths, FIELD_COMPARED)
        out(f"| {name} | " + " | ".join(rows.get(m, "–") for m in FIELD_COMPARED) + " |")
        behind += behind_on(name, rows)
    return behind, missing, kept
