#!/usr/bin/env python3
"""How far a run's failing roads turn, and the paper's diversity of those that turn far.

Development-time only (docs/experiments/2026-11-28-winding-roads.md). Per group, means per run:
the failing roads a run has; the share of them heading within 0.64 rad of back at the middle of
the road (the authors' direction of their 38th segment, in magnitude above 2.5 rad); the median
over a run's failing roads of their largest turn from their first heading (the authors'
directions unwrapped, in magnitude); and, for the run's failures turning at least T (each
`--turns` value; 0 is every failure), how many there are and the paper's diversity of them, on
whole roads and over the road driven (a pair compared up to 30 m past the later of its two lane
exits, as driven_diversity.py does, here over the authors' directions). Roads and exits are read
as driven_diversity.py reads them (a run file through the pipeline's own `_interpolate`, a result
folder's `interpolated_points`):

    python3 scripts/experiments/winding_failures.py --pipeline ~/peers/pipeline \
        "preset=target/sbst/dave2-proxy.preset-sbst.*.jsonl" \
        "AmbieGen=target/peers/dave2-proxy.ambiegen.*/"
"""

import argparse
import os
import statistics
import sys

import numpy as np

from direction_measures import authors_directions, run_paths
from driven_diversity import driven_values, failures, pair_distances

MIDDLE = 37
BACK_RAD = 2.5


def subset_figures(profiles, driven):
    """(failures, whole-road median, driven-part median) of the authors' profiles given."""
    whole, driven_part = pair_distances(profiles, driven)
    return len(profiles), float(np.median(whole)), float(np.median(driven_part))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("groups", nargs="+", help="NAME=GLOB of run files or result folders")
    parser.add_argument("--pipeline", required=True,
                        help="checkout of se2p/tool-competition-av (its code_pipeline)")
    parser.add_argument("--turns", default="0,2,2.5,3.14,4",
                        help="least turns T (radians, comma-separated)")
    args = parser.parse_args()
    sys.path.insert(0, os.path.abspath(os.path.expanduser(args.pipeline)))
    from code_pipeline.tests_generation import _interpolate
    turns = [float(t) for t in args.turns.split(",")]
    print("| group | runs | failures a run | heading back at the middle | median largest turn (rad) | "
          + " | ".join(f"turning ≥ {t:g}: failures, diversity whole / driven" for t in turns) + " |")
    print("|---|---|---|---|---|" + "---|" * len(turns))
    for group in args.groups:
        name, pattern = group.split("=", 1)
        runs = []
        for path in run_paths(pattern):
            roads = list(failures(path, _interpolate))
            if len(roads) < 3:
                continue
            profiles = np.array([authors_directions(road) for road, _ in roads])
            driven = np.array([driven_values(road, exit_point, profiles.shape[1])
                               for road, exit_point in roads])
            largest = np.abs(np.unwrap(profiles, axis=1)).max(axis=1)
            row = [len(roads), float((np.abs(profiles[:, MIDDLE]) > BACK_RAD).mean()),
                   float(np.median(largest))]
            for t in turns:
                keep = largest >= t
                row.append(subset_figures(profiles[keep], driven[keep]) if keep.sum() >= 3 else None)
            runs.append(row)
        if not runs:
            print(f"| {name} | 0 |" + " |" * (3 + len(turns)))
            continue
        cells = [f"{statistics.mean(r[0] for r in runs):.1f}",
                 f"{statistics.mean(r[1] for r in runs):.2f}",
                 f"{statistics.mean(r[2] for r in runs):.2f}"]
        for i in range(len(turns)):
            kept = [r[3 + i] for r in runs if r[3 + i] is not None]
            cells.append("–" if not kept else
                         f"{statistics.mean(k[0] for k in kept):.1f}, "
                         f"{statistics.mean(k[1] for k in kept):.2f} / "
                         f"{statistics.mean(k[2] for k in kept):.2f}")
        print(f"| {name} | {len(runs)} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
