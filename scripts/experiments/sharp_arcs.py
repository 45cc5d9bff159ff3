#!/usr/bin/env python3
"""How long the sharp arcs of a road family run: per road, the longest stretch of the interpolated
centre line whose curvature stays above a bound, and the share of roads where it reaches a length.

A driver that fails per sharp bend fails long roads of many bends more often than WOGAN's 75 m
roads; one that failed only on long sustained arcs would not, if 75 m roads held more of them.
This measures whether they do (docs/experiments/2026-11-23-drivers-on-long-roads.md).

    python3 scripts/experiments/sharp_arcs.py tests/reference/roads.jsonl tests/reference/peer_roads_dev.jsonl
    target/release/wogan run --algorithm random --curvature-points 12 --max-tests 300 --seed 1 \
        --out long.jsonl && python3 scripts/experiments/sharp_arcs.py long.jsonl

Roads are read by `wogan validate --details` (its interpolated centre line), so any form it reads
works; a file with a "generator" field per road is split by it. Curvature is that of the circle
through the centre-line points 3 m behind and ahead, on the line resampled every metre.
Standard library only; WOGAN names the binary (default target/release/wogan).
"""
import json
import math
import os
import subprocess
import sys

SHARP_PER_M = 0.05
LENGTHS_M = (20, 30, 40)
HALF_CHORD_M = 3


def resample(points, step_m=1.0):
    """The polyline's points every `step_m` metres of arc length."""
    out = [points[0]]
    carried = 0.0
    for (x0, y0), (x1, y1) in zip(points, points[1:]):
        length = math.hypot(x1 - x0, y1 - y0)
        s = step_m - carried
        while s <= length:
            t = s / length
            out.append((x0 + t * (x1 - x0), y0 + t * (y1 - y0)))
            s += step_m
        carried = length - (s - step_m)
    return out


def curvature(a, b, c):
    """Unsigned curvature of the circle through three points, 1/m."""
    cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    sides = math.dist(a, b) * math.dist(b, c) * math.dist(c, a)
    return 2 * abs(cross) / sides if sides > 0 else 0.0


def longest_sharp_arc_m(points):
    """Longest run of 1 m steps whose curvature exceeds SHARP_PER_M, metres."""
    line = resample(points)
    h = HALF_CHORD_M
    longest = run = 0
    for i in range(h, len(line) - h):
        run = run + 1 if curvature(line[i - h], line[i], line[i + h]) > SHARP_PER_M else 0
        longest = max(longest, run)
    return longest


def families(path, wogan):
    """{family label: [longest sharp arc per valid road]} for one file of roads."""
    with open(path) as f:
        lines = [line for line in f if line.strip()]
    roads = [json.loads(line) for line in lines]
    if roads and roads[0].get("type") == "header":
        lines = [line for line, road in zip(lines, roads) if road.get("type") == "test"]
        roads = [road for road in roads if road.get("type") == "test"]
    verdicts = subprocess.run(
        [wogan, "validate", "--details", "-"], input="".join(lines), text=True,
        capture_output=True, check=True,
    ).stdout.splitlines()
    out = {}
    for road, verdict in zip(roads, map(json.loads, verdicts)):
        if not verdict["valid"]:
            continue
        label = road.get("generator", os.path.basename(path))
        centre = verdict["interpolated_points"]
        out.setdefault(label, []).append(longest_sharp_arc_m(centre))
    return out


def main():
    wogan = os.environ.get("WOGAN", "target/release/wogan")
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    shares = "  ".join(f"{f'>= {n} m':>7}" for n in LENGTHS_M)
    print(f"longest arc with curvature above {SHARP_PER_M}/m, per road: median, max, share of roads")
    print(f"{'family':<28} {'roads':>5}  {'median':>6}  {'max':>4}  {shares}")
    for path in sys.argv[1:]:
        for label, arcs in families(path, wogan).items():
            arcs.sort()
            cells = "  ".join(
                f"{100 * sum(a >= n for a in arcs) / len(arcs):6.1f}%" for n in LENGTHS_M
            )
            print(f"{label:<28} {len(arcs):>5}  {arcs[len(arcs) // 2]:>4} m  {arcs[-1]:>2} m  {cells}")


if __name__ == "__main__":
    main()
