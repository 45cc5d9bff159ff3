#!/usr/bin/env python3
"""Compares the SBST 2022 pipeline's own OOB analysis with wogan's on exported runs.

Development-time only. For each result directory written by `wogan export --format sbst`, runs
the pipeline's `OOBAnalyzer` (from a checkout of se2p/tool-competition-av, with numpy, scipy,
shapely and matplotlib installed) and prints its `_analyse()` values and `create_summary()` CSV
beside the `oob_stats.csv` wogan wrote there, and whether the two CSV texts are identical:

    python3 scripts/reference/sbst_oob_compare.py --pipeline /work/tca target/sbst/export/*

A directory on which the pipeline's analysis raises is reported with the exception; wogan then
writes no `oob_stats.csv` and says why on stderr. Exits 1 when any directory disagrees.
"""

import argparse
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
        disagreements += not same
        print(f"{directory}\n  pipeline _analyse(): {values}")
        print(f"  pipeline CSV: {theirs!r}\n  wogan CSV:    {ours!r}\n  identical: {same}")
    sys.exit(1 if disagreements else 0)


if __name__ == "__main__":
    main()
