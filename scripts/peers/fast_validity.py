"""The competition pipeline's road validity check, the same verdicts in a fraction of the time.

The pipeline's `RoadPolygon.is_valid` (self_driving/road_polygon.py) cuts the road into one
polygon per metre and compares every polygon with every other one in Python: equality, containment
both ways, and intersection (or, for neighbours, the type of the intersection). A 200 m road is
40,000 pairs, three or four GEOS calls each, and the validator runs it twice per test: about a
second per road on this machine, most of a peer run's time.

Two changes, neither of which can change a verdict:

* `Polygon.__eq__` through WKB. Shapely 1.8 compares two polygons in Python (type, then the
  coordinate tuples of every ring); for the pipeline's 2-D polygons the WKB of two polygons is equal
  exactly when those are.
* Pairs whose bounding boxes are apart are skipped, except neighbours. Such a pair cannot be equal,
  cannot contain one another and cannot intersect, so for a non-neighbouring pair every test of the
  original loop is false and the loop goes on; neighbours are always visited, since their check
  fails when they do not touch. The pairs that remain are visited in the original order, so the
  first failing pair (or assertion) is the same one.

`python fast_validity.py --check ROADS.jsonl ...` runs both versions on every road of the given
files (lines with `road_points`, e.g. a peer run's tests.jsonl) and counts disagreements; it needs
the pipeline on PYTHONPATH.
"""
import argparse
import json
import sys
import time

import numpy as np
from shapely.geometry import Polygon

_ORIGINAL_EQ = Polygon.__eq__


def _polygon_eq(self, other):
    if type(other) is not type(self):
        return False
    if self.has_z or other.has_z:
        return _ORIGINAL_EQ(self, other)
    return self.wkb == other.wkb


def _is_valid(self) -> bool:
    """RoadPolygon.is_valid with the pairs that cannot fail skipped (see the module's doc)."""
    from shapely.geometry import LineString

    if self.num_polygons == 0:
        return False
    for polygon in self.polygons:
        if not polygon.is_valid:
            return False
    boxes = np.array([p.bounds for p in self.polygons], dtype=float).reshape(-1, 4)
    for i, polygon in enumerate(self.polygons):
        min_x, min_y, max_x, max_y = boxes[i]
        near = ((boxes[:, 0] <= max_x) & (boxes[:, 2] >= min_x)
                & (boxes[:, 1] <= max_y) & (boxes[:, 3] >= min_y))
        near[max(i - 1, 0):i + 2] = True
        for j in np.flatnonzero(near):
            j = int(j)
            other = self.polygons[j]
            if other == polygon:
                assert i == j
                continue
            if polygon.contains(other) or other.contains(polygon):
                return False
            neighbours = self._are_neighbouring_polygons(i, j)
            if not neighbours and other.intersects(polygon):
                return False
            if neighbours and not isinstance(other.intersection(polygon), LineString):
                return False
    return True


def install():
    """Patches Shapely's Polygon equality and the pipeline's RoadPolygon.is_valid."""
    from self_driving.road_polygon import RoadPolygon

    Polygon.__eq__ = _polygon_eq
    Polygon.__hash__ = None  # as Shapely 1.8 has it: Polygon defines __eq__, so it is unhashable
    RoadPolygon._original_is_valid = RoadPolygon.is_valid
    RoadPolygon.is_valid = _is_valid


def check(paths):
    """Both validators on every road of `paths`; returns (roads, disagreements, seconds of each)."""
    from code_pipeline.tests_generation import RoadTestFactory
    from code_pipeline.validation import TestValidator

    validator = TestValidator(map_size=200)
    roads, disagreements, seconds = 0, 0, [0.0, 0.0]
    for path in paths:
        with open(path) as lines:
            for number, line in enumerate(lines, 1):
                points = json.loads(line).get("road_points")
                if not points:
                    continue
                verdicts = []
                for patched in (False, True):
                    (install if patched else _uninstall)()
                    test = RoadTestFactory.create_road_test([tuple(p) for p in points])
                    started = time.perf_counter()
                    try:
                        verdicts.append(validator.validate_test(test))
                    except AssertionError as error:
                        verdicts.append(("assertion", str(error)))
                    seconds[patched] += time.perf_counter() - started
                roads += 1
                if verdicts[0] != verdicts[1]:
                    disagreements += 1
                    print(f"{path}:{number}: original {verdicts[0]}, fast {verdicts[1]}")
    return roads, disagreements, seconds


def _uninstall():
    from self_driving.road_polygon import RoadPolygon

    Polygon.__eq__ = _ORIGINAL_EQ
    if hasattr(RoadPolygon, "_original_is_valid"):
        RoadPolygon.is_valid = RoadPolygon._original_is_valid


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", nargs="+", required=True, metavar="ROADS.jsonl")
    roads, disagreements, seconds = check(parser.parse_args().check)
    print(f"{roads} roads, {disagreements} disagreements; validation {seconds[0]:.1f} s as the "
          f"pipeline has it, {seconds[1]:.1f} s fast ({seconds[0] / max(seconds[1], 1e-9):.1f}x)")
    sys.exit(1 if disagreements else 0)
