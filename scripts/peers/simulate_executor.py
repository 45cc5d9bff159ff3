"""The competition pipeline's executor with `wogan simulate` in place of BeamNG, for the peers' runs.

It subclasses the 2022 pipeline's AbstractTestExecutor as its own executors do, so the pipeline
still validates every test, keeps the budgets and statistics and writes its test.NNNN.json files;
only `_execute` differs: the road goes to one long-lived `wogan simulate --execution-data` child
(a streaming filter: one road in, one answer out), or to an executor speaking wogan's executor
protocol that answers with execution data (`ExecutorChild`: MetaDrive's), and the answer's
`execution_data` becomes the pipeline's SimulationDataRecord list. Besides, the executor

* makes each drive cost the run's virtual clock (run_peer.py) its simulated time, which passes
  during execution as BeamNG's real time would (the drive's own wall time counted in it);
* appends every proposal to tests.jsonl: the pipeline's verdict, the outcome, the road, wogan's
  answer (without its records) and the pipeline clock;
* leaves the empty folder simulations/beamng_executor/sim_NNNNN that BeamNG's executor would
  (Frenetic-based generators read the newest one's name);
* can stop after a number of executed valid tests, the pipeline's FORCE EXIT path.

`Api2021Executor` lets a generator written for the 2021 pipeline run in this one: the 2021 API's
`get_remaining_time()` is a number of seconds of the generator's `time_budget`, here the
remaining simulated execution budget.
"""
import json
import logging as log
import os
import subprocess
import sys
import time

from code_pipeline.executors import AbstractTestExecutor
from self_driving.simulation_data import SimulationDataRecord

# The pipeline counts a failure as an OBE only when its description starts with this.
OUT_OF_LANE = "Car drove out of the lane "
# The 17 fields of wogan's execution_data arrays, in the 2022 record's order.
RECORD_FIELDS = ("timer", "pos", "dir", "vel", "steering", "steering_input", "brake",
                 "brake_input", "throttle", "throttle_input", "wheelspeed", "vel_kmh", "is_oob",
                 "oob_counter", "max_oob_percentage", "oob_distance", "oob_percentage")


class SimulateError(RuntimeError):
    """The child ended or answered something that is not the answer to the road sent."""


class LineChild:
    """A child process answering one JSON line with one JSON line, a road at a time: `ask` sends
    a road and checks the answer names it (`echo`: the answer's field that does)."""

    echo = None
    who = "the child"

    def __init__(self, command):
        self.process = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                        text=True, bufsize=1)
        self.lines = 0

    def send(self, message):
        self.process.stdin.write(json.dumps(message) + "\n")
        self.process.stdin.flush()

    def ask(self, request):
        """The answer to `request`, or SimulateError saying what came instead."""
        self.lines += 1
        try:
            self.send(request(self.lines))
            line = self.process.stdout.readline()
        except (BrokenPipeError, ValueError):
            line = ""
        if not line:
            self.process.poll()
            raise SimulateError(f"{self.who} ended before answering road {self.lines} "
                                f"(exit status {self.process.returncode})")
        try:
            answer = json.loads(line)
        except ValueError:
            answer = None
        if not isinstance(answer, dict) or answer.get(self.echo) != self.lines:
            raise SimulateError(f"{self.who} answered road {self.lines} with {line[:200]!r}")
        return answer

    def close(self, last=None):
        """Ends the child: `last` (if any) and end of input, then a kill if it has not exited
        within 10 s."""
        try:
            if last is not None:
                self.send(last)
            self.process.stdin.close()
        except (BrokenPipeError, ValueError):
            pass
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        self.process.stdout.close()


def road_points_of(road_points):
    return [[float(x), float(y)] for x, y in road_points]


class SimulateChild(LineChild):
    """One `wogan simulate --execution-data` process (a streaming filter: each answer names its
    input line)."""

    echo = "line"
    who = "wogan simulate"

    def __init__(self, binary, oracle, oob_tolerance, speed_limit, map_size):
        super().__init__([binary, "simulate", "--execution-data", "--oracle", oracle,
                          "--oob-tolerance", str(oob_tolerance), "--speed-limit", str(speed_limit),
                          "--map-size", str(map_size)])

    def drive(self, road_points):
        """The answer to one road (a dict with outcome, max_bolp, sim_time_s, execution_data...)."""
        return self.ask(lambda _: {"road_points": road_points_of(road_points)})


class ExecutorChild(LineChild):
    """One executor speaking wogan's executor protocol, version 3 (docs/reference.md), that
    answers with the pipeline's `execution_data` (examples/metadrive/executor.py
    `--execution-data`): hello once, answered by one `hello` line once the executor is ready
    (read here, before the budget clock starts: its start-up is charged to no budget, as BeamNG's
    start is not), then one road, one answer naming it by `id`. It is charged as wogan charges an
    executor: the answer's `sim_time_s`. `description` is the reply's `executor` object (`name`,
    `version`, `settings`, each optional; {} when it gives none)."""

    echo = "id"
    who = "the executor"
    protocol_version = 3

    def __init__(self, command, oob_tolerance, speed_limit, map_size):
        super().__init__(command)
        try:
            self.send({"type": "hello", "protocol": "wogan-executor", "version": self.protocol_version,
                       "units": "metres, seconds", "map_size_m": float(map_size),
                       "oob_tolerance": float(oob_tolerance), "speed_limit_kmh": float(speed_limit)})
            line = self.process.stdout.readline()
        except (BrokenPipeError, ValueError):
            line = ""
        try:
            self.description = self.reply_of(line)
        except SimulateError:
            self.process.kill()
            self.process.wait()
            self.process.stdout.close()
            raise
        log.info("executor %s", json.dumps(self.description))

    def reply_of(self, line):
        """The `executor` object of a reply to hello, or SimulateError naming what came instead."""
        if not line:
            try:  # its output closed: it ends, or has ended
                self.process.wait(timeout=5)
            except subprocess.TimeoutExpired:
                pass
            raise SimulateError(f"{self.who} ended (or closed its output) before answering hello "
                                f"(exit status {self.process.returncode})")
        try:
            reply = json.loads(line)
        except ValueError:
            reply = None
        expected = (f"a reply to hello (type hello, protocol wogan-executor, version {self.protocol_version}): "
                    "an executor of an older protocol version answers no hello")
        if (not isinstance(reply, dict) or reply.get("type") != "hello"
                or reply.get("protocol") != "wogan-executor" or reply.get("version") != self.protocol_version):
            raise SimulateError(f"{self.who} answered hello with {line[:200]!r}, not {expected}")
        description = reply.get("executor") or {}
        if not isinstance(description, dict):
            raise SimulateError(f"{self.who}'s reply to hello: executor: not an object: {line[:200]!r}")
        for field, kind, what in (("name", str, "text"), ("version", str, "text"),
                                  ("settings", dict, "an object")):
            if description.get(field) is not None and not isinstance(description[field], kind):
                raise SimulateError(f"{self.who}'s reply to hello: executor.{field}: not {what}: "
                                    f"{line[:200]!r}")
        return description

    def drive(self, road_points):
        """The answer to one road (a dict with outcome, reason, max_bolp, sim_time_s,
        execution_data...)."""
        answer = self.ask(lambda n: {"type": "road", "id": n,
                                     "road_points": road_points_of(road_points)})
        if answer.get("outcome") == "ERROR":
            answer.setdefault("message", answer.get("error"))
        return answer

    def close(self):
        super().close({"type": "bye"})


def pipeline_records(execution_data):
    """wogan's 17-field arrays as this pipeline's SimulationDataRecord, field by field."""
    records = []
    for values in execution_data:
        named = dict(zip(RECORD_FIELDS, values))
        records.append(SimulationDataRecord(**{f: named[f] for f in SimulationDataRecord._fields}))
    return records


def outcome_of(answer, test_id):
    """The pipeline's (outcome, description) for wogan's answer."""
    outcome, reason = answer.get("outcome"), answer.get("reason")
    if outcome == "PASS":
        return "PASS", "Successful test"
    if outcome == "FAIL" and reason == "out_of_lane":
        return "FAIL", f"{OUT_OF_LANE}(wogan simulate, test {test_id})"
    if outcome == "FAIL" and reason == "not_moving":
        return "FAIL", "Car is not moving fast enough (wogan simulate)"
    if outcome == "FAIL":
        return "FAIL", f"wogan {reason}"
    # ERROR, or a road wogan's validator refuses after the pipeline's accepted it.
    return "ERROR", f"wogan {outcome}: {answer.get('message') or reason}"


class WoganExecutor(AbstractTestExecutor):
    """The 2022 pipeline's executor driving roads with one `wogan simulate` child."""

    def __init__(self, result_folder, map_size, child, generation_budget=None,
                 execution_budget=None, time_budget=None, max_valid_tests=None, clock=None):
        self.child = child
        self.max_valid_tests = max_valid_tests
        self.clock = clock
        self.log_path = os.path.join(result_folder, "tests.jsonl")
        self.proposals = 0
        self.last_answer = None
        self.started = time.monotonic()
        super().__init__(result_folder, map_size, generation_budget=generation_budget,
                         execution_budget=execution_budget, time_budget=time_budget)

    def execute_test(self, the_test):
        self.proposals += 1
        self.last_answer = None
        outcome, description, execution_data = super().execute_test(the_test)
        self._log(the_test, outcome, description)
        if self.max_valid_tests is not None and self.stats.test_valid >= self.max_valid_tests:
            log.info("Executed %d valid tests: FORCE EXIT", self.stats.test_valid)
            self.timeout_forced = True
            sys.exit(123)
        return outcome, description, execution_data

    def _execute(self, the_test):
        super()._execute(the_test)
        started = time.monotonic()
        answer = self.child.drive(the_test.road_points)
        records = pipeline_records(answer.pop("execution_data", None) or [])
        self.last_answer = answer
        os.makedirs(os.path.join("simulations", "beamng_executor", f"sim_{the_test.id:05d}"),
                    exist_ok=True)
        if self.clock is not None:
            # The drive costs its simulated time: the clock passed the drive's wall time already.
            spent = time.monotonic() - started
            self.clock.advance(max(answer.get("sim_time_s", 0.0) - spent, 0.0))
        outcome, description = outcome_of(answer, the_test.id)
        return outcome, description, records

    def _log(self, the_test, outcome, description):
        entry = {"proposal": self.proposals, "id": the_test.id,
                 "pipeline_valid": the_test.is_valid,
                 "validation_message": the_test.validation_message, "outcome": outcome,
                 "description": description,
                 "road_points": [list(p) for p in the_test.road_points],
                 "valid_so_far": self.stats.test_valid,
                 "clock_s": round(time.monotonic() - self.started, 3)}
        if self.last_answer is not None:
            entry["wogan"] = self.last_answer
        with open(self.log_path, "a") as f:
            f.write(json.dumps(entry) + "\n")

    def _close(self):
        self.child.close()
        super()._close()


class Api2021Executor(WoganExecutor):
    """The executor as a generator written for the 2021 pipeline expects it."""

    def get_remaining_time(self):
        return self.time_budget.get_remaining_simulated_time()
