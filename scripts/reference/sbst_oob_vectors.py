#!/usr/bin/env python3
"""Reference vectors for road-sim's `oob` module, made by the SBST 2022 pipeline's own code.

Development-time only: the Rust tests read the committed JSON and need no Python. Needs a
checkout of se2p/tool-competition-av and numpy, scipy, shapely and matplotlib:

    python3 scripts/reference/sbst_synthetic_results.py --pipeline /work/tca --out /tmp/sbst_oob_synthetic
    python3 scripts/reference/sbst_oob_vectors.py --pipeline /work/tca /tmp/sbst_oob_synthetic/*

Each positional argument is a result directory in the pipeline's layout (`test.NNNN.json` files
with `id`, `is_valid`, `test_outcome`, `road_points` and `execution_data`, e.g. the output of
`wogan export --format sbst`); the vectors are written to one JSON file (default
tests/reference/sbst/oob_vectors.json). For each directory they hold the inputs the analysis
reads (per test file, in the order the pipeline walks them) and what the pipeline answers:
`OOBAnalyzer`'s entries (side, interesting segment and, for a few, the resampled road), every
`iterative_levenshtein` call `_compute_sparseness` makes, its per-test maxima, `_analyse()`
and `create_summary()`, or the exception the analysis raised. Unit vectors come from the
functions of `self_driving/edit_distance_polyline.py` and from numpy and Python formatting.

Every answer is computed by the pipeline's code; this script only records calls and returns.
The one change: numpy 2 removed `np.NaN`, which `_compute_sparseness` returns when there are
no pairs, so `numpy.NaN` is set to `numpy.nan` (what it was in the numpy 1.x the pipeline was
written for) when it is missing. NaN is written as null in the JSON.
"""

import argparse
import itertools
import json
import logging
import math
import os
import random
import sys

RESAMPLED_ENTRIES = 5  # entries per directory whose resampled road is written
MAX_PAIRS = 5000  # distances per directory


def plain(value):
    """JSON-ready copy: numpy scalars to Python numbers, tuples to lists, NaN to None."""
    if isinstance(value, dict):
        return {k: plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if hasattr(value, "item") and not isinstance(value, (str, bytes)):
        value = value.item()
    if isinstance(value, float) and math.isnan(value):
        return None
    return value


def points(seq):
    return [[plain(p[0]), plain(p[1])] for p in seq]


def error_of(exc):
    return {"type": type(exc).__name__, "message": str(exc)}


class Pipeline:
    def __init__(self, path):
        sys.path.insert(0, path)
        import numpy

        try:
            numpy.NaN
            self.nan_shim = False
        except AttributeError:
            numpy.NaN = numpy.nan
            self.nan_shim = True
        import scipy
        import shapely
        from code_pipeline import tests_evaluation as te
        from self_driving import edit_distance_polyline as ed

        self.te = te
        self.ed = ed
        self.numpy = numpy
        self.versions = {
            "numpy": numpy.__version__,
            "scipy": scipy.__version__,
            "shapely": shapely.__version__,
            "geos": ".".join(map(str, shapely.geos_version)),
            "python": sys.version.split()[0],
        }
        logging.getLogger("OOBAnalyzer").setLevel(logging.ERROR)

    def test_files(self, directory):
        """The files OOBAnalyzer reads, in its order (os.walk, each folder's files sorted)."""
        files = []
        for subdir, _dirs, names in os.walk(directory, followlinks=False):
            files += sorted(
                os.path.join(subdir, f) for f in names if f.startswith("test.") and f.endswith(".json")
            )
        return files

    def inputs(self, directory, path):
        """What the analysis reads of one test file (as `_load_test_data` reads it)."""
        with open(path) as f:
            data = json.load(f)
        entry = {
            "file": os.path.relpath(path, directory),
            "id": data.get("id"),
            "is_valid": data.get("is_valid"),
            "test_outcome": data.get("test_outcome"),
            "road_points": points(data.get("road_points", [])),
            "oob_point": None,
        }
        try:
            _id, is_valid, _outcome, _road, execution_data = self.te.OOBAnalyzer._load_test_data(None, path)
        except Exception as exc:
            entry["load_error"] = error_of(exc)
            return entry
        if is_valid:
            for rec in execution_data:
                if rec.is_oob:
                    entry["oob_point"] = [plain(rec.pos[0]), plain(rec.pos[1])]
                    break
        return entry

    def directory(self, directory):
        te = self.te
        out = {"name": os.path.basename(os.path.normpath(directory))}
        files = self.test_files(directory)
        out["tests"] = [self.inputs(directory, f) for f in files]

        calls = []
        original = te.iterative_levenshtein

        def recording(s, t):
            calls.append(None)
            d = original(s, t)
            calls[-1] = d
            return d

        captured = {}

        def profiler(frame, event, arg):
            if event == "return" and frame.f_code is te.OOBAnalyzer._compute_sparseness.__code__:
                captured["max"] = list(frame.f_locals["max_distances_starting_from"].items())

        te.iterative_levenshtein = recording
        try:
            try:
                analyzer = te.OOBAnalyzer(directory)
            except Exception as exc:
                out["error"] = dict(error_of(exc), stage="load")
                return out
            out["entries"] = [self.entry(directory, i, o) for i, o in enumerate(analyzer.oobs)]
            analysed = {}
            analyse = analyzer._analyse

            def recording_analyse():
                analysed["value"] = analyse()
                return analysed["value"]

            analyzer._analyse = recording_analyse
            sys.setprofile(profiler)
            try:
                summary = analyzer.create_summary()
                out["error"] = None
            except Exception as exc:
                summary = None
                out["error"] = dict(error_of(exc), stage="summary")
            finally:
                sys.setprofile(None)
        finally:
            te.iterative_levenshtein = original

        n = len(analyzer.oobs)
        pairs = list(itertools.islice(itertools.combinations(range(n), 2), len(calls)))
        if out["error"] is not None and calls and calls[-1] is None:
            i, j = pairs[-1]
            out["error"]["pair"] = [plain(analyzer.oobs[i]["test id"]), plain(analyzer.oobs[j]["test id"])]
        out["pairs_total"] = n * (n - 1) // 2
        out["distances"] = [[i, j, plain(d)] for (i, j), d in zip(pairs, calls) if d is not None][:MAX_PAIRS]
        out["max_distances"] = [[plain(k), plain(v)] for k, v in captured["max"]] if "max" in captured else None
        if "value" in analysed:
            value = analysed["value"]
            out["analyse"] = {"sparseness": plain(value["sparseness"]), "oob_side": plain(value["oob_side"])}
        else:
            out["analyse"] = None
        out["summary_csv"] = summary
        return out

    def entry(self, directory, index, oob):
        e = {
            "test_id": plain(oob["test id"]),
            "file": os.path.relpath(oob["simulation file"], directory),
            "side": oob["oob side"],
            "oob_point": None if oob["oob point"] is None else [oob["oob point"].x, oob["oob point"].y],
            "segment": points(oob["interesting segment"]),
        }
        test_id, _valid, _outcome, road, execution_data = self.te.OOBAnalyzer._load_test_data(
            None, oob["simulation file"]
        )
        if oob["oob side"] is None:
            # The pipeline swallows the exception; run the same call again to name it.
            evaluator = self.te.RoadTestEvaluator(road_length_before_oob=30, road_lengrth_after_oob=30)
            try:
                evaluator.identify_interesting_road_segments(road, execution_data)
                e["error"] = None
            except Exception as exc:
                e["error"] = error_of(exc)
        if index < RESAMPLED_ENTRIES:
            try:
                e["resampled"] = points(self.te._interpolate_and_resample_splines(road))
            except Exception as exc:
                e["resampled_error"] = error_of(exc)
        return e

    def units(self):
        ed, np = self.ed, self.numpy
        rng = random.Random(7)
        out = {}

        costs = []
        pairs = [
            ((0.0, 1.0), (0.0, 1.0)),
            ((0.29, 1.0), (0.0, 1.1)),
            ((0.3, 1.0), (0.0, 1.0)),
            ((0.0, 1.2), (0.0, 1.0)),
            ((0.0, 1.19999), (0.0, 1.0)),
            ((0.1, 1.0), (0.3999, 1.1999)),
            ((-0.2, 2.0), (0.05, 2.1)),
            ((350.0, 1.0), (-10.0, 1.0)),
            ((179.0, 1.0), (-179.0, 1.0)),
            ((-179.0, 1.0), (179.0, 1.0)),
            ((540.0, 1.0), (0.0, 1.0)),
            ((720.0, 1.0), (0.0, 1.05)),
            ((360.2, 1.0), (0.0, 1.0)),
            ((-360.1, 1.0), (0.0, 1.0)),
            ((180.0, 0.0), (0.0, 3.0)),
            ((90.0, 5.0), (-90.0, 0.5)),
        ]
        for _ in range(40):
            pairs.append(
                (
                    (rng.uniform(-400, 400), rng.uniform(0, 3)),
                    (rng.uniform(-400, 400), rng.uniform(0, 3)),
                )
            )
        for u, v in pairs:
            costs.append({"u": list(u), "v": list(v), "cost": plain(ed._calc_cost_weighted(u, v))})
        out["cost"] = costs

        lists = [
            [[0.0, 0.0], [1.0, 0.0]],
            [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]],
            [[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [2.0, 1.0]],  # a repeated point: atan2(0, 0)
            [[0.0, 0.0], [-1.0, 0.01], [-2.0, -0.01], [-3.0, 0.02]],  # across the -x axis
            [[5.0, 5.0], [4.0, 5.5], [3.0, 5.0], [4.0, 4.5], [5.0, 5.0]],  # a loop
        ]
        for n in (3, 8, 20, 45):
            x, y, heading = rng.uniform(0, 200), rng.uniform(0, 200), rng.uniform(-math.pi, math.pi)
            pts = [[round(x, 4), round(y, 4)]]
            for _ in range(n - 1):
                heading += rng.uniform(-0.4, 0.4)
                step = rng.uniform(0.8, 1.3)
                x, y = x + step * math.cos(heading), y + step * math.sin(heading)
                pts.append([round(x, 4), round(y, 4)])
            lists.append(pts)
        out["dist_angle"] = [
            {"points": p, "angle_length": [[plain(a), plain(l)] for a, l in ed._calc_dist_angle(p)]} for p in lists
        ]
        lev = []
        for s, t in itertools.combinations_with_replacement(range(len(lists)), 2):
            lev.append({"s": lists[s], "t": lists[t], "distance": plain(ed.iterative_levenshtein(lists[s], lists[t]))})
        # Reversed and slightly moved copies of the same points.
        base = lists[-2]
        lev.append({"s": base, "t": base[::-1], "distance": plain(ed.iterative_levenshtein(base, base[::-1]))})
        moved = [[p[0] + 0.05, p[1] - 0.05] for p in base]
        lev.append({"s": base, "t": moved, "distance": plain(ed.iterative_levenshtein(base, moved))})
        out["levenshtein"] = lev
        too_short = []
        for s in ([], [[1.0, 1.0]]):
            try:
                ed.iterative_levenshtein(s, lists[0])
                too_short.append({"s": s, "error": None})
            except Exception as exc:
                too_short.append({"s": s, "error": error_of(exc)})
        out["levenshtein_errors"] = too_short

        roads = [
            [[100.0, 10.0], [100.0, 17.0], [100.0, 24.0], [100.0, 31.0]],  # 21 m: n + 2 samples
            [[100.0, 10.0], [100.0, 20.0], [100.0, 30.0], [100.0, 40.0]],
            [[0.0, 0.0], [10.0, 0.0], [20.0, 5.0]],  # 3 points
            [[1.0, 1.0]],  # 1 point: shapely refuses the line
            [],
            [[20.0, 20.0], [20.2, 20.0], [20.4, 20.1], [20.5, 20.3]],  # shorter than 1 m
            [[0.0, 0.0], [10.0, 0.0], [10.0, 0.0], [20.0, 5.0], [30.0, 0.0]],  # a repeated point
            [[10.0, 10.0], [30.0, 12.0], [45.0, 30.0], [50.0, 55.0], [70.0, 60.0]],
            [[100.0, 10.0], [100.0, 25.0], [104.0, 39.5], [115.0, 50.0], [130.0, 53.0], [145.0, 50.0]],
        ]
        resampled = []
        for road in roads:
            try:
                r = {"road_points": road, "resampled": points(self.te._interpolate_and_resample_splines(road))}
            except Exception as exc:
                r = {"road_points": road, "error": error_of(exc)}
            resampled.append(r)
        out["resample"] = resampled

        values = [0.0, 0.5, 1.5, 2.5, 3.5, 4.5, 0.125, 0.0625, 0.0005, 1.0005, 2.675, 12.3456, 999.5, 1000.5,
                  123456.5, 1e-7, 7.49999, 1e21, float("nan"), float("inf"), 0.25, 0.375, 10.0]
        values += [rng.uniform(0, 100) for _ in range(20)]
        out["format"] = [
            {"value": None if math.isnan(v) else (str(v) if math.isinf(v) else v),
             "f3": "%.3f" % v, "width3_f0": "%3.f" % v}
            for v in values
        ]

        stats = []
        for n in (1, 2, 3, 7, 8, 9, 15, 16, 17, 31, 127, 128, 129, 200, 257, 300):
            vals = [rng.uniform(0, 60) * (10 ** rng.randint(-2, 1)) for _ in range(n)]
            if n == 9:
                vals[3] = 4  # an int among floats, as a Levenshtein distance can be
            stats.append({"values": vals, "mean": plain(np.mean([vals])), "std": plain(np.std([vals]))})
        out["mean_std"] = stats
        return out


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--pipeline", required=True, help="checkout of se2p/tool-competition-av")
    parser.add_argument("--out", default="tests/reference/sbst/oob_vectors.json")
    parser.add_argument("directories", nargs="+", help="result directories (test.NNNN.json files)")
    args = parser.parse_args()

    pipeline = Pipeline(args.pipeline)
    vectors = {
        "made_by": "scripts/reference/sbst_oob_vectors.py",
        "pipeline": {
            "code": ["code_pipeline/tests_evaluation.py", "self_driving/edit_distance_polyline.py"],
            "numpy_nan_shim": pipeline.nan_shim,
            **pipeline.versions,
        },
        "directories": [],
        "units": pipeline.units(),
    }
    for d in args.directories:
        print("analysing", d, file=sys.stderr)
        vectors["directories"].append(pipeline.directory(d))
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, "w") as f:
        json.dump(plain(vectors), f, separators=(",", ":"), allow_nan=False)
        f.write("\n")
    for d in vectors["directories"]:
        err = d.get("error")
        print(
            "%-22s tests %3d entries %3d pairs %5d/%-5d %s"
            % (
                d["name"],
                len(d["tests"]),
                len(d.get("entries", [])),
                len(d.get("distances", [])),
                d.get("pairs_total", 0),
                repr(d.get("summary_csv")) if err is None else "error %s %s" % (err["type"], err.get("pair")),
            ),
            file=sys.stderr,
        )
    print("wrote", args.out, os.path.getsize(args.out), "bytes", file=sys.stderr)


if __name__ == "__main__":
    main()
