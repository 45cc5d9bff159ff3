#!/usr/bin/env bash
# Writes docs/results.md: every measured figure the project quotes, regenerated from run files,
# the reference roads and criterion's bench output, stamped with the date and the machine.
# The README states no figures; it points here.
#
#   scripts/results.sh                                  # uses target/release/wogan
#   WOGAN=/path/to/wogan scripts/results.sh
#   MAKE_RUNS=1 scripts/results.sh                      # first make the missing search runs
#   ALLOW_MISSING=1 scripts/results.sh                  # write what there is; name what is missing
#   ONLY=generator,ci scripts/results.sh                # regenerate those sections of docs/results.md in place
#   ORACLES=dave2-proxy ONLY=field scripts/results.sh   # ... and of them only that driver's subsections
#
# What it reads (nothing here is measured twice: each source has its own script):
#   target/effectiveness/ORACLE.TAG.ALGORITHM.SEED.jsonl   scripts/search_figures.sh (seeds 1-20)
#   target/stgem/ORACLE.stgem.SEED.jsonl                   scripts/reference/stgem_search.py
#   target/sbst/ORACLE.ALGORITHM.SEED.jsonl                 scripts/sbst_budget_runs.sh (optional)
#   target/peers/ORACLE.TOOL.SEED/                         scripts/peers/campaign.sh (optional)
#   target/criterion/**/new/estimates.json                 cargo bench (commands in the output)
#   target/results/train-driver.json (optional)            wogan train-driver --seed 1 ... (below)
#   tests/reference/*.jsonl                                the competition's vectors
#   target/bench-output/{ci,plug-points,campaigns,parallel}.txt  scripts/{ci,plug_points,campaign,parallel}_bench.sh
# What it runs: `wogan report ... --table`, whose tables of run files it includes as they are,
# and `wogan simulate` / `wogan validate` on the reference roads (about a minute: dave2-proxy
# renders and infers 300 drives).
#
# Missing run files stop it with the list and the commands that make them, unless ALLOW_MISSING=1.
# SEEDS (default 1-20) and ORACLES narrow the set. Python 3 (stdlib only) does the arithmetic.
set -euo pipefail
cd "$(dirname "$0")/.."
export WOGAN=${WOGAN:-target/release/wogan}
export SEEDS=${SEEDS:-$(seq -s ' ' 1 20)}
export ORACLES=${ORACLES:-beamng-ai-proxy dave2-proxy}
export OUT=${OUT:-docs/results.md}
export WORK=${WORK:-target/results}
export TRAIN_LOG=${TRAIN_LOG:-target/results/train-driver.json}

if [ ! -x "$WOGAN" ]; then
  echo "results.sh: no wogan binary at $WOGAN: build it (cargo build --release -p wogan-cli) or set WOGAN" >&2
  exit 2
fi

# The search settings, as scripts/search_figures.sh names and makes them: TAG ALGORITHM.
# (The options of each are read back from the run headers, so this list cannot drift silently.)
export SETTINGS="paper:wogan distance:wogan distance-matched:wogan mutants:wogan decay995:wogan jobs2:wogan jobs4:wogan jobs2-continue:wogan jobs4-continue:wogan random:random"

# Which run files are absent. Printed per oracle and setting with the command that makes them,
# so that a missing run is never silently left out of a median.
missing_runs() {
  local oracle setting tag algorithm seed absent
  for oracle in $ORACLES; do
    for setting in $SETTINGS; do
      tag=${setting%%:*} algorithm=${setting#*:} absent=""
      for seed in $SEEDS; do
        [ -f "target/effectiveness/$oracle.$tag.$algorithm.$seed.jsonl" ] || absent="$absent $seed"
      done
      [ -z "$absent" ] || echo "$oracle $tag seeds$absent"
    done
    absent=""
    for seed in $SEEDS; do
      [ -f "target/stgem/$oracle.stgem.$seed.jsonl" ] || absent="$absent $seed"
    done
    [ -z "$absent" ] || echo "$oracle stgem seeds$absent"
  done
}

missing=$(missing_runs)
# Regenerating only other sections (ONLY=...) needs none of the search runs.
if [ -n "${ONLY:-}" ] && ! echo ",$ONLY," | grep -qE ',(search|comparisons),'; then
  missing=""
fi
if [ -n "$missing" ] && [ "${MAKE_RUNS:-0}" = 1 ]; then
  # search_figures.sh reuses every complete run (REUSE=1) and makes the rest; stgem's runs need
  # torch and a stgem checkout, so they are only named.
  for oracle in $ORACLES; do
    sets=$(echo "$missing" | awk -v o="$oracle" '$1 == o && $2 != "stgem" {printf "%s ", $2}')
    [ -z "$sets" ] || ORACLES=$oracle SETS="$sets" SEEDS="$SEEDS" scripts/search_figures.sh
  done
  missing=$(missing_runs)
fi
if [ -n "$missing" ]; then
  {
    echo "results.sh: run files missing:"
    echo "$missing" | sed 's/^/  /'
    echo "make them with (complete runs are reused):"
    seeds_env=""
    [ "$SEEDS" = "$(seq -s ' ' 1 20)" ] || seeds_env="SEEDS=\"$SEEDS\" "
    echo "$missing" | awk -v s="$seeds_env" '$2 != "stgem" {print "  " s "ORACLES=" $1 " SETS=" $2 " scripts/search_figures.sh"}'
    echo "$missing" | awk '$2 == "stgem" {
      seeds = $4; for (i = 5; i <= NF; i++) seeds = seeds "," $i
      print "  python3 scripts/reference/stgem_search.py --oracle " $1 " --seeds " seeds "   # needs torch and a stgem checkout: see the script"}'
    echo "or MAKE_RUNS=1 scripts/results.sh; ALLOW_MISSING=1 writes the results without them."
  } >&2
  [ "${ALLOW_MISSING:-0}" = 1 ] || exit 1
fi
export MISSING=$missing

mkdir -p "$WORK" "$(dirname "$OUT")"
python3 - <<'PY'
import datetime, glob, json, os, re, statistics, subprocess, sys, time
sys.path.insert(0, "scripts/peers")
import crashes  # which peers' runs a crash ended, and whose crash it was

WOGAN = os.environ["WOGAN"]
SEEDS = os.environ["SEEDS"].split()
ORACLES = os.environ["ORACLES"].split()
# Every driver the page has sections for (ORACLES narrows which are regenerated).
ALL_ORACLES = ("beamng-ai-proxy", "dave2-proxy")
WORK = os.environ["WORK"]
SETTINGS = [s.split(":") for s in os.environ["SETTINGS"].split()]
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
        sys.exit(f"results.sh: wogan report {' '.join(args)} --table failed: {done.stderr.strip()}")
    for line in done.stderr.splitlines():
        print(f"results.sh: {line}", file=sys.stderr)
    return done.stdout.rstrip("\n").split("\n")


def run_files(oracle, tag, algorithm):
    if tag == "stgem":
        paths = [f"target/stgem/{oracle}.stgem.{s}.jsonl" for s in SEEDS]
    else:
        paths = [f"target/effectiveness/{oracle}.{tag}.{algorithm}.{s}.jsonl" for s in SEEDS]
    return [p for p in paths if os.path.exists(p)]


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
    out("Runs: `scripts/search_figures.sh` (ours, in target/effectiveness/), "
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
        "jobs2-continue jobs4-continue\" scripts/search_figures.sh`. Their speed: \"Every core\".")
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


# ---------------------------------------------------------------------------------------------
# Under the SBST 2022 competition's budgets (scripts/sbst_budget_runs.sh: 1 h generation, 2 h
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
        "`scripts/sbst_budget_runs.sh ORACLE \"$(seq -s ' ' 1 20)\" 1h 2h`.")
    for oracle in ORACLES:
        out()
        out(f"### {oracle}")
        out()
        wogan = [f"target/sbst/{oracle}.wogan.{s}.jsonl" for s in SEEDS]
        random = [f"target/sbst/{oracle}.random.{s}.jsonl" for s in SEEDS]
        wogan = [p for p in wogan if os.path.exists(p)]
        random = [p for p in random if os.path.exists(p)]
        if not wogan or not random:
            out(f"Runs missing: `scripts/sbst_budget_runs.sh {oracle} \"$(seq -s ' ' 1 20)\" 1h 2h`.")
            continue
        out(f"{len(wogan)} WOGAN runs, {len(random)} random runs.")
        out()
        for line in report_table(*wogan, "--vs", *random):
            out(line)


# ---------------------------------------------------------------------------------------------
# The SBST 2022 field (issue 38): the peers' result folders (scripts/peers/campaign.sh) beside
# wogan's runs under the same budgets (scripts/sbst_budget_runs.sh), with `wogan report`'s
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
        sys.exit(f"results.sh: wogan report of {paths[0]}...: {done.stderr.strip()}")
    figures = {}
    for line in open(os.path.join(folder, "report.md")):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 4 and cells[1] not in ("mean", "---", ""):
            figures.setdefault(cells[0], (cells[1], cells[3]))
    return figures


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
            sys.exit(f"results.sh: {folder}: {verdict[1]}; fix the harness and run it again")
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
        "1h --execution-budget 2h`: `scripts/sbst_budget_runs.sh`; the preset's runs with "
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
        kept = False
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
        out("| tool | runs | " + " | ".join(label for _, label in FIELD_ROWS) + " |")
        out("|---|---|" + "---|" * len(FIELD_ROWS))
        for name, paths in groups:
            if not paths:
                row = kept_row(page, 0, name, 1)
                kept |= row is not None
                out(row or f"| {name} | 0 |" + " – |" * len(FIELD_ROWS))
                continue
            figures = group_means(paths)
            cells = []
            for key, _ in FIELD_ROWS:
                found = next((v for k, v in figures.items() if k.startswith(key)), ("–", ""))
                cells.append(rounded(found[0]))
            out(f"| {name} | {runs_cell(paths)} | " + " | ".join(cells) + " |")
        preset = groups[0][1]
        if not preset:
            continue
        out()
        out("`--preset sbst` (A) against each other row (B), Mann–Whitney U, two-sided:")
        out()
        out("| B | " + " | ".join(f"{m}: A / B, p" for m in FIELD_COMPARED) + " |")
        out("|---|" + "---|" * len(FIELD_COMPARED))
        behind = []
        for name, paths in groups[1:]:
            if not paths:
                row = kept_row(page, 1, name, 0)
                kept |= row is not None
                if row:
                    out(row)
                    cells = [c.strip() for c in row.strip().strip("|").split("|")][1:]
                    behind += behind_on(name, dict(zip(FIELD_COMPARED, cells)))
                continue
            rows = compared(preset, paths, FIELD_COMPARED)
            out(f"| {name} | " + " | ".join(rows.get(m, "–") for m in FIELD_COMPARED) + " |")
            behind += behind_on(name, rows)
        if kept:
            out()
            out(kept_note(page_commit()))
        out()
        if behind:
            out("Where `--preset sbst` is behind (A below B, p < 0.05): " + "; ".join(behind) + ".")
        else:
            out("`--preset sbst` is behind no row on these figures (A below B, p < 0.05).")


# ---------------------------------------------------------------------------------------------
# The `sbst` preset (issue 38) against the preset without niches, the paper's WOGAN and each peer
# whose runs are on the machine, under the competition's budgets.
PRESET_COMPARED = ("failures per run", "distinct failures per run", "diversity", "angle diversity",
                   "sparseness mean over the OOBs it places")


def sbst_preset_section():
    out()
    out("## The `sbst` preset")
    out()
    out("`--preset sbst` (A) against `--preset sbst-no-niches` and the paper's WOGAN (B) under the "
        "competition's budgets (`ALGORITHMS=\"preset-sbst preset-sbst-no-niches wogan\" "
        "scripts/sbst_budget_runs.sh ORACLE \"$(seq -s ' ' 1 20)\" 1h 2h`): means per run, "
        "Mann–Whitney U, two-sided, from `wogan report A --vs B --table`; then against each SBST "
        "2022 tool whose runs are on the machine (`PEERS_HOME=... scripts/peers/campaign.sh "
        "ORACLE \"$(seq -s ' ' 1 20)\" TOOLS`; all of their figures are in the field's section). How "
        "the settings were chosen: docs/experiments/2026-11-26-niches.md, 2026-11-26-niche-roads.md, "
        "2026-11-26-sbst-preset.md and 2026-11-26-field-20-runs.md; the DAVE-2 setup's small niches: "
        "2026-11-27-tiny-niches-larger-steps.md; the BeamNG.AI setup's roads compared by directions: "
        "2026-11-28-niches-by-directions.md; the DAVE-2 setup's winding roads (`--min-road-turn 2.5`; "
        "`--preset sbst --min-road-turn 0` is the preset before them): 2026-11-28-winding-roads.md.")
    for oracle in ORACLES:
        preset = runs_of(f"target/sbst/{oracle}.preset-sbst")
        out()
        out(f"### {oracle}")
        out()
        if not preset:
            out(f"Runs missing: `ALGORITHMS=preset-sbst scripts/sbst_budget_runs.sh {oracle} ...`.")
            continue
        page = page_tables("The `sbst` preset", oracle)
        kept = False
        out(f"A: {len(preset)} runs of `--preset sbst`.")
        out()
        out("| B | " + " | ".join(f"{m}: A / B, p" for m in PRESET_COMPARED) + " |")
        out("|---|" + "---|" * len(PRESET_COMPARED))
        # The seeds A has, so that both sides are the same searches' luck.
        seeds = {n.rsplit(".", 2)[-2] for n in preset}
        others = [(name, [p for p in runs_of(f"target/sbst/{oracle}.{tag}")
                          if p.rsplit(".", 2)[-2] in seeds]) for tag, name in OURS[1:3] + OURS[4:]]
        # And the peers' runs (scripts/peers/campaign.sh), each against A.
        others += [(name, peer_runs(oracle, tool)) for tool, name in PEERS]
        for name, paths in others:
            if not paths:
                row = kept_row(page, 0, name, 0)
                kept |= row is not None
                if row:
                    out(row)
                continue
            rows = compared(preset, paths, PRESET_COMPARED)
            out(f"| {name} ({len(paths)} runs) | " + " | ".join(rows.get(m, "–") for m in PRESET_COMPARED) + " |")
        if kept:
            out()
            out(kept_note(page_commit()))


# ---------------------------------------------------------------------------------------------
# A real simulator (issue 59): searches against MetaDrive through examples/metadrive/'s executor
# (scripts/metadrive_runs.sh), per policy. The section lists what is on the machine.
METADRIVE_ALGORITHMS = [("random", "random search"), ("wogan", "the paper's WOGAN"),
                        ("preset-sbst", "`--preset sbst`")]
METADRIVE_COMPARED = ("failures per run", "distinct failures per run", "diversity")


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
        "(0.85 tolerance, 70 km/h): `scripts/metadrive_runs.sh POLICY SEEDS 1h 2h`. Figures are "
        "`wogan report`'s, means per run, and each search against random search by Mann–Whitney "
        "(`wogan report A --vs B`); tests per wall minute from each run's summary (the machine's "
        "load at the time counts: these runs shared its 2 cores with others).")
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
            figures = group_means(paths)
            cells = [rounded(next((v for k, v in figures.items() if k.startswith(key)), ("–", ""))[0])
                     for key in ("tests executed", "failures", "distinct failures (", "diversity (")]
            rate = tests_per_wall_minute(paths)
            out(f"| {name} | {len(paths)} | " + " | ".join(cells) + f" | {num(rate) if rate else '–'} |")
        random_runs = groups[0][1]
        for name, paths in groups[1:]:
            if random_runs and paths:
                rows = compared(paths, random_runs, METADRIVE_COMPARED)
                out()
                out(f"{name} (A) against random search (B): " + "; ".join(
                    f"{m} {rows.get(m, '–')}" for m in METADRIVE_COMPARED) + ".")
        metadrive_field(policy, groups)
    metadrive_speedup()


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
        figures = group_means(paths)
        cells = [rounded(next((v for k, v in figures.items() if k.startswith(key)), ("–", ""))[0])
                 for key in ("tests executed", "failures", "distinct failures (", "diversity (")]
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
    scripts/metadrive_runs.sh idm 2 1h 2h` with nothing else running)."""
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
# Camera networks trained elsewhere (issue 63): a Keras DAVE-2 trained on `wogan dataset` frames,
# converted without TensorFlow, under the `udacity` contract (scripts/experiments/keras_loop.sh).
def keras_section():
    out()
    out("## A Keras network trained on wogan's frames")
    out()
    base = "target/keras-loop"
    if not os.path.exists(f"{base}/reference.keras.jsonl"):
        out("No runs on this machine: `scripts/experiments/keras_loop.sh`.")
        return
    out("A Keras DAVE-2 (the Udacity course's architecture and training, tensorflow-cpu 2.15) "
        "trained on frames of `wogan dataset` (beamng-ai-proxy on random roads at 40 km/h), "
        "converted by `examples/onnx/keras_to_onnx.py` and driven with `--oracle onnx:` under "
        "`{\"driver\": {\"contract\": \"udacity\"}}`: `scripts/experiments/keras_loop.sh` "
        "(docs/experiments/2026-11-28-keras-loop.md).")
    out()
    out("| driver | reference roads failed (of 300) | lane exits | not moving | time-outs |")
    out("|---|---|---|---|---|")
    for name, label in (("keras", "the Keras DAVE-2 (`udacity` contract)"), ("dave2-proxy", "dave2-proxy")):
        results = [r for r in read_jsonl(f"{base}/reference.{name}.jsonl") if r.get("type") == "result"]
        failed = [r for r in results if r.get("outcome") == "FAIL"]
        reasons = [sum(r.get("reason") == k for r in failed) for k in ("out_of_lane", "not_moving", "timeout")]
        out(f"| {label} | {len(failed)} of {len(results)} | " + " | ".join(str(v) for v in reasons) + " |")
    wogan_runs, random_runs = runs_of(f"{base}/wogan"), runs_of(f"{base}/random")
    if wogan_runs and random_runs:
        rows = compared(wogan_runs, random_runs, ("failures per run", "distinct failures per run", "diversity"))
        out()
        out(f"WOGAN (A, {len(wogan_runs)} runs of 300 tests) against random search (B, "
            f"{len(random_runs)} runs) on it: " + "; ".join(f"{m} {rows.get(m, '–')}" for m in rows) + ".")


# ---------------------------------------------------------------------------------------------
# The saved generator (issue 35): 50 tests chosen with the generator of a 300-test run against 50
# random tests of the same seed, per driver (scripts/generator_figures.sh).
def generator_section():
    out()
    out("## Sampling from a saved generator")
    out()
    out("Per seed (1–20) and driver, a 300-test WOGAN run at the paper's settings saves its "
        "generator (`--save-generator`); 50 tests chosen with it (`wogan run --generator`, the "
        "roads `wogan sample` draws with the same seed, without training) are compared with 50 "
        "random tests of the same seed by `wogan report SAMPLED --vs RANDOM --table` (A: sampled, "
        "B: random). Runs: `scripts/generator_figures.sh`.")
    for oracle in ORACLES:
        sampled = [f"target/generator/{oracle}.sampled.{s}.jsonl" for s in SEEDS]
        random = [f"target/generator/{oracle}.random.{s}.jsonl" for s in SEEDS]
        sampled = [p for p in sampled if os.path.exists(p)]
        random = [p for p in random if os.path.exists(p)]
        out()
        out(f"### {oracle}")
        out()
        if not sampled or not random:
            out(f"Runs missing: `ORACLES={oracle} scripts/generator_figures.sh`.")
            continue
        rows = report_table(*sampled, "--vs", *random)
        keep = ("| failures per run ", "| diversity ", "| closest approach", "| first failing test")
        for line in rows:
            if not line.startswith("| ") or line.startswith(("| measure ",) + keep):
                out(line)


# ---------------------------------------------------------------------------------------------
# What the CI commands, the plug points and a campaign's report cost (issues 35, 36 and 37), from
# their bench scripts' saved output, each line as the script printed it.
def saved_bench_section(heading, script, name):
    out()
    out(f"## {heading}")
    out()
    path = f"target/bench-output/{name}.txt"
    if not os.path.exists(path):
        out(f"Not measured yet: `{script} | tee {path}`.")
        return
    when = datetime.datetime.fromtimestamp(os.path.getmtime(path), datetime.timezone.utc)
    out(f"`{script}` ({when:%Y-%m-%d}), each line its own output:")
    out()
    for line in open(path):
        if line.startswith("wogan "):
            out(f"- {line.strip()}")


def ci_section():
    saved_bench_section("CI commands", "scripts/ci_bench.sh", "ci")


def plug_points_section():
    saved_bench_section("Plug points", "scripts/plug_points_bench.sh", "plug-points")


def every_core_section():
    saved_bench_section("Every core (`--jobs`)", "scripts/parallel_bench.sh", "parallel")


def campaigns_section():
    saved_bench_section("Campaigns", "scripts/campaign_bench.sh", "campaigns")


# ---------------------------------------------------------------------------------------------
# The drivers on the competition's 300 reference roads: their failure profile (what a driver is
# calibrated against) and the simulator's speed, from `wogan simulate`'s own timings.
def simulate_roads(oracle, jobs=1, copies=1):
    with open("tests/reference/roads.jsonl") as f:
        roads = f.read()
    started = time.monotonic()
    done = subprocess.run([WOGAN, "simulate", "--oracle", oracle, "--jobs", str(jobs)],
                          input=roads * copies, capture_output=True, text=True, check=True)
    wall = time.monotonic() - started
    return [json.loads(l) for l in done.stdout.splitlines() if l.strip()], wall


def cpu_busy(seconds=2.0):
    """Share of all cores busy over the next few seconds, before this script times anything.
    (The load average lags by a minute and would count this script's own work.)"""
    def sample():
        with open("/proc/stat") as f:
            values = [int(v) for v in f.readline().split()[1:]]
        return sum(values), values[3] + values[4]  # total, idle + iowait
    try:
        total0, idle0 = sample()
        time.sleep(seconds)
        total1, idle1 = sample()
    except (OSError, ValueError, IndexError):
        return None
    return 1 - (idle1 - idle0) / max(1, total1 - total0)


def busy_warning():
    """Speed figures from a machine that was doing something else mislead; say so where they are."""
    busy = cpu_busy()
    if busy is None:
        return
    if busy >= 0.2:
        out(f"**The machine was busy** ({100 * busy:.0f}% of its {os.cpu_count()} cores in use by "
            "other work just before these were measured): the wall times below are slower than on "
            "an idle machine; run the script again on an idle one for speed figures.")
    else:
        out(f"Other work on the machine just before these were measured: {100 * busy:.0f}% of its cores.")
    out()


def reference_roads_section(bench):
    out()
    out("## The drivers on the 300 reference roads")
    out()
    busy_warning()
    out("`wogan simulate --oracle ORACLE tests/reference/roads.jsonl` at each driver's defaults, one job. "
        "Graded: 0.002 < max BOLP ≤ 0.1 (the slope the BOLP fitness can climb at DAVE-2's tolerance).")
    out()
    out("| driver | FAIL | max BOLP < 0.05 | max BOLP ≤ 0.002 | graded | wall time per road, median | simulated / wall time |")
    out("|---|---|---|---|---|---|---|")
    per_road = {}
    for oracle in ["beamng-ai-proxy", "dave2-proxy"]:
        results, _ = simulate_roads(oracle)
        n = len(results)
        share = lambda k: f"{100 * k / n:.1f}%"
        fails = sum(r["outcome"] == "FAIL" for r in results)
        bolp = [r["max_bolp"] for r in results]
        ms = [r["execution_ms"] for r in results]
        per_road[oracle] = results
        factor = sum(r["sim_time_s"] for r in results) / (sum(ms) / 1000)
        out(f"| {oracle} | {fails} ({share(fails)}) | {share(sum(b < 0.05 for b in bolp))} | "
            f"{share(sum(b <= 0.002 for b in bolp))} | {share(sum(0.002 < b <= 0.1 for b in bolp))} | "
            f"{num(median(ms), 2)} ms | {num(factor, 0)}x |")
    # Parallel simulation: the same 1,200 beamng-ai-proxy drives with one job and with two.
    _, one = simulate_roads("beamng-ai-proxy", 1, 4)
    _, two = simulate_roads("beamng-ai-proxy", 2, 4)
    out()
    out(f"`wogan simulate --jobs 2` against `--jobs 1` (1,200 beamng-ai-proxy drives): "
        f"{one / two:.2f}x the throughput ({one:.2f} s / {two:.2f} s wall; other work on the "
        f"machine lowers this most, see the note above).")
    return per_road


# The drivers on the road families they are calibrated on (issue 11): the output of
# scripts/driver_rates.sh, saved per driver, with the competition's anchors beside it.
RATES = "target/results/driver_rates.{}.txt"


def long_roads_section():
    out()
    out("## The drivers on long roads of the competition's kind")
    out()
    rates = {}
    for oracle in ["beamng-ai-proxy", "dave2-proxy"]:
        try:
            with open(RATES.format(oracle)) as f:
                for line in f:
                    # driver_rates.sh prints a label, then "FAILED / ROADS RATE".
                    *label, failed, _, roads, rate = line.split()
                    rates.setdefault(" ".join(label), {})[oracle] = f"{rate} ({failed}/{roads})"
        except OSError:
            out(f"No saved rates for {oracle}: make them with `scripts/driver_rates.sh {oracle} > "
                f"{RATES.format(oracle)}`.")
            out()
    if not rates:
        return
    out("Failures at each driver's defaults, by road family: `scripts/driver_rates.sh ORACLE > "
        f"{RATES.format('ORACLE')}` (saved output, read here). The issue's bounds: at most 20% "
        "(beamng-ai-proxy) and 10% (dave2-proxy) on long roads, 1–8% and 0.5–10% on WOGAN's 75 m roads. "
        "How they were calibrated: `docs/experiments/2026-11-23-drivers-on-long-roads.md`.")
    out()
    out("| roads | beamng-ai-proxy | dave2-proxy |")
    out("|---|---|---|")
    for label, cells in rates.items():
        out(f"| {label} | {cells.get('beamng-ai-proxy', '–')} | {cells.get('dave2-proxy', '–')} |")


# ---------------------------------------------------------------------------------------------
# Agreement with the competition's own pipeline, checked through the binary (the same checks as
# tests/reference_vectors.rs, which fails below its thresholds; here the counts are shown).
REASONS = {
    "Not enough road points.": "not_enough_points",
    "The road definition contains too many points": "too_many_points",
    "Not entirely inside the map boundaries": "outside_map",
    "The road is self-intersecting": "self_intersecting",
    "The road is not long enough.": "too_short",
    "The road is too sharp": "too_sharp",
}


def validate(path, *options):
    done = subprocess.run([WOGAN, "validate", *options, path], capture_output=True, text=True)
    return [json.loads(l) for l in done.stdout.splitlines() if l.strip()]


def fidelity_section():
    out()
    out("## Agreement with the competition's pipeline")
    out()
    out("Against the vectors of `tests/reference/` (made by the competition's own Python code), "
        "through `wogan validate` and `wogan simulate`.")
    out()
    out("| what | agreement |")
    out("|---|---|")
    ref = read_jsonl("tests/reference/validator.jsonl")
    ours = validate("tests/reference/validator.jsonl")
    same = sum(r["valid"] == o.get("valid") for r, o in zip(ref, ours))
    both_invalid = [(r, o) for r, o in zip(ref, ours) if not r["valid"] and o.get("valid") is False]
    # Where the reference itself raised, any reason of ours counts (the test does the same).
    same_reason = sum(r["message"].startswith("reference raised:") or REASONS.get(r["message"]) == o.get("reason")
                      for r, o in both_invalid)
    out(f"| validity verdicts | {same}/{len(ref)} |")
    out(f"| reasons (both invalid) | {same_reason}/{len(both_invalid)} |")
    ref = read_jsonl("tests/reference/spline.jsonl")
    ours = validate("tests/reference/spline.jsonl", "--details")
    worst, equal = 0.0, 0
    for r, o in zip(ref, ours):
        a, b = r["interpolated_points"], o.get("interpolated_points") or []
        if len(a) != len(b):
            continue
        d = max((abs(x - y) for p, q in zip(a, b) for x, y in zip(p, q)), default=0.0)
        worst, equal = max(worst, d), equal + (d < 5e-4)
    out(f"| interpolated points (3 decimals) | {equal}/{len(ref)} roads, largest difference {worst:g} m |")
    ref = read_jsonl("tests/reference/features.jsonl")
    done = subprocess.run([WOGAN, "simulate", "tests/reference/features.jsonl"], capture_output=True, text=True, check=True)
    ours = [json.loads(l) for l in done.stdout.splitlines() if l.strip()]
    for feature in ["MAX_CURV", "DIR_COV"]:
        d = max(abs(r[feature] - o[feature]) for r, o in zip(ref, ours))
        out(f"| {feature} ({len(ref)} roads) | largest difference {d:.1e} |")


# ---------------------------------------------------------------------------------------------
# Criterion's estimates, as the last `cargo bench` left them. Each carries the date it was
# measured (the file's time), which may be older than this page.
BENCHES = [
    ("validator/per 6-point WOGAN road", "cargo bench -p road-sim --bench validator"),
    ("validator/all reference roads", "cargo bench -p road-sim --bench validator"),
    ("simulate one roads.jsonl road (beamng-ai-proxy)", "cargo bench -p road-sim --bench simulate"),
    ("simulate one roads.jsonl road (dave2-proxy)", "cargo bench -p road-sim --bench simulate"),
    ("camera/render_gray_66x200", "cargo bench -p road-sim --bench camera"),
    ("dave2/inference", "cargo bench -p road-sim --bench camera"),
    ("dave2/render_and_inference", "cargo bench -p road-sim --bench camera"),
    ("wogan_iteration/300", "RAYON_NUM_THREADS=1 cargo bench -p wogan-core --bench iteration"),
    ("wogan_iteration/3000", "RAYON_NUM_THREADS=1 cargo bench -p wogan-core --bench iteration"),
    ("wogan_iteration/30000", "RAYON_NUM_THREADS=1 cargo bench -p wogan-core --bench iteration"),
    ("wogan_iteration/100000", "RAYON_NUM_THREADS=1 cargo bench -p wogan-core --bench iteration"),
] + [(f"{group}/{n}", "RAYON_NUM_THREADS=1 cargo bench -p wogan-core --bench iteration")
     for group, sizes in [("wogan_iteration_two_threads", [300, 3000, 30000, 100000]),
                          ("iteration_parts/train", [300, 30000]),
                          ("iteration_parts/train_without_analyzer", [300, 30000]),
                          ("iteration_parts/train_one_critic_step", [300, 30000]),
                          ("iteration_parts/propose", [300, 30000])]
     for n in sizes]


def criterion():
    found = {}
    for path in glob.glob("target/criterion/**/new/benchmark.json", recursive=True):
        estimates = os.path.join(os.path.dirname(path), "estimates.json")
        if not os.path.exists(estimates):
            continue
        name = json.load(open(path)).get("full_id")
        e = json.load(open(estimates))
        found[name] = {
            "median_ns": e["median"]["point_estimate"],
            "slope_ns": (e.get("slope") or {}).get("point_estimate"),
            "when": time.strftime("%Y-%m-%d", time.gmtime(os.path.getmtime(estimates))),
        }
    return found


def duration(ns):
    if ns is None:
        return "–"
    for unit, scale in (("s", 1e9), ("ms", 1e6), ("µs", 1e3)):
        if ns >= scale:
            return f"{ns / scale:.3g} {unit}"
    return f"{ns:.3g} ns"


def bench_section(bench, per_road):
    out()
    out("## Benchmarks (criterion, one core)")
    out()
    out("Read from target/criterion/ as the last `cargo bench` left it; the date is when each was measured.")
    out()
    out("| benchmark | median | slope | measured | made by |")
    out("|---|---|---|---|---|")
    absent = []
    known = [name for name, _ in BENCHES]
    for name, command in BENCHES:
        b = bench.get(name)
        if b:
            out(f"| {name} | {duration(b['median_ns'])} | {duration(b['slope_ns'])} | {b['when']} | `{command}` |")
        else:
            absent.append((name, command))
    for name in sorted(set(bench) - set(known)):
        b = bench[name]
        out(f"| {name} | {duration(b['median_ns'])} | {duration(b['slope_ns'])} | {b['when']} | |")
    if absent:
        out()
        out("Not measured on this machine yet (run the command, then this script again; earlier "
            "sessions' measurements are in `docs/experiments/2026-11-22-speed-and-fidelity.md`):")
        out()
        for command in dict.fromkeys(c for _, c in absent):
            out(f"- `{command}`: " + ", ".join(n for n, c in absent if c == command))
    derived = []
    # Real time: a reference road's simulated seconds against its benched wall time.
    for oracle in ["beamng-ai-proxy", "dave2-proxy"]:
        b = bench.get(f"simulate one roads.jsonl road ({oracle})")
        if b and oracle in per_road:
            sim_s = median([r["sim_time_s"] for r in per_road[oracle]])
            derived.append(f"one reference road, {oracle}: {duration(b['median_ns'])}, "
                           f"{sim_s * 1e9 / b['median_ns']:,.0f}x real time")
    # Where a dave2-proxy drive's time goes: frames (10 Hz control) times the per-frame costs.
    drive, render, infer = (bench.get(n) for n in ("simulate one roads.jsonl road (dave2-proxy)",
                                                    "camera/render_gray_66x200", "dave2/inference"))
    if drive and render and infer and "dave2-proxy" in per_road:
        frames = median([r["sim_time_s"] for r in per_road["dave2-proxy"]]) * 10
        r_ms, i_ms = render["median_ns"] * frames / 1e6, infer["median_ns"] * frames / 1e6
        derived.append(f"a dave2-proxy drive ({frames:.0f} frames): rendering {r_ms:.0f} ms, "
                       f"inference {i_ms:.0f} ms, the rest (physics, oracle) {drive['median_ns'] / 1e6 - r_ms - i_ms:.0f} ms")
    # The competition's validator timed itself on each reference road (ref_seconds).
    v = bench.get("validator/per 6-point WOGAN road")
    if v:
        ref = [r["ref_seconds"] for r in read_jsonl("tests/reference/validator.jsonl") if len(r["road_points"]) == 6]
        if ref:
            derived.append(f"validating a 6-point road: {duration(v['median_ns'])} against the competition's "
                           f"{duration(median(ref) * 1e9)} (its own timing, `ref_seconds`): {median(ref) * 1e9 / v['median_ns']:,.0f}x")
    if derived:
        out()
        out("Derived from the estimates above and the reference roads:")
        out()
        for d in derived:
            out(f"- {d}")


# ---------------------------------------------------------------------------------------------
# The bench commands that are not criterion's: the most expensive work the settings' ranges
# accept (one road, one drive, one WOGAN round) and the streaming filters' latency. Each is run
# by hand (minutes, for the DAVE-2 corner) with its output kept in target/bench-output/NAME.txt.
BENCH_COMMANDS = [
    ("road-sim-corners", "cargo bench -p road-sim --bench corners"),
    ("wogan-core-corners", "cargo bench -p wogan-core --bench corners"),
    ("streaming", "cargo bench -p wogan-cli --bench streaming"),
]


def bounds_section():
    out()
    out("## Bounds and streaming (bench commands)")
    out()
    out("The most expensive setting each range accepts (docs/reference.md, \"Valid ranges\"), and the "
        "time from a line written to `simulate`/`validate` to its answer. Each line is the command's "
        "own output, kept with the date it was made:")
    out()
    for name, command in BENCH_COMMANDS:
        path = f"target/bench-output/{name}.txt"
        if not os.path.exists(path):
            out(f"- not measured yet: `{command} | tee {path}`")
            continue
        when = datetime.datetime.fromtimestamp(os.path.getmtime(path), datetime.timezone.utc)
        lines = [l.strip() for l in open(path) if l.startswith(("validator corner", "drive corner",
                                                                    "wogan corner", "wogan "))]
        for line in lines:
            out(f"- {line} ({when:%Y-%m-%d}; `{command}`)")


# ---------------------------------------------------------------------------------------------
# The built-in driver's training: 8-9 minutes, so it is read from a saved output line rather than
# rerun here.
def find_key(obj, key):
    if isinstance(obj, dict):
        if key in obj:
            return obj[key]
        for v in obj.values():
            found = find_key(v, key)
            if found is not None:
                return found
    return None


def training_section():
    path = os.environ["TRAIN_LOG"]
    out()
    out("## Training dave2-proxy (`wogan train-driver` at its defaults)")
    out()
    if not os.path.exists(path):
        out(f"No saved training output at `{path}`. Make it with "
            f"`wogan train-driver --seed 1 --out target/results/dave2.bin > {path}` "
            "(the defaults trained the built-in weights; on another CPU they train a different student); "
            "the figures of an earlier session are below.")
        return False
    record = next((json.loads(l) for l in open(path) if l.strip().startswith("{")), {})
    when = time.strftime("%Y-%m-%d", time.gmtime(os.path.getmtime(path)))
    out(f"From `{path}` (written {when}): steering error on unseen roads "
        f"{num(find_key(record, 'student_rmse_deg'), 2)}° (best constant steering "
        f"{num(find_key(record, 'constant_rmse_deg'), 2)}°, untrained network "
        f"{num(find_key(record, 'untrained_rmse_deg'), 2)}°), {num((find_key(record, 'seconds') or 0) / 60, 1)} minutes.")
    # Whether this machine's training gave the built-in weights: the same seed does on the same
    # CPU, but gemm blocks its sums by the caches it detects (docs/reference.md).
    weights, built_in = record.get("weights"), "crates/road-sim/weights/dave2-proxy.bin"
    if weights and os.path.exists(weights):
        same = open(weights, "rb").read() == open(built_in, "rb").read()
        out()
        out(f"The weights it wrote (`{weights}`) are " + ("bit for bit the built-in ones." if same else
            "not the built-in ones: this CPU rounds the training's matrix products differently from "
            "the one that trained them. Measure their failure rates with `scripts/driver_rates.sh "
            f"dave2-proxy \"\" {weights}`."))
    return True


# ---------------------------------------------------------------------------------------------
# What this script cannot regenerate, kept so that it is not lost, and labelled as such.
def earlier_section(trained):
    out()
    out("## Figures from earlier sessions, not regenerated by this script")
    out()
    out("Source: `docs/experiments/2026-11-22-speed-and-fidelity.md` (2026-11-21 and 2026-11-22, "
        "a 2-core machine); they are not re-measured by `scripts/results.sh`.")
    out()
    out("- BOLP and lane distance of a car rectangle against the competition's shapely code: within "
        "1e-12 (`cargo test --release --test end_to_end reference_vectors -- --nocapture` prints it).")
    out("- A cold build: 10–20 minutes on 2 cores.")
    out("- dave2-proxy, one reference road: the host's speed varied by 10–25% between sessions with the "
        "same code (medians of 135, 175 and 152 ms on one day), all inside the 250 ms bound.")
    out("- One WOGAN iteration with the generator used before 2026-11-22 (not the authors' layout): "
        "14.0 / 14.7 / 13.3 / 15.2 ms at 300 / 3,000 / 30,000 / 100,000 tests.")
    if not trained:
        out("- `wogan train-driver` at its defaults: about 8.5 minutes; steering error on unseen roads "
            "0.29° (best constant steering 4.33°, untrained network 4.32°).")
    out()
    out("## The paper's figures, for comparison (not measured here)")
    out()
    out("Peltomäki, Spencer, Porres (SBST 2022), BeamNG.AI, 2 h of BeamNG per run, 20 runs: failing "
        "roads 31.3 (WOGAN) against 8.7 (random); diversity 11.5 against 16.4; generation time per "
        "test 5.1 s for WOGAN (146.7 ms of it without the validity checks, on a desktop GPU) "
        "against 0.5 s for random search.")


# ---------------------------------------------------------------------------------------------
# Every section, in page order: its name (for ONLY=...) and what writes it.
def sections(bench):
    state = {}

    def reference_roads():
        state["per_road"] = reference_roads_section(bench)

    def benches():
        bench_section(bench, state.get("per_road") or reference_roads_section_quiet())

    def training():
        state["trained"] = training_section()

    return [
        ("search", search_section),
        ("comparisons", comparisons_section),
        ("sbst", sbst_section),
        ("field", field_section),
        ("sbst-preset", sbst_preset_section),
        ("metadrive", metadrive_section),
        ("keras", keras_section),
        ("generator", generator_section),
        ("ci", ci_section),
        ("plug-points", plug_points_section),
        ("rounds", rounds_section),
        ("every-core", every_core_section),
        ("campaigns", campaigns_section),
        ("reference-roads", reference_roads),
        ("long-roads", long_roads_section),
        ("fidelity", fidelity_section),
        ("benches", benches),
        ("bounds", bounds_section),
        ("training", training),
        ("earlier", lambda: earlier_section(state.get("trained"))),
    ]


def reference_roads_section_quiet():
    """The reference roads' timings without writing their section (benches alone)."""
    kept = len(lines)
    per_road = reference_roads_section(criterion())
    del lines[kept:]
    return per_road


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


def keep_other_oracles(old_block, fresh_block):
    """`fresh_block` with the `### ` subsections of `old_block` that it lacks kept in their places:
    with ORACLES narrowed, a section's other drivers are not regenerated, not dropped."""
    _, old_subs = split(old_block, "### ")
    intro, fresh_subs = split(fresh_block, "### ")
    by_heading = {b[0]: b for b in fresh_subs}
    merged = [by_heading.pop(b[0], b) for b in old_subs] + list(by_heading.values())
    return intro + joined(merged)


def joined(blocks):
    """The lines of `blocks`, each ended by exactly one blank line."""
    for block in blocks:
        while block and block[-1] == "":
            block.pop()
        block.append("")
    return [line for block in blocks for line in block]


def splice(old_text, new_lines, stamp, narrowed):
    """`old_text` with each `## ` section of `new_lines` put in place of the one of that heading
    (or, when it has none, before the earlier sessions' section), and `stamp` under the header;
    when `narrowed` (ORACLES names fewer than every driver), the old section's subsections of the
    drivers not regenerated are kept."""
    head, blocks = split(old_text.split("\n"), "## ")
    _, fresh = split(new_lines, "## ")
    by_heading = {b[0]: b for b in fresh}
    if narrowed:
        by_heading = {h: keep_other_oracles(next((b for b in blocks if b[0] == h), []), b)
                      for h, b in by_heading.items()}
    merged = [by_heading.pop(b[0], b) for b in blocks]
    at = next((i for i, b in enumerate(merged) if b[0].startswith("## Figures from earlier")), len(merged))
    merged[at:at] = list(by_heading.values())
    while head and head[-1] == "":
        head.pop()
    head += [stamp, ""]
    return "\n".join(head + joined(merged)).rstrip("\n") + "\n"


def main():
    m = machine()
    bench = criterion()
    only = [name for name in os.environ.get("ONLY", "").split(",") if name]
    chosen = sections(bench)
    unknown = [name for name in only if name not in dict(chosen)]
    if unknown:
        sys.exit(f"results.sh: ONLY names no section: {', '.join(unknown)} (sections: {', '.join(n for n, _ in chosen)})")
    if only:
        for name, write in chosen:
            if name in only:
                write()
        narrowed = set(ORACLES) != set(ALL_ORACLES)
        oracles = f"ORACLES={' '.join(ORACLES)} " if narrowed else ""
        stamp = (f"- sections {', '.join(only)} regenerated on {m['date']} (commit {m['commit']}"
                 f"{' with local changes' if m['dirty'] else ''}; `{oracles}ONLY={','.join(only)} "
                 f"scripts/results.sh`)")
        with open(os.environ["OUT"]) as f:
            text = splice(f.read(), lines, stamp, narrowed)
        with open(os.environ["OUT"], "w") as f:
            f.write(text)
        print(f"results.sh: regenerated {', '.join(only)} in {os.environ['OUT']}", file=sys.stderr)
        return
    out("# Results")
    out()
    out("Generated by `scripts/results.sh` (do not edit by hand; run it again). "
        "Experiment logs, with what was decided from these figures: `docs/experiments/`.")
    out()
    out(f"- date: {m['date']}")
    out(f"- machine: {m['uname']}, {m['cores']} cores, {m['cpu']}, {m['mem']}; load average at the start {m['load']}")
    out(f"- code: commit {m['commit']}{' with local changes' if m['dirty'] else ''}; binary `{WOGAN}` ({m['wogan']})")
    out("- regenerate: `scripts/results.sh` (after `cargo build --release -p wogan-cli`; "
        "`WOGAN=PATH` chooses another binary); `ONLY=generator,ci scripts/results.sh` "
        "regenerates those sections in place")
    if os.environ.get("MISSING"):
        out()
        out("**Run files missing** (the tables below leave them out; make them as `scripts/results.sh` prints):")
        out()
        for line in os.environ["MISSING"].splitlines():
            out(f"- {line}")
    out()
    for _, write in chosen:
        write()
    with open(os.environ["OUT"], "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"results.sh: wrote {os.environ['OUT']}", file=sys.stderr)

main()
PY
