#!/usr/bin/env python3
"""Reference vectors for the paper's diversity, made by the WOGAN authors' own measure.

Development-time only: CI reads the committed JSON file and needs neither stgem nor the pipeline.

    git -C <mirror of mshaheryarmalik/stgem> archive HEAD \
        problems/sbst/sbst_results_analysis.sync.py problems/sbst/util.py | tar -x -C /tmp/stgem
    python3 scripts/reference/stgem_diversity_vectors.py --stgem /tmp/stgem \
        --pipeline <checkout of se2p/tool-competition-av> \
        --out tests/reference/wogan/diversity.json

The measure is `euclidean_diversity` of stgem's `problems/sbst/sbst_results_analysis.sync.py`
(with its helper `move_road`), called as the authors' notebook calls it (75 points, every test
counted as failing). The notebook loads experiment results at top level, so the two functions
are taken out of its syntax tree and run alone, as scripts/reference/stgem_vectors.py takes the
SBST parameters; the curvature roads are made by stgem's own `test_to_road_points`, taken out
the same way. Roads are interpolated by the competition pipeline's `_interpolate`, as stgem's
SUT records the interpolated points of each executed road.

The file holds `roads` (interpolated points, each with how it was made), `pairs` (the measure
over two roads: their distance) and `groups` (the measure over several roads: the median of
their pairwise distances).
"""

import argparse
import ast
import itertools
import json
import math
import os
import random
import sys
import types

import numpy as np

ANALYSIS = os.path.join("problems", "sbst", "sbst_results_analysis.sync.py")
UTIL = os.path.join("problems", "sbst", "util.py")


def stgem_measure(stgem_dir):
    """stgem's `euclidean_diversity`, with the `move_road` it calls, out of the notebook."""
    path = os.path.join(stgem_dir, ANALYSIS)
    tree = ast.parse(open(path).read())
    namespace = {"np": np, "math": math, "itertools": itertools}
    wanted = {"move_road", "euclidean_diversity"}
    nodes = [n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name in wanted]
    assert {n.name for n in nodes} == wanted, f"{path} lacks one of {wanted}"
    exec(compile(ast.Module(body=nodes, type_ignores=[]), path, "exec"), namespace)
    return namespace["euclidean_diversity"]


class _Test:
    """What the measure reads of a test: its interpolated points as a (2, N) signal."""

    def __init__(self, points):
        self.input_denormalized = np.array(points, dtype=float).T


class _Repository:
    """A test repository of roads that all failed (objective 0, below any threshold)."""

    def __init__(self, roads):
        self.roads = roads

    def get(self):
        return [_Test(r) for r in self.roads], None, [0.0] * len(self.roads)


def stgem_road_points(stgem_dir):
    """stgem's `test_to_road_points` (problems/sbst/util.py: curvature values to road points, the
    authors' SBST road), out of its module, which imports the pipeline and shapely at top level.
    Its `np.math` is gone from numpy 2, so `np` is given as the little of numpy it uses."""
    path = os.path.join(stgem_dir, UTIL)
    tree = ast.parse(open(path).read())
    nodes = [n for n in tree.body
             if isinstance(n, ast.FunctionDef) and n.name == "test_to_road_points"]
    assert nodes, f"{path} lacks test_to_road_points"
    numpy_used = types.SimpleNamespace(math=math, cos=np.cos, sin=np.sin)
    namespace = {"np": numpy_used}
    exec(compile(ast.Module(body=nodes, type_ignores=[]), path, "exec"), namespace)
    return namespace["test_to_road_points"]


def roads(interpolate, road_points, rng):
    """(how it was made, interpolated points) for roads of many kinds: straight and curling
    further than half a revolution either way, of the paper's length and longer, short ones of
    fewer points than the measure picks, and lengths whose picked indices fall on halves."""
    made = []
    for values, step_m, count in [(5, 15.0, 6), (16, 10.0, 8), (22, 10.0, 6)]:
        for _ in range(count):
            curvature = [rng.uniform(-0.07, 0.07) for _ in range(values)]
            made.append((f"{values} random curvature values {step_m:g} m apart",
                         road_points(np.array(curvature), step_m, 200)))
    # Curling: one long bend either way, further than half a revolution from the start.
    for sign in (1, -1, 1, -1):
        values = [sign * rng.uniform(0.04, 0.05) for _ in range(20)]
        made.append(("one bend past half a revolution",
                     road_points(np.array(values), 10.0, 200)))
    made.append(("straight", [(100.0, 10.0), (100.0, 60.0), (100.0, 140.0)]))
    made.append(("short: fewer points than picked", [(100.0, 10.0), (101.0, 25.0), (108.0, 38.0)]))
    result = [(kind, [list(p[:2]) for p in interpolate(points)]) for kind, points in made]
    # Polylines of 38 and 112 points, whose picked indices i x 37/74 and i x 111/74 land on
    # halves: numpy rounds those to even.
    for n in (38, 112):
        angle, x, y, line = 0.3, 50.0, 50.0, []
        for _ in range(n):
            line.append([x, y])
            angle += rng.uniform(-0.2, 0.2)
            x, y = x + math.sin(angle), y + math.cos(angle)
        result.append((f"{n} points 1 m apart, picked indices on halves", line))
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--stgem", required=True, help="stgem checkout (problems/sbst at least)")
    parser.add_argument("--pipeline", required=True, help="se2p/tool-competition-av checkout")
    parser.add_argument("--out", required=True, help="JSON file to write")
    args = parser.parse_args()
    measure = stgem_measure(args.stgem)
    sys.path.insert(0, os.path.abspath(args.pipeline))
    from code_pipeline.tests_generation import _interpolate

    rng = random.Random(20221127)
    made = roads(_interpolate, stgem_road_points(args.stgem), rng)
    lines = [points for _, points in made]
    pairs = [
        [i, j, float(measure(_Repository([lines[i], lines[j]]), 75, 0.05))]
        for i, j in itertools.combinations(range(len(lines)), 2)
    ]
    groups = []
    for size in (3, 4, 7, 10, len(lines)):
        members = sorted(rng.sample(range(len(lines)), size))
        groups.append({
            "roads": members,
            "median": float(measure(_Repository([lines[i] for i in members]), 75, 0.05)),
        })
    out = {
        "source": f"stgem {ANALYSIS}: euclidean_diversity(repository, 75, 0.05)",
        "roads": [{"kind": kind, "interpolated_points": points} for kind, points in made],
        "pairs": pairs,
        "groups": groups,
    }
    with open(args.out, "w") as file:
        json.dump(out, file)
        file.write("\n")
    print(f"{args.out}: {len(made)} roads, {len(pairs)} pairs, {len(groups)} groups")


if __name__ == "__main__":
    main()
