"""Section `metadrive-calibration`: how often MetaDrive's subjects fail the SBST 2022 entries' roads
(tests/reference/peer_roads_dev.jsonl), per speed limit and executor setting, from the saved
per-road answers of scripts/experiments/executor_rates.py (target/results/metadrive_rates.*.jsonl).

A file's name says the executor's options: `metadrive_rates.POLICY[-OPTION-VALUE...].jsonl`, e.g.
`metadrive_rates.expert-friction-0.4.jsonl` is `--policy expert --wheel-friction 0.4`; its rows
say the speed limit (from `hello`, wogan's `--speed-limit`) and the road's generator.
"""

import glob
import os
from collections import Counter, defaultdict

from common import out, read_jsonl

RATES = "target/results/metadrive_rates.{}.jsonl"
# A file name's option words and the executor's options they stand for.
OPTIONS = {"friction": "--wheel-friction", "lane": "--lane-width"}
FAMILIES = ("ambiegen", "freneticv", "random_generator")
# The speed limit chosen for `--policy idm` (docs/experiments/2026-12-07-metadrive-calibration.md).
CALIBRATED_IDM_KMH = 46


def executor_options(tag):
    """The executor's options of a file's tag (`expert-friction-0.4`), or None if it names none."""
    policy, *rest = tag.split("-")
    if len(rest) % 2 or any(word not in OPTIONS for word in rest[::2]):
        return None
    return " ".join([f"--policy {policy}"] + [f"{OPTIONS[w]} {v}" for w, v in zip(rest[::2], rest[1::2])])


def rate(failed, roads):
    return f"{100 * failed / roads:.1f}% ({failed}/{roads})" if roads else "–"


def rows_of(path):
    """{speed: (failed per family, roads per family, failures by reason, largest max BOLP)} of one
    file."""
    by_speed = defaultdict(lambda: (Counter(), Counter(), Counter(), [0.0]))
    for row in read_jsonl(path):
        failed, roads, reasons, bolp = by_speed[row["speed_limit_kmh"]]
        bolp[0] = max(bolp[0], row.get("max_bolp") or 0.0)
        roads[row["generator"]] += 1
        if row["outcome"] == "FAIL":
            failed[row["generator"]] += 1
            # Rows written before the script saved the reason: a drive ends at its first BOLP past
            # the tolerance (0.85 here), so a larger max BOLP is a lane exit.
            reason = row.get("reason") or ("out_of_lane" if (row.get("max_bolp") or 0) > 0.85 else "not recorded")
            reasons[reason] += 1
    return by_speed


def table_row(first, failed, roads, reasons, bolp):
    every = sum(roads.values())
    whole = rate(sum(failed.values()), every) if all(roads[f] for f in FAMILIES) else "–"
    cells = [whole] + [rate(failed[f], roads[f]) for f in FAMILIES]
    why = ", ".join(f"{r.replace('_', ' ')} {c}" for r, c in sorted(reasons.items())) or "–"
    return f"| {first} | " + " | ".join(cells) + f" | {why} | {bolp[0]:.2f} |"


def metadrive_calibration_section():
    out()
    out("## MetaDrive's subjects calibrated")
    out()
    files = {os.path.basename(p)[len("metadrive_rates."):-len(".jsonl")]: p
             for p in sorted(glob.glob(RATES.format("*")))}
    files = {tag: p for tag, p in files.items() if executor_options(tag)}
    if not files:
        out("No saved rates on this machine: make them with `python3 scripts/experiments/executor_rates.py "
            f"--speeds 45 46 47 --out {RATES.format('idm')} -- target/metadrive-venv/bin/python "
            "examples/metadrive/executor.py --policy idm` (the other settings: "
            "docs/experiments/2026-12-07-metadrive-calibration.md).")
        return
    out("As wogan's own drivers were (\"The drivers on long roads of the competition's kind\"): a subject "
        "must fail a BeamNG.AI-like share, 8–20%, of the SBST 2022 entries' roads (the 900 of "
        "`tests/reference/peer_roads_dev.jsonl`; beamng-ai-proxy fails 13.3% of them, BeamNG.AI about "
        "10–13%) before it can judge a search. Each road driven by `examples/metadrive/executor.py` "
        "(MetaDrive 0.4.3, headless) at the speed limit of the row, tolerance 0.85, map 200 m: "
        "`python3 scripts/experiments/executor_rates.py --speeds KMH... --out "
        f"{RATES.format('TAG')} -- target/metadrive-venv/bin/python examples/metadrive/executor.py OPTIONS` "
        "(saved per-road answers, read here; TAG names the options, `expert-friction-0.4` for "
        "`--policy expert --wheel-friction 0.4`; `--generator ambiegen` drives AmbieGen's 300 only, "
        "`--limit N` the first N). "
        "A rate of the whole set (\"all\") only where all three generators' roads were driven; "
        "failures by the executor's `reason`. What was decided, and the rates of other speeds "
        "measured without saved per-road files (IDM: 5.6% of the 900 at 45 km/h, 17.3% at 47; 74% of "
        "300 at 70): docs/experiments/2026-12-07-metadrive-calibration.md.")
    out()
    out(f"The calibrated IDM: `wogan run --speed-limit {CALIBRATED_IDM_KMH} --executor "
        "cmd:\"target/metadrive-venv/bin/python examples/metadrive/executor.py --policy idm\"`: the "
        "speed inside 8–20% nearest beamng-ai-proxy's 13.3%. `--policy expert` cannot be calibrated by "
        "a setting a user would plausibly choose (its table: speed, `--wheel-friction`, "
        "`--lane-width`): at 70 km/h it leaves its lane on none of AmbieGen's roads and its few "
        "failures are stalls (`not moving`) on a slippery road; it fails more only above 80 km/h, where "
        "the executor raises the car's top speed to the limit and the expert, reading its speed as a "
        "share of it, speeds up, and then mostly by stalling after a slide. The searches of "
        "\"A real simulator: MetaDrive\" above ran at 70 km/h, uncalibrated.")
    for policy in sorted({tag.split("-")[0] for tag in files}, key=lambda p: (p != "idm", p)):
        out()
        out(f"### `--policy {policy}`")
        out()
        out("| executor options, speed limit | all | ambiegen | freneticv | random_generator | failures by reason "
            "| largest max BOLP |")
        out("|---|---|---|---|---|---|---|")
        for tag in sorted((t for t in files if t.split("-")[0] == policy), key=lambda t: (t != policy, t)):
            for speed, (failed, roads, reasons, bolp) in sorted(rows_of(files[tag]).items()):
                first = f"`{executor_options(tag)}`, {speed:g} km/h"
                if policy == "idm" and speed == CALIBRATED_IDM_KMH and tag == policy:
                    first += " (calibrated)"
                out(table_row(first, failed, roads, reasons, bolp))
