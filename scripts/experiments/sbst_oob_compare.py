#!/usr/bin/env python3
"""Compares the SBST 2022 pipeline's own analysis with wogan's on exported runs.

Development-time only. For each result directory written by `wogan export --format sbst`, runs
the pipeline's `OOBAnalyzer` (from a checkout of se2p/tool-competition-av, with numpy, scipy,
shapely and matplotlib installed) and prints its `_analyse()` values and `create_summary()` CSV
beside the `oob_stats.csv` wogan wrote there, and whether the two CSV texts are identical; and
recomputes every test's features with the pipeline's `compute_all_features` from the file's road
and `execution_data`, reporting the largest difference from the `features` wogan wrote:

    python3 scripts/experiments/sbst_oob_compare.py --pipeline /work/tca target/sbst/export/*

A directory on which the pipeline's analysis raises is reported with the exception; wogan then
writes no `oob_stats.csv` and says why on stderr. Exits 1 when any directory disagrees.
"""

import argparse
import json
import logging
import os
import sys


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pipeline", required=True, help="checkout of se2p/tool-competition-av")
    parser.add_argument("directories", nargs="+")
    args = parser.parse_args()
    sys.path.insert(0, args.pipeline)
    import numpy

    if not hasattr(numpy, "NaN"):  # removed in numpy 2; the pipeline was written for 1.x
        numpy.NaN = numpy.nan
    from code_pipeline.tests_evaluation import OOBAnalyzer
    from code_pipeline.test_analysis import compute_all_features
    from code_pipeline.tests_generation import RoadTestFactory
    from self_driving.simulation_data import SimulationDataRecord

    logging.disable(logging.WARNING)
    disagreements = 0
    for directory in args.directories:
        ours_path = os.path.join(directory, "oob_stats.csv")
        ours = open(ours_path).read() if os.path.exists(ours_path) else None
        try:
            analyzer = OOBAnalyzer(directory)
            values = analyzer._analyse()
            theirs = analyzer.create_summary()
        except Exception as exc:  # the pipeline's analysis itself fails
            values, theirs = f"raised {type(exc).__name__}: {exc}", None
        same = ours == theirs
        worst, tests = 0.0, 0
        for name in sorted(os.listdir(directory)):
            if not (name.startswith("test.") and name.endswith(".json")):
                continue
            with open(os.path.join(directory, name)) as f:
                data = json.load(f)
            road = RoadTestFactory.create_road_test(data["road_points"])
            records = [SimulationDataRecord(*r) for r in data["execution_data"]]
            for key, value in compute_all_features(road, records).items():
                worst = max(worst, abs(float(value) - data["features"][key]))
            tests += 1
        disagreements += not same or worst > 1e-9
        print(f"{directory}\n  pipeline _analyse(): {values}")
        print(f"  pipeline CSV: {theirs!r}\n  wogan CSV:    {ours!r}\n  identical: {same}")
        print(f"  features of {tests} tests recomputed by the pipeline: largest difference {worst:.3g}")
    sys.exit(1 if disagreements else 0)


if __name__ == "__main__":
    main()
