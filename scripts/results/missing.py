"""Which search runs are missing, and the commands that make them: a missing run is never silently
left out of a median."""

import os

ALL_SEEDS = " ".join(str(seed) for seed in range(1, 21))


def missing_runs(oracles, seeds, settings):
    """`ORACLE TAG seeds N...` for each setting with absent run files, so that a missing run is
    never silently left out of a median."""
    missing = []
    for oracle in oracles:
        for tag, algorithm in settings:
            absent = [s for s in seeds if not os.path.isfile(f"target/effectiveness/{oracle}.{tag}.{algorithm}.{s}.jsonl")]
            if absent:
                missing.append(f"{oracle} {tag} seeds {' '.join(absent)}")
        absent = [s for s in seeds if not os.path.isfile(f"target/stgem/{oracle}.stgem.{s}.jsonl")]
        if absent:
            missing.append(f"{oracle} stgem seeds {' '.join(absent)}")
    return missing


def how_to_make(missing, seeds):
    """The commands that make the `missing` runs: ours first (one script makes them all), then
    stgem's."""
    seeds_env = "" if " ".join(seeds) == ALL_SEEDS else f'SEEDS="{" ".join(seeds)}" '
    ours, stgem = [], []
    for line in missing:
        oracle, tag, _, *numbers = line.split()
        if tag == "stgem":
            stgem.append(f"  python3 scripts/reference/stgem_search.py --oracle {oracle} --seeds {','.join(numbers)}"
                         "   # needs torch and a stgem checkout: see the script")
        else:
            ours.append(f"  {seeds_env}ORACLES={oracle} SETS={tag} scripts/runs/search_figures.sh")
    return ours + stgem
