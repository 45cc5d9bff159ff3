#!/usr/bin/env python3
"""How varied failing roads are as a road family: the paper's diversity pooled over runs.

Development-time only (docs/experiments/2026-11-26-field-20-runs.md). `wogan report` gives the
paper's diversity per run: the median distance between one run's failing roads, which a search that
exploits a region lowers. Pooling failures of many independent runs (or only those of wogan's
random phase, which no search shaped) measures instead what the road family's failures allow at
best (the headings unwrapped, as `wogan report` measured until 2026-11-27; the authors' own measure
wraps them, docs/reference.md). For each group it prints the pooled median over whole roads (the
heading profile: 75 points by arc length, heading relative to the first segment), the same
over each road's first `--first-m` metres only (so that roads of different lengths compare alike),
and the median failing road length; with `--plot`, a picture of the groups' heading profiles (needs
matplotlib, as the peers' venv has). Every road is the one driven, as `wogan report` profiles it: a
result folder's `interpolated_points`, and a `wogan run` file's `road_points` interpolated by the
competition pipeline's own `_interpolate` (imported from a checkout, `--pipeline`; wogan's roads
agree with it, tests/reference), so that both sides are smoothed alike:

    python3 scripts/experiments/failure_profiles.py \
        "AdaFrenetic=target/peers/dave2-proxy.adafrenetic.*/" \
        "wogan random phase=random:target/sbst/dave2-proxy.preset-sbst.*.jsonl" \
        --pipeline ~/peers/pipeline --plot profiles.png

A group is NAME=GLOB: a glob of result folders (`test.NNNN.json`, their `interpolated_points`) or
of `wogan run` files; `random:` before a run-file glob keeps only tests of the random phase. A
group of more than `--max-roads` failing roads is measured (and drawn) on a fixed random sample of
that many; the table gives the number before sampling.
"""

import argparse
import glob
import json
import math
import os
import random
import statistics
import sys

PROFILE_POINTS = 75


def arc_lengths(line):
    total = [0.0]
    for a, b in zip(line, line[1:]):
        total.append(total[-1] + math.dist(a, b))
    return total


def resample(line, count, length=None):
    """`count` points evenly spaced by arc length over the first `length` metres (all of it
    when None), as `wogan report`'s heading profile resamples."""
    cumulative = arc_lengths(line)
    length = cumulative[-1] if length is None else length
    points, segment = [], 0
    for i in range(count):
        target = length * i / (count - 1)
        while segment + 2 < len(line) and cumulative[segment + 1] < target:
            segment += 1
        span = cumulative[segment + 1] - cumulative[segment]
        t = min(1.0, max(0.0, (target - cumulative[segment]) / span)) if span > 0 else 0.0
        a, b = line[segment], line[segment + 1]
        points.append((a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])))
    return points


def heading_profile(line, length=None):
    """Unwrapped headings of the resampled segments relative to the first, radians."""
    points = resample(line, PROFILE_POINTS, length)
    profile, previous, unwrapped = [], None, 0.0
    for a, b in zip(points, points[1:]):
        heading = math.atan2(b[1] - a[1], b[0] - a[0])
        if previous is not None:
            turn = heading - previous
            unwrapped += turn - math.tau * round(turn / math.tau)
        previous = heading
        profile.append(unwrapped)
    return profile


def interpolated_points(test):
    points = test["interpolated_points"]
    return json.loads(points) if isinstance(points, str) else points


def failing_tests(path):
    """Each failing test of one run file or result folder: its record (a run file's test line or
    a folder's `test.NNNN.json`) and whether it is a run file's."""
    if path.endswith(".jsonl"):
        with open(path) as lines:
            for line in lines:
                record = json.loads(line)
                if record.get("type") == "test" and record.get("outcome") == "FAIL":
                    yield record, True
        return
    for name in sorted(glob.glob(path.rstrip("/") + "/test.*.json")):
        with open(name) as file:
            test = json.load(file)
        if test.get("test_outcome") == "FAIL":
            yield test, False


def failing_roads(path, random_phase_only):
    """The failing roads of one run file or result folder, each with whether it is a run file's
    road points, still to be interpolated."""
    for test, in_run_file in failing_tests(path):
        if not in_run_file:
            yield interpolated_points(test), False
        elif not random_phase_only or test.get("phase") == "random":
            yield test["road_points"], True


def median_pairwise(profiles):
    distances = [math.dist(a, b) for i, a in enumerate(profiles) for b in profiles[i + 1:]]
    return statistics.median(distances) if distances else float("nan")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("groups", nargs="+", help="NAME=GLOB, GLOB possibly prefixed random:")
    parser.add_argument("--first-m", type=float, default=130.0)
    parser.add_argument("--max-roads", type=int, default=400)
    parser.add_argument("--pipeline", required=True,
                        help="checkout of se2p/tool-competition-av (its code_pipeline)")
    parser.add_argument("--plot", help="write a picture of the heading profiles to this PNG")
    args = parser.parse_args()
    sys.path.insert(0, os.path.abspath(os.path.expanduser(args.pipeline)))
    from code_pipeline.tests_generation import _interpolate
    print("| group | runs | failing roads | pooled diversity, whole roads "
          f"| pooled diversity, first {args.first_m:g} m | failing road length (m) |")
    print("|---|---|---|---|---|---|")
    plotted = []
    for group in args.groups:
        name, pattern = group.split("=", 1)
        random_phase_only = pattern.startswith("random:")
        pattern = pattern.removeprefix("random:")
        paths = sorted(glob.glob(pattern))
        roads = [road for path in paths for road in failing_roads(path, random_phase_only)]
        failing = len(roads)
        # Sampled before interpolating: a search's thousands of failures cost minutes each.
        if len(roads) > args.max_roads:
            roads = random.Random(0).sample(roads, args.max_roads)
        roads = [[p[:2] for p in _interpolate(road)] if raw else road for road, raw in roads]
        lengths = [arc_lengths(road)[-1] for road in roads]
        long_enough = [road for road, length in zip(roads, lengths) if length >= args.first_m]
        profiles = [heading_profile(r) for r in roads]
        whole = median_pairwise(profiles)
        first = median_pairwise(
            [heading_profile(r, args.first_m) for r in long_enough])
        length = statistics.median(lengths) if lengths else float("nan")
        print(f"| {name} | {len(paths)} | {failing} | {whole:.1f} | {first:.1f} | {length:.0f} |")
        plotted.append((name, profiles, lengths, failing))
    if args.plot:
        plot(plotted, args.plot)


def plot(groups, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    columns = 2
    rows = (len(groups) + columns - 1) // columns
    figure, axes = plt.subplots(rows, columns, figsize=(7 * columns, 4.5 * rows), squeeze=False)
    for axis, (name, profiles, lengths, failing) in zip(axes.flat, groups):
        for profile, length in zip(profiles, lengths):
            steps = len(profile)
            axis.plot([length * (i + 0.5) / steps for i in range(steps)], profile,
                      color="C0", alpha=0.3, linewidth=0.7)
        shown = "" if len(profiles) == failing else f" (a sample of {len(profiles)} drawn)"
        axis.set_title(f"{name}: {failing} failing roads{shown}")
        axis.set_xlabel("arc length (m)")
        axis.set_ylabel("heading relative to the first segment (rad)")
    for axis in list(axes.flat)[len(groups):]:
        axis.axis("off")
    figure.tight_layout()
    figure.savefig(path, dpi=70)


if __name__ == "__main__":
    main()
