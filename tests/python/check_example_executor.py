#!/usr/bin/env python3
"""Checks examples/sbst_executor/wogan_executor.py against a wogan binary, without the competition's
pipeline: a stand-in of the pipeline's interface (tests/python/pipeline_stand_in) comes first on
sys.path.

    python3 tests/python/check_example_executor.py --wogan target/release/wogan

--wogan may be a command with arguments ("python3 fake.py"). Exits 1 with a message on failure.
"""
import argparse
import os
import shlex
import sys
import tempfile
import types

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
STAND_IN = os.path.join(HERE, "pipeline_stand_in")
sys.path[:0] = [STAND_IN, os.path.join(REPO, "examples", "sbst_executor")]

import code_pipeline.executors  # noqa: E402
from wogan_executor import WoganError, WoganExecutor  # noqa: E402

# (name, road_points, expected outcome). Roads from the reference data: the pipeline's validator
# accepts all but "too sharp" ("The road is too sharp"). With beamng-ai-proxy at tolerance 0.85,
# "gentle bend" passes (it still passes at tolerance 0.3) and "hairpin" leaves the lane (its
# largest BOLP is 0.91 at tolerance 0.99).
ROADS = [
    ("straight", [[100, 10], [100, 60], [100, 110]], "PASS"),
    ("gentle bend", [[77, 180], [129, 143], [132, 129]], "PASS"),
    ("too sharp", [[80, 20], [100, 60], [120, 20]], "ERROR"),
    ("hairpin", [[100, 10], [100, 120], [70, 130], [60, 75]], "FAIL"),
]


class CheckFailed(Exception):
    pass


def check(condition, message):
    if not condition:
        raise CheckFailed(message)


def make_executor(command, folder, **budget):
    return WoganExecutor(folder, 200, oob_tolerance=0.85, max_speed_in_kmh=70,
                         wogan=command, oracle="beamng-ai-proxy", **budget)


def check_drive(name, outcome, description, data, answer):
    check(len(data) > 0, f"{name}: empty execution_data")
    for record in data:
        check(len(record) == 17 and len(record.pos) == 3, f"{name}: malformed record {record}")
    timers = [r.timer for r in data]
    check(all(a < b for a, b in zip(timers, timers[1:])), f"{name}: timers do not increase")
    check(abs(timers[-1] - answer["sim_time_s"]) < 1e-9,
          f"{name}: last timer {timers[-1]} != sim_time_s {answer['sim_time_s']}")
    out_of_lane = outcome == "FAIL" and answer["reason"] == "out_of_lane"
    flags = [bool(r.is_oob) for r in data]
    check(flags == [False] * (len(data) - 1) + [out_of_lane],
          f"{name}: is_oob should be true only on the last record of an out_of_lane FAIL")
    # The pipeline recomputes these features from the records into each test.NNNN.json.
    steering, lateral = [r.steering for r in data], [r.oob_distance for r in data]
    mean = sum(steering) / len(steering)
    mine = {"STD_SA": (sum((v - mean) ** 2 for v in steering) / len(steering)) ** 0.5,
            "MEAN_LP": sum(lateral) / len(lateral), "MAX_LP": max(lateral)}
    for key, value in mine.items():
        check(abs(value - answer[key]) <= 1e-6 * max(1.0, abs(value)),
              f"{name}: {key} from execution_data is {value}, the answer says {answer[key]}")
    if outcome == "PASS":
        check(description == "Successful test", f"{name}: PASS described as {description!r}")
    if out_of_lane:
        check(description.startswith("Car drove out of the lane "),
              f"{name}: the pipeline would not count {description!r} as an OBE")


def main_checks(command, folder):
    executor = make_executor(command, folder)
    pid = executor.child.pid
    outcomes = []
    try:
        for test_id, (name, points, expected) in enumerate(ROADS, start=1):
            the_test = types.SimpleNamespace(id=test_id, road_points=points)
            outcome, description, data = executor.execute_test(the_test)
            outcomes.append(outcome)
            check(outcome in ("PASS", "FAIL", "ERROR"), f"{name}: outcome {outcome!r}")
            check(outcome == expected, f"{name}: expected {expected}, got {outcome} ({description})")
            check(executor.child.pid == pid and executor.child.poll() is None,
                  f"{name}: the wogan child is not the one started first, or it exited")
            if executor.last_answer.get("outcome") in ("PASS", "FAIL", "ERROR"):
                check_drive(name, outcome, description, data, executor.last_answer)
            else:
                check(data == [], f"{name}: an undriven road has execution_data")
        check(executor.budget_checks == len(ROADS), "_execute() skipped the pipeline's budget check")
    finally:
        executor.close()
    check(executor.closed, "close() did not reach the pipeline's _close()")
    check(executor.child.returncode == 0, f"wogan exited with {executor.child.returncode} after close()")
    return pid, outcomes, executor.results


def failure_checks(folder):
    """A child that dies, one that answers junk, and a budget that is already spent."""
    py = sys.executable
    dead = [py, "-c", "import sys; sys.stdin.readline()"]
    junk = [py, "-c", "import sys\nfor _ in sys.stdin: print('{\"no\": 1}', flush=True)"]
    for command, what in ((dead, "ended before answering test 7"), (junk, "garbage")):
        executor = make_executor(command, folder)
        try:
            executor.execute_test(types.SimpleNamespace(id=7, road_points=ROADS[0][1]))
            raise CheckFailed(f"no WoganError for a child that {what}")
        except WoganError as error:
            check(what in str(error) and "test 7" in str(error), f"unclear error: {error}")
        finally:
            executor.close()
    executor = make_executor(dead, folder, execution_budget=0)
    try:
        executor.execute_test(types.SimpleNamespace(id=8, road_points=ROADS[0][1]))
        raise CheckFailed("a test ran with no execution budget left")
    except SystemExit as stop:
        check(stop.code == 123, f"budget exhaustion exited with {stop.code}, not 123")
    finally:
        executor.close()
    # The child was never written to, so it saw EOF only at close() and exited 0.
    check(executor.child.returncode == 0, "the child was not closed cleanly after sys.exit(123)")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--wogan", default="wogan", help="path of the binary, or a command")
    command = shlex.split(parser.parse_args().wogan)
    check_stand_in = code_pipeline.executors.__file__.startswith(STAND_IN)
    try:
        check(check_stand_in, f"imported the real pipeline ({code_pipeline.executors.__file__})")
        with tempfile.TemporaryDirectory() as folder:
            pid, outcomes, results = main_checks(command, folder)
            failure_checks(folder)
    except (CheckFailed, WoganError, OSError) as error:
        print(f"check_example_executor: FAILED: {error}", file=sys.stderr)
        return 1
    simulated = sum(data[-1].timer for _, _, _, data in results if data)
    print(f"check_example_executor: ok: {len(outcomes)} tests {'/'.join(outcomes)} in one wogan "
          f"process (pid {pid}), {simulated:.1f} simulated s; dead/junk child and spent budget handled")
    return 0


if __name__ == "__main__":
    sys.exit(main())
