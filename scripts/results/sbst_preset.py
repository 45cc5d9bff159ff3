"""Section `sbst-preset`: `--preset sbst` against the field and the paper's WOGAN under the
competition's budgets.
"""

from common import ORACLES, out
from field import (
    OURS,
    PEERS,
    compared,
    kept_note,
    kept_row,
    page_commit,
    page_tables,
    peer_runs,
    runs_of,
)


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
        "scripts/runs/sbst_budget_runs.sh ORACLE \"$(seq -s ' ' 1 20)\" 1h 2h`): means per run, "
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
            out(f"Runs missing: `ALGORITHMS=preset-sbst scripts/runs/sbst_budget_runs.sh {oracle} ...`.")
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
