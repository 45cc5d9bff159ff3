#!/usr/bin/env python3
"""Checks examples/sbst2022/wogan_generator.py (WOGAN as a test generator of the SBST 2022 pipeline)
against a wogan binary, without the pipeline: its stand-in (tests/python/pipeline_stand_in) with
examples/sbst_executor's WoganExecutor as the pipeline's executor, so that wogan's search hands
roads through the pipeline's interface to `wogan simulate`, until the execution budget ends the
run as the pipeline ends it (sys.exit from inside execute_test).

    python3 tests/python/check_sbst_generator.py --wogan target/release/wogan

Exits 1 with a message on failure.
"""
import argparse
import json
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path[:0] = [os.path.join(HERE, "pipeline_stand_in"),
                os.path.join(REPO, "examples", "sbst_executor"),
                os.path.join(REPO, "examples", "sbst2022")]

from wogan_executor import WoganExecutor  # noqa: E402
from wogan_generator import WoganGenerator  # noqa: E402


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--wogan", required=True)
    args = parser.parse_args()
    folder = tempfile.mkdtemp(prefix="wogan-sbst-generator-")
    run_file = os.path.join(folder, "run.jsonl")
    os.environ.update({"WOGAN": args.wogan, "WOGAN_OUT": run_file, "WOGAN_SEED": "1"})
    # 300 simulated seconds: some 50 roads of WOGAN's kind.
    executor = WoganExecutor(folder, 200, generation_budget=3600, execution_budget=300,
                             wogan=[args.wogan], oracle="beamng-ai-proxy")
    generator = WoganGenerator(executor=executor, map_size=200)
    ended_by_budget = False
    try:
        try:
            generator.start()
        finally:
            executor.close()
    except SystemExit as stop:
        ended_by_budget = stop.code == 123
    problems = []
    if not ended_by_budget:
        problems.append("the pipeline's execution budget did not end the run")
    pipeline = executor.results
    records = [json.loads(l) for l in open(run_file)]
    tests = [r for r in records if r["type"] == "test"]
    if len(pipeline) < 10:
        problems.append(f"only {len(pipeline)} roads reached the pipeline's executor")
    # The last road may have been cut short when the budget ended the run: every road wogan wrote
    # down is one the pipeline executed, with the outcome and BOLP the pipeline's executor reported.
    if not 0 <= len(pipeline) - len(tests) <= 1:
        problems.append(f"{len(pipeline)} roads executed by the pipeline, {len(tests)} in wogan's run")
    for (test_id, outcome, _description, data), test in zip(pipeline, tests):
        bolp = max(r.oob_percentage for r in data)
        if test["outcome"] != outcome or test["max_bolp"] != min(1.0, bolp):
            problems.append(f"pipeline test {test_id} ({outcome}, {bolp}) is wogan's test "
                            f"{test['id']} ({test['outcome']}, {test['max_bolp']})")
    if records[-1]["type"] != "summary":
        problems.append("wogan's run has no summary: it was not ended cleanly")
    phases = {t["phase"] for t in tests}
    if "wogan" not in phases:
        problems.append(f"the search never left its random phase ({phases})")
    if problems:
        print("check_sbst_generator: " + "\n  ".join(problems))
        sys.exit(1)
    failing = sum(t["outcome"] == "FAIL" for t in tests)
    print(f"check_sbst_generator: {len(pipeline)} roads through the pipeline's interface, "
          f"{failing} failing, wogan's run ended cleanly ({records[-1]['executed']} tests)")


if __name__ == "__main__":
    main()
