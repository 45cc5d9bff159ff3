#!/usr/bin/env python3
"""Where the paper's diversity comes from: the authors' wrapped directions against true angles.

Development-time only (docs/experiments/2026-11-27-wrap-and-shape.md). The WOGAN authors' measure
(`wogan report`'s diversity; docs/reference.md, "Diversity") compares each road's segment
directions in (-pi, pi] as plain numbers, so two roads both heading nearly back the way they came
(directions near +pi and -pi) count as almost a whole turn apart. This prints, per group and as
means per run, the authors' measure beside the same median pairwise distance with each
direction difference taken as the angle between the two directions (folded into [-pi, pi]), the
same with the headings unwrapped, the share of direction samples within `--back-rad` of
heading back, and how the authors' pairs split: the share nearer than `--near` (near copies) and
the median of the others (docs/experiments/2026-11-27-random-between-niches.md). Roads are the
driven ones, as failure_profiles.py loads them (a run file's `road_points` through the
pipeline's `_interpolate`, a result folder's `interpolated_points`):

    python3 scripts/experiments/direction_measures.py --pipeline ~/peers/pipeline \
        "preset sbst=target/sbst/beamng-ai-proxy.preset-sbst.*.jsonl" \
        "AmbieGen=target/peers/beamng-ai-proxy.ambiegen.*/"

A GLOB matching `NAME.N.log` files is filtered to run files and result folders.
"""

import argparse
import glob
import math
import os
import statistics
import sys

import numpy as np

from failure_profiles import failing_roads

POINTS = 75


def authors_directions(line):
    """The authors' description: 75 points picked by index (numpy rounds half to even), turned
    so the first segment points north, each segment's direction atan2(dx, dy)."""
    line = np.asarray(line, dtype=float)[:, :2]
    last = len(line) - 1
    picked = line[[int(np.round(i * last / (POINTS - 1))) for i in range(POINTS)]]
    picked = picked - picked[0]
    first = picked[1]
    angle = math.pi / 2 - math.atan2(first[1], first[0])
    cos, sin = math.cos(angle), math.sin(angle)
    turned = np.stack([cos * picked[:, 0] - sin * picked[:, 1],
                       sin * picked[:, 0] + cos * picked[:, 1]], axis=1)
    steps = np.diff(turned, axis=0)
    return np.arctan2(steps[:, 0], steps[:, 1])


def pairwise(profiles, fold):
    """The Euclidean distance of every pair of profiles; with `fold`, each difference is first
    taken as the angle between the two directions."""
    distances = []
    for i in range(len(profiles) - 1):
        differences = profiles[i + 1:] - profiles[i]
        if fold:
            differences = (differences + np.pi) % (2 * np.pi) - np.pi
        distances.extend(np.sqrt((differences ** 2).sum(axis=1)))
    return np.array(distances)


def median_pairwise(profiles, fold):
    """Median over pairs of the Euclidean distance between two profiles (as `pairwise`)."""
    return statistics.median(pairwise(profiles, fold))


def run_paths(pattern):
    return [p for p in sorted(glob.glob(pattern)) if not p.endswith(".log")]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("groups", nargs="+", help="NAME=GLOB of run files or result folders")
    parser.add_argument("--pipeline", required=True,
                        help="checkout of se2p/tool-competition-av (its code_pipeline)")
    parser.add_argument("--back-rad", type=float, default=0.5)
    parser.add_argument("--near", type=float, default=10.0,
                        help="authors' distance under which a pair counts as near copies")
    args = parser.parse_args()
    sys.path.insert(0, os.path.abspath(os.path.expanduser(args.pipeline)))
    from code_pipeline.tests_generation import _interpolate
    print("| group | runs | failures a run | the authors' measure | angles between directions "
          f"| headings unwrapped | direction samples within {args.back_rad:g} rad of heading back "
          f"| pairs nearer than {args.near:g} | median of the other pairs |")
    print("|---|---|---|---|---|---|---|---|---|")
    for group in args.groups:
        name, pattern = group.split("=", 1)
        rows = []
        for path in run_paths(pattern):
            roads = [[p[:2] for p in _interpolate(road)] if raw else road
                     for road, raw in failing_roads(path, False)]
            if len(roads) < 2:
                continue
            profiles = np.array([authors_directions(r) for r in roads])
            unwrapped = np.unwrap(profiles, axis=1)
            back = float((np.abs(profiles) > math.pi - args.back_rad).mean())
            authors = pairwise(profiles, False)
            near = authors < args.near
            others = float(np.median(authors[~near])) if (~near).any() else 0.0
            rows.append((len(roads), float(np.median(authors)),
                         median_pairwise(profiles, True), median_pairwise(unwrapped, False), back,
                         float(near.mean()), others))
        if not rows:
            print(f"| {name} | 0 | | | | | | | |")
            continue
        means = [statistics.mean(column) for column in zip(*rows)]
        print(f"| {name} | {len(rows)} | {means[0]:.1f} | {means[1]:.1f} | {means[2]:.1f} "
              f"| {means[3]:.1f} | {means[4]:.2f} | {means[5]:.2f} | {means[6]:.1f} |")


if __name__ == "__main__":
    main()
