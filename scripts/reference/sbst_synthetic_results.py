#!/usr/bin/env python3
"""Synthetic result directories in the SBST 2022 pipeline's layout, for sbst_oob_vectors.py.

Development-time only. Needs a checkout of se2p/tool-competition-av (its resampling places the
out-of-bound points) with numpy, scipy, shapely and matplotlib installed:

    python3 scripts/reference/sbst_synthetic_results.py --pipeline /work/tca --out /tmp/sbst_oob_synthetic

Each directory holds `test.NNNN.json` files as the pipeline writes them (`id`, `is_valid`,
`validation_message`, `road_points`, `test_outcome`, `description`, `execution_data` as lists of
the 17 values of `SimulationDataRecordProperties`). A failed test's execution data is three
records: one on the road, the out-of-bound point (the first `is_oob` record, the one the
analysis uses) and a later `is_oob` record elsewhere. Everything is drawn from one seed.

Directories (the `error_*` and `failed_*` ones hold tests whose OOB processing fails in the
pipeline, which makes its sparseness computation raise as soon as such a test meets another):
  peer_roads       roads of FreneticV and AmbieGen (/work/shared/reference/peer_roads_dev.jsonl)
  wogan_roads      WOGAN's 6-point roads (/work/shared/reference/roads.jsonl)
  edge_cases       straight and bent hand-made roads: distances of exactly 2 m, points before the
                   start and past the end, a nearest point just after a sample, a repeated test id
  single_oob       one OOB among passed tests: no pairs, so no sparseness
  no_oobs          passed, invalid, errored tests and a FAIL without any is_oob record
  error_short_road a FAIL on a 3-point road (the spline needs 4) among good OOBs
  error_no_vertex_near  a nearest road point 0.5 m from both neighbouring samples
  error_tiny_road  a FAIL on a road shorter than 1 m (the resampling divides by zero)
  failed_alone     the 3-point road is the only OOB: counted, no pairs
  failed_without_oob   a FAIL on a 3-point road with no is_oob record: the resampling raises
                   before the record is looked at, so it is counted as an OOB all the same
"""

import argparse
import json
import math
import os
import random
import shutil
import sys

ROAD_FILES = {
    "peer": "/work/shared/reference/peer_roads_dev.jsonl",
    "wogan": "/work/shared/reference/roads.jsonl",
}


def record(timer, pos, is_oob, oob_counter):
    """One execution record: the 17 values of SimulationDataRecordProperties, in order."""
    return [
        timer,  # timer
        [pos[0], pos[1], -28.0],  # pos
        [0.0, 1.0, 0.0],  # dir
        [0.0, 10.0, 0.0],  # vel
        0.0,  # steering
        0.0,  # steering_input
        0.0,  # brake
        0.0,  # brake_input
        0.5,  # throttle
        0.5,  # throttle_input
        10.0,  # wheelspeed
        36.0,  # vel_kmh
        is_oob,  # is_oob
        oob_counter,  # oob_counter
        0.0,  # max_oob_percentage
        -1.0 if is_oob else 1.0,  # oob_distance
        0.0,  # oob_percentage
    ]


class Writer:
    """Writes the tests of one directory, numbering files and ids from 1."""

    def __init__(self, root, name):
        self.dir = os.path.join(root, name)
        os.makedirs(self.dir)
        self.next_id = 1

    def test(self, road_points, outcome, records=(), valid=True, test_id=None):
        number = self.next_id
        self.next_id += 1
        obj = {
            "id": number if test_id is None else test_id,
            "is_valid": valid,
            "validation_message": "" if valid else "Not entirely inside the map boundaries",
            "road_points": [list(p) for p in road_points],
            "test_outcome": outcome,
            "description": {
                "FAIL": "Car drove out of the lane ",
                "PASS": "Successful test",
                "ERROR": "Simulation error",
                "INVALID": "Not entirely inside the map boundaries",
            }[outcome],
            "execution_data": list(records),
        }
        with open(os.path.join(self.dir, "test.%04d.json" % number), "w") as f:
            json.dump(obj, f)

    def fail(self, road_points, oob, later=None, test_id=None):
        """A FAIL whose first is_oob record is at `oob`."""
        start = road_points[0]
        later = later or [oob[0] + 1.0, oob[1] + 1.0]
        records = [
            record(0.0, start, False, 0),
            record(0.5, oob, True, 1),
            record(1.0, later, True, 1),
        ]
        self.test(road_points, "FAIL", records, test_id=test_id)

    def fail_without_oob(self, road_points):
        self.test(road_points, "FAIL", [record(0.0, road_points[0], False, 0)])

    def passed(self, road_points):
        self.test(road_points, "PASS", [record(0.0, road_points[0], False, 0)])


class Pipeline:
    """The pipeline's resampling and segment search, to place points and to check them."""

    def __init__(self, path):
        sys.path.insert(0, path)
        from code_pipeline.tests_evaluation import RoadTestEvaluator, _interpolate_and_resample_splines
        from self_driving.simulation_data import SimulationDataRecord

        self.resample = lambda road: [(p[0], p[1]) for p in _interpolate_and_resample_splines(road)]
        self.evaluator = RoadTestEvaluator(road_length_before_oob=30, road_lengrth_after_oob=30)
        self.record = SimulationDataRecord

    def processes(self, road, oob):
        """Whether the pipeline finds an interesting segment for an OOB at `oob`."""
        try:
            self.evaluator.identify_interesting_road_segments(
                road, [self.record(*record(0.0, oob, True, 1))]
            )
            return True
        except Exception:
            return False


def along(coords, s, offset):
    """The point `offset` metres to the left of the polyline `coords`, `s` metres along it."""
    for a, b in zip(coords, coords[1:]):
        length = math.dist(a, b)
        if length > 0 and s <= length:
            t = s / length
            ux, uy = (b[0] - a[0]) / length, (b[1] - a[1]) / length
            return [a[0] + t * (b[0] - a[0]) - offset * uy, a[1] + t * (b[1] - a[1]) + offset * ux]
        s -= length
    a, b = coords[-2], coords[-1]
    length = math.dist(a, b)
    ux, uy = (b[0] - a[0]) / length, (b[1] - a[1]) / length
    return [b[0] - offset * uy, b[1] + offset * ux]


def offsets(rng, count):
    """Lateral offsets (left positive) over -7..+3 m, with some at the 2 m threshold."""
    fixed = [-2.0, -1.99, 1.99, 2.01, -2.01, 2.0, 0.0, -4.0]
    drawn = [round(rng.uniform(-7.0, 3.0), 3) for _ in range(count - len(fixed))]
    values = fixed + drawn
    rng.shuffle(values)
    return values


def good_oob(pipeline, rng, road, offset):
    """An OOB `offset` metres beside a random place of the road that the pipeline can process."""
    coords = pipeline.resample(road)
    length = sum(math.dist(a, b) for a, b in zip(coords, coords[1:]))
    for _ in range(200):
        point = along(coords, rng.uniform(0.0, length), offset)
        point = [round(point[0], 6), round(point[1], 6)]
        if pipeline.processes(road, point):
            return point
    raise RuntimeError("no processable OOB point found")


def road_directory(pipeline, rng, root, name, roads):
    """FAILs with OOBs on most roads, and a few PASS, ERROR, INVALID and OOB-less FAIL tests."""
    w = Writer(root, name)
    kinds = ["fail"] * (len(roads) - 6) + ["pass"] * 3 + ["error", "invalid", "fail_without_oob"]
    rng.shuffle(kinds)
    offs = iter(offsets(rng, kinds.count("fail")))
    for road, kind in zip(roads, kinds):
        if kind == "fail":
            w.fail(road, good_oob(pipeline, rng, road, next(offs)))
        elif kind == "pass":
            w.passed(road)
        elif kind == "error":
            w.test(road, "ERROR", [record(0.0, road[0], False, 0)])
        elif kind == "invalid":
            w.test(road, "INVALID", [], valid=False)
        else:
            w.fail_without_oob(road)


STRAIGHT = [[50.0, 10.0], [50.0, 30.0], [50.0, 50.0], [50.0, 70.0]]
BENT = [[100.0, 10.0], [100.0, 25.0], [104.0, 39.5], [115.0, 50.0], [130.0, 53.0], [145.0, 50.0]]
THREE_POINTS = [[100.0, 10.0], [100.0, 60.0], [130.0, 90.0]]
TINY = [[20.0, 20.0], [20.2, 20.0], [20.4, 20.1], [20.5, 20.3]]


def edge_cases(pipeline, root):
    w = Writer(root, "edge_cases")
    # Straight road x = 50, samples at every metre of y: distances of exactly 2 m are RIGHT.
    w.fail(STRAIGHT, [52.0, 30.0])  # nearest point is the sample (50, 30) itself
    w.fail(STRAIGHT, [48.0, 40.4])  # distance 2 m; nearest point 0.4 m past a sample
    w.fail(STRAIGHT, [51.9999, 45.3])  # just under 2 m: LEFT
    w.fail(STRAIGHT, [50.0, 5.0])  # before the start: nearest point is the first sample
    w.fail(STRAIGHT, [50.0, 80.0])  # past the end: nearest point is the last sample
    w.fail(STRAIGHT, [50.3, 40.7])  # nearest point within 0.5 m of the next sample only
    w.passed(STRAIGHT)
    # A bend: outside it the nearest point is a sample, inside it is on a segment.
    coords = pipeline.resample(BENT)
    for s, offset in [(20.0, -5.0), (30.0, 5.0), (36.5, -6.5), (44.0, 2.5), (12.0, -1.0)]:
        point = along(coords, s, offset)
        w.fail(BENT, [round(point[0], 6), round(point[1], 6)])
    # Two files with one test id: sparseness keeps one maximum per id.
    w.fail(STRAIGHT, [54.5, 60.0], test_id=3)
    w.fail(BENT, [round(c, 6) for c in along(coords, 25.0, -4.5)], test_id=3)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--pipeline", required=True, help="checkout of se2p/tool-competition-av")
    parser.add_argument("--out", default="/tmp/sbst_oob_synthetic")
    parser.add_argument("--seed", type=int, default=2022)
    parser.add_argument("--roads", type=int, default=36, help="tests per road directory")
    args = parser.parse_args()

    pipeline = Pipeline(args.pipeline)
    rng = random.Random(args.seed)
    if os.path.exists(args.out):
        shutil.rmtree(args.out)
    os.makedirs(args.out)

    def roads(kind, min_points):
        with open(ROAD_FILES[kind]) as f:
            lines = [json.loads(line) for line in f if line.strip()]
        usable = [l["road_points"] for l in lines if len(l["road_points"]) >= min_points]
        return rng.sample(usable, args.roads)

    road_directory(pipeline, rng, args.out, "peer_roads", roads("peer", 4))
    road_directory(pipeline, rng, args.out, "wogan_roads", roads("wogan", 4))
    edge_cases(pipeline, args.out)

    w = Writer(args.out, "single_oob")
    w.passed(STRAIGHT)
    w.fail(STRAIGHT, [53.0, 33.3])
    w.passed(BENT)

    w = Writer(args.out, "no_oobs")
    w.passed(STRAIGHT)
    w.test(BENT, "INVALID", [], valid=False)
    w.test(BENT, "ERROR", [record(0.0, BENT[0], False, 0)])
    w.fail_without_oob(STRAIGHT)

    w = Writer(args.out, "error_short_road")
    w.fail(STRAIGHT, [47.0, 20.2])
    w.fail(THREE_POINTS, [104.0, 40.0])
    w.fail(BENT, [104.0, 30.0])

    w = Writer(args.out, "error_no_vertex_near")
    w.fail(STRAIGHT, [47.0, 20.2])
    w.fail(STRAIGHT, [48.0, 40.5])  # nearest point (50, 40.5): 0.5 m from both samples
    w.fail(BENT, [104.0, 30.0])

    w = Writer(args.out, "error_tiny_road")
    w.fail(TINY, [20.3, 22.0])
    w.fail(STRAIGHT, [47.0, 20.2])

    w = Writer(args.out, "failed_alone")
    w.passed(STRAIGHT)
    w.fail(THREE_POINTS, [104.0, 40.0])

    w = Writer(args.out, "failed_without_oob")
    w.fail_without_oob(THREE_POINTS)
    w.passed(STRAIGHT)

    print("wrote", ", ".join(sorted(os.listdir(args.out))), "under", args.out)


if __name__ == "__main__":
    main()
