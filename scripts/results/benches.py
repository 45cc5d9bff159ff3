"""Sections `bench`, `bounds`, `ci`, `plug-points`, `every-core` and `campaigns`: criterion's
estimates and the saved output of the bench scripts (target/bench-output/, scripts/bench/).
"""

import datetime
import glob
import json
import os
import time

from common import median, out, read_jsonl


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
    saved_bench_section("CI commands", "scripts/bench/ci_bench.sh", "ci")


def plug_points_section():
    saved_bench_section("Plug points", "scripts/bench/plug_points_bench.sh", "plug-points")


def every_core_section():
    saved_bench_section("Every core (`--jobs`)", "scripts/bench/parallel_bench.sh", "parallel")


def ray_section():
    saved_bench_section("Ray", "scripts/bench/ray_bench.sh", "ray")
    out()
    out("The sleeping pools are driven through the executor protocol by the script itself, as wogan "
        "drives an executor (hello, then up to `roads_at_once` roads in flight, matched by id): the "
        "clock runs from the reply to hello (the actors started) to the last answer; the dispatch "
        "overhead is the wall time of a road per actor (wall x actors / roads) minus the 1 s sleep. "
        "Each pool is a private Ray (`--address local`, `--actor-cpus 0.05`) in a loopback-only "
        "network namespace. The MetaDrive pair runs the same 60 roads both ways (same outcomes); "
        "Ray's start, paid once per run, is in its time, and on 2 shared cores the two ways are "
        "within the machine's noise of each other.")


def report_section():
    saved_bench_section("`wogan report` on large runs", "scripts/bench/report_bench.sh", "report")
    out()
    out("Each copy of a seeded run's failing tests is turned about the map's centre by its own "
        "angle, so that no two lane exits are alike. Before the measures were bounded (the "
        "hostile-input report of 2026-11-29, at commit 5cb33d3), 5,000 such tests took 138 s and "
        "100,000 wrote nothing in 600 s: the competition's OOB sparseness compares every pair. It "
        "now measures every pair up to 1,000 OOBs and a seeded sample of 1,000 above, distinct "
        "failures a seeded 20,000, the diversity 1,000,000 seeded pairs (docs/reference.md, "
        "`wogan report`); what is left grows with the run's size (reading, building each road).")


def campaigns_section():
    saved_bench_section("Campaigns", "scripts/bench/campaign_bench.sh", "campaigns")


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
        saved = [text.strip() for text in open(path)
                 if text.startswith(("validator corner", "drive corner", "wogan corner", "wogan "))]
        for line in saved:
            out(f"- {line} ({when:%Y-%m-%d}; `{command}`)")
