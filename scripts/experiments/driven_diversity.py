#!/usr/bin/env python3
"""How much of a run's diversity lies in road that was driven: the paper's measure per run, whole
roads and driven parts.

Development-time only (docs/experiments/2026-11-27-diversity-guard.md). The paper's diversity is
the median distance between a run's failing roads' heading profiles (75 points by arc length over
the whole road). The competition's executor ends a test at the first lane exit, so the road past it
was never driven: two failing roads that agree up to the exit and part after it are the same
failure, yet the whole-road measure counts them apart. This script gives, per run and averaged over
a group's runs, that measure (as `wogan report` computed it until 2026-11-27, with the headings
unwrapped; the authors' own measure wraps them, docs/reference.md) beside the same measure over the
driven part: a pair of failing roads is compared up to 30 m past the later of its two lane exits
(the competition's OOB segment reach), the profile values beyond adding nothing.

    python3 scripts/experiments/driven_diversity.py \\
        "AdaFrenetic=target/peers/dave2-proxy.adafrenetic.*[0-9]/" \\
        "wogan --preset sbst=target/sbst/dave2-proxy.preset-sbst.*.jsonl" \\
        --pipeline ~/peers/pipeline

A group is NAME=GLOB: a glob of result folders (`test.NNNN.json`: `interpolated_points`, and the
exit is the `pos` of the first `execution_data` record with `is_oob`) or of `wogan run` files
(`road_points` interpolated by the pipeline's own `_interpolate`, imported from a checkout, and
the test's `oob` point). A run of more than `--max-failures` failing roads is measured on a fixed
random sample of that many. Needs numpy (the peers' venv has it).
"""

import argparse
import glob
import json
import os
import sys

import numpy as np

from failure_profiles import arc_lengths, failing_tests, heading_profile, interpolated_points

# Road compared past a lane exit, metres (the competition's OOB segment reach).
REACH_M = 30.0
# `execution_data` record field holding `is_oob` (the pipeline's SimulationDataRecord order).
IS_OOB_FIELD = 12


def arc_length_nearest(line, point):
    """Arc length of the point of `line` nearest `point`."""
    best, at = (float("inf"), 0.0), 0.0
    for a, b in zip(line, line[1:]):
        a, b = np.asarray(a, float), np.asarray(b, float)
        d = b - a
        length = float(np.hypot(*d))
        t = 0.0 if length == 0 else float(np.clip(np.dot(np.asarray(point) - a, d) / length**2, 0, 1))
        gap = float(np.hypot(*(a + t * d - point)))
        if gap < best[0]:
            best = (gap, at + t * length)
        at += length
    return best[1]


def failures(path, interpolate):
    """(interpolated road, exit point or None) of each failing test of a run file or folder."""
    for test, in_run_file in failing_tests(path):
        if in_run_file:
            if test.get("beyond_budget"):
                # Past the budget: not one of the run's tests (`wogan report` skips it).
                continue
            oob = test.get("oob")
            road = [p[:2] for p in interpolate(test["road_points"])]
            yield road, (oob["x"], oob["y"]) if oob else None
            continue
        records = test["execution_data"]
        records = json.loads(records) if isinstance(records, str) else records
        exit_point = next((r[1][:2] for r in records if r[IS_OOB_FIELD]), None)
        yield [p[:2] for p in interpolated_points(test)], exit_point


def driven_values(road, exit_point, values):
    """How many profile values (segments, by their start) lie within REACH_M past the exit."""
    if exit_point is None:
        return values
    total = arc_lengths(road)[-1]
    reached = arc_length_nearest(road, exit_point) + REACH_M
    return sum(1 for i in range(values) if total * i / values <= reached)


def run_figures(path, interpolate, max_failures):
    """(failing roads, whole-road median, driven-part median, median driven share) of a run."""
    roads = list(failures(path, interpolate))
    count = len(roads)
    if count > max_failures:
        keep = np.random.RandomState(0).choice(count, max_failures, replace=False)
        roads = [roads[i] for i in sorted(keep)]
    if len(roads) < 2:
        return None
    profiles = np.array([heading_profile(road) for road, _ in roads])
    values = profiles.shape[1]
    driven = np.array([driven_values(road, exit_point, values) for road, exit_point in roads])
    whole, driven_part = pair_distances(profiles, driven)
    return count, float(np.median(whole)), float(np.median(driven_part)), float(np.median(driven)) / values


def pair_distances(profiles, driven):
    """(whole-road, driven-part) Euclidean distance of every pair of `profiles` (one row per road),
    `driven` giving each road's count of driven profile values (driven_values)."""
    values = profiles.shape[1]
    squared = (profiles[:, None, :] - profiles[None, :, :]) ** 2
    # A pair is compared up to the later of its two exits (+ REACH_M).
    reach = np.maximum(driven[:, None], driven[None, :])
    within = np.arange(values)[None, None, :] < reach[:, :, None]
    pairs = np.triu_indices(len(profiles), 1)
    return np.sqrt(squared.sum(-1))[pairs], np.sqrt((squared * within).sum(-1))[pairs]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("groups", nargs="+", help="NAME=GLOB")
    parser.add_argument("--max-failures", type=int, default=300)
    parser.add_argument("--pipeline", required=True,
                        help="checkout of se2p/tool-competition-av (its code_pipeline)")
    args = parser.parse_args()
    sys.path.insert(0, os.path.abspath(os.path.expanduser(args.pipeline)))
    from code_pipeline.tests_generation import _interpolate
    print("| group | runs | failing roads per run | diversity, whole roads (the paper's) "
          "| diversity, driven parts | share of a failing road driven |")
    print("|---|---|---|---|---|---|")
    for group in args.groups:
        name, pattern = group.split("=", 1)
        rows = [run_figures(path, _interpolate, args.max_failures)
                for path in sorted(glob.glob(pattern))]
        rows = np.array([row for row in rows if row is not None])
        if len(rows) == 0:
            print(f"| {name} | 0 | – | – | – | – |")
            continue
        count, whole, driven, share = rows.mean(axis=0)
        print(f"| {name} | {len(rows)} | {count:.1f} | {whole:.1f} | {driven:.1f} | {share:.2f} |")


if __name__ == "__main__":
    main()
