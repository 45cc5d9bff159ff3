#!/usr/bin/env python3
"""Dev-time check: run a tool-competition test generator against WoganExecutor, the way the
pipeline's competition.py runs one against BeamNG, and write its results into --results.

    python3 run_in_pipeline.py --pipeline /work/tca --wogan target/release/wogan \
        --generator random --generation-budget 20 --execution-budget 120 --results /tmp/run

--generator is "random" (the pipeline's sample RandomTestGenerator) or module:Class (importable
with the pipeline and --module-path on sys.path). --wogan may be a command ("python3 fake.py").
"""
import argparse
import csv
import importlib
import logging as log
import os
import shlex
import sys
import traceback

HERE = os.path.dirname(os.path.abspath(__file__))


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--pipeline", required=True, help="checkout of se2p/tool-competition-av")
    p.add_argument("--wogan", default="wogan", help="path of the binary, or a command")
    p.add_argument("--oracle", default="beamng-ai-proxy", choices=["beamng-ai-proxy", "dave2-proxy"])
    p.add_argument("--generator", default="random", help="'random' or module:Class")
    p.add_argument("--module-path", help="directory to add to sys.path for the generator")
    p.add_argument("--time-budget", type=int, help="real seconds for everything")
    p.add_argument("--generation-budget", type=int, help="real seconds of generation")
    p.add_argument("--execution-budget", type=int, help="simulated seconds of execution")
    p.add_argument("--map-size", type=int, default=200)
    p.add_argument("--oob-tolerance", type=float, help="default: the oracle's own (0.85 / 0.10)")
    p.add_argument("--speed-limit", type=int, help="km/h; default: the oracle's own (70 / 25)")
    p.add_argument("--results", required=True, help="folder for test.NNNN.json and the CSV reports")
    p.add_argument("--debug", action="store_true")
    args = p.parse_args()
    # The same combinations competition.py accepts.
    has_time = args.time_budget is not None
    has_generation, has_execution = args.generation_budget is not None, args.execution_budget is not None
    if has_time == (has_generation or has_execution) or has_generation != has_execution:
        p.error("give --time-budget, or both --generation-budget and --execution-budget")
    return args


def main():
    args = parse_args()
    log.basicConfig(format="%(asctime)s %(levelname)-8s %(message)s",
                    level=log.DEBUG if args.debug else log.INFO)
    sys.path[:0] = [os.path.abspath(args.pipeline), HERE] + ([args.module_path] if args.module_path else [])
    try:
        # competition.py's own reports. Importing it needs click, matplotlib and descartes.
        from competition import create_experiment_description, create_summary
    except ImportError as error:
        log.warning("cannot import competition.py (%s); writing its reports with its pieces", error)
        create_experiment_description, create_summary = write_description, write_summary
    from wogan_executor import WoganExecutor

    module_name, class_name = (("sample_test_generators.random_generator", "RandomTestGenerator")
                               if args.generator == "random" else args.generator.split(":"))
    generator_class = getattr(importlib.import_module(module_name), class_name)
    os.makedirs(args.results, exist_ok=True)

    executor = WoganExecutor(args.results, args.map_size,
                             generation_budget=args.generation_budget,
                             execution_budget=args.execution_budget, time_budget=args.time_budget,
                             oob_tolerance=args.oob_tolerance, max_speed_in_kmh=args.speed_limit,
                             debug=args.debug, wogan=shlex.split(args.wogan), oracle=args.oracle)
    try:
        try:
            generator_class(executor=executor, map_size=args.map_size).start()
        finally:
            executor.close()  # as competition.py: always, also on sys.exit(123)
    except SystemExit:
        # The pipeline ends a run whose budget is spent with sys.exit(123) from inside execute_test().
        # competition.py then writes the reports from an exit hook and the process exits 123; here
        # we catch it and write the same reports below.
        if not executor.is_force_timeout():
            raise
        log.info("Budget spent: the pipeline stopped the generator")
    except Exception:
        traceback.print_exc()
        return 2

    log.info("Test Generation Statistics:\n%s", executor.get_stats())
    create_experiment_description(args.results, vars(args))
    status = 0
    try:
        create_summary(args.results, executor.get_stats())
    except Exception as error:  # generation_stats.csv is written before the OOB analysis
        # Known pipeline limits: OOBAnalyzer fits a cubic spline to road_points, so it cannot place
        # an OOB on a 3-point road (the random generator's) and its sparseness then fails once
        # there are 2 OOBs; with fewer than 2 it uses np.NaN, which numpy 2 removed.
        log.error("the pipeline's create_summary failed: %r; oob_stats.csv is not written", error)
        status = 3
    print(f"OBEs (failures the pipeline counts as out of lane): {executor.get_stats().obes}")
    for name in ("generation_stats.csv", "oob_stats.csv"):
        path = os.path.join(args.results, name)
        if os.path.exists(path):
            with open(path) as report:
                print(f"{name}:\n{report.read().strip()}")
    return status


def write_description(result_folder, params):
    """competition.py's experiment_description.csv: one header row, one row of the run's settings."""
    with open(os.path.join(result_folder, "experiment_description.csv"), "w", newline="") as out:
        writer = csv.DictWriter(out, fieldnames=list(params))
        writer.writeheader()
        writer.writerow(params)


def write_summary(result_folder, stats):
    """competition.py's create_summary, from the pipeline classes it uses."""
    from code_pipeline.tests_evaluation import OOBAnalyzer
    with open(os.path.join(result_folder, "generation_stats.csv"), "w") as out:
        out.write(stats.as_csv())
    oob_summary = OOBAnalyzer(result_folder).create_summary()
    with open(os.path.join(result_folder, "oob_stats.csv"), "w") as out:
        out.write(oob_summary)


if __name__ == "__main__":
    sys.exit(main())
