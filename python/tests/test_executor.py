"""wogan.Executor and wogan.Answer: in-process over given streams, and executors written with the
class driving real `wogan run --executor` searches."""

import io
import json
import math
import os
import signal
import subprocess
import sys

import pytest
from geometric_executor import bolp_of
from helpers import HERE, command

import wogan

HELLO = {"type": "hello", "protocol": "wogan-executor", "version": 2, "units": "metres, seconds",
         "map_size_m": 200.0, "oob_tolerance": 0.85, "speed_limit_kmh": 70.0}


def serve(executor, *messages):
    """The answers `executor` writes to `messages` (dicts, or raw lines as str)."""
    lines = "".join((m if isinstance(m, str) else json.dumps(m)) + "\n" for m in messages)
    out = io.StringIO()
    executor.serve(io.StringIO(lines), out)
    return [json.loads(line) for line in out.getvalue().splitlines()]


def road(id, points=((0.0, 0.0), (0.0, 30.0))):
    return {"type": "road", "id": id, "road_points": [list(p) for p in points]}


class Recorder(wogan.Executor):
    def __init__(self):
        super().__init__()
        self.seen, self.hellos, self.closed = [], [], 0

    def hello(self, settings):
        self.hellos.append(settings)

    def drive(self, road):
        self.seen.append(road)
        if road.id == 2:
            raise KeyError("no such road")
        return wogan.Answer(max_bolp=0.25, sim_time_s=3.5, extra={"note": f"road {road.id}"})

    def close(self):
        self.closed += 1


def test_each_road_is_answered_by_its_id_and_serving_ends_at_bye():
    executor = Recorder()
    answers = serve(executor, HELLO, road(7), road(2), "not JSON", {"type": "news", "id": 1}, road(9),
                    {"type": "bye"}, road(10))
    assert executor.settings == {k: v for k, v in HELLO.items() if k != "type"}
    assert executor.hellos == [executor.settings]
    assert [r.id for r in executor.seen] == [7, 2, 9]
    assert executor.seen[0].points == [(0.0, 0.0), (0.0, 30.0)]
    assert answers[0] == {"id": 7, "max_bolp": 0.25, "sim_time_s": 3.5, "note": "road 7"}
    # The drive that raised: ERROR with the exception's message; the next road is driven.
    assert answers[1] == {"id": 2, "max_bolp": 0.0, "outcome": "ERROR", "sim_time_s": 0.0,
                          "error": "KeyError: 'no such road'"}
    assert [a["id"] for a in answers] == [7, 2, 9]  # nothing after bye
    assert executor.closed == 1


def test_an_answer_that_cannot_be_sent_answers_error_and_drive_failed_may_stop_serving():
    class Bad(wogan.Executor):
        def drive(self, road):
            return {"max_bolp": 0.1} if road.id == 1 else wogan.Answer(0.1, extra={"x": math.nan})

    answers = serve(Bad(), road(1), road(2))
    assert [a["outcome"] for a in answers] == ["ERROR", "ERROR"]
    assert "drive() returned dict, not a wogan.Answer" in answers[0]["error"]
    assert "cannot be written as JSON" in answers[1]["error"]

    class Strict(wogan.Executor):
        def drive(self, road):
            raise OSError("the simulator is gone")

        def drive_failed(self, road, error):
            raise error

    with pytest.raises(OSError, match="the simulator is gone"):
        serve(Strict(), road(1))


def test_answers_are_checked_when_made():
    for fields, says in [
        ({"max_bolp": 1.5}, "max_bolp: 1.5 is outside"),
        ({"max_bolp": math.nan}, "max_bolp: nan is not a finite number"),
        ({"max_bolp": True}, "max_bolp: True is not a finite number"),
        ({"max_bolp": 0.5, "outcome": "pass"}, "outcome: 'pass' is not one of PASS, FAIL, ERROR"),
        ({"max_bolp": 0.5, "sim_time_s": -1}, "sim_time_s: -1 is below 0"),
        ({"max_bolp": 0.5, "oob_side": "up"}, "oob_side: 'up' is not 'left' or 'right'"),
        ({"max_bolp": 0.5, "oob_point": (1, 2)}, "oob_point: given without oob_side"),
        ({"max_bolp": 0.5, "oob_side": "left", "oob_point": (1,)}, "oob_point: (1,) is not a point"),
        ({"max_bolp": 0.5, "min_lane_distance_m": 2.5}, "min_lane_distance_m: 2.5 is above 2.0 m"),
        ({"max_bolp": 0.5, "error": 3}, "error: 3 is not text"),
        ({"max_bolp": 0.5, "extra": {"id": 4}}, "extra: 'id' is a field of the answer itself"),
    ]:
        with pytest.raises(ValueError, match=says.replace("(", r"\(").replace(")", r"\)")):
            wogan.Answer(**fields)
    full = wogan.Answer(0.9, "FAIL", 6.0, "right", (3, 4), -0.25, None, {"reason": "out_of_lane"})
    assert full.to_message(5) == {"id": 5, "max_bolp": 0.9, "outcome": "FAIL", "sim_time_s": 6.0,
                                  "min_lane_distance_m": -0.25, "oob_side": "right", "oob_point": [3.0, 4.0],
                                  "reason": "out_of_lane"}


def test_an_executor_written_with_the_class_drives_a_search():
    run = wogan.run(["--max-tests", "20", "--seed", "1", "--executor", command("geometric_executor.py")])
    assert run.header["config"]["executor"].endswith("geometric_executor.py")
    assert [t["id"] for t in run.tests] == list(range(1, 21))
    assert run.summary["executed"] == 20 and run.status == 0
    # Every road answered by the executor, with what it computed from the road's points.
    for test in run.tests:
        bolp = bolp_of(test["road_points"])
        assert test["max_bolp"] == pytest.approx(bolp, abs=1e-12), test["id"]
        assert test["outcome"] == ("FAIL" if bolp > 0.85 else "PASS"), test
        assert test["sim_time_s"] == 10.0
        assert (test["oob"] or {}).get("side") == ("left" if bolp > 0.85 else None), test["oob"]
    outcomes = {t["outcome"] for t in run.tests}
    assert outcomes == {"PASS", "FAIL"}, "the search finds failing roads and passing ones"
    assert run.summary["failed"] == len(run.failures) > 0


def test_a_drive_that_raises_answers_error_and_the_run_goes_on(monkeypatch):
    monkeypatch.setenv("RAISE_AT", "3")
    run = wogan.run(["--max-tests", "20", "--seed", "1", "--executor", command("geometric_executor.py")])
    assert len(run.tests) == 20 and run.summary["executed"] == 20
    third = run.tests[2]
    assert third["outcome"] == "ERROR"
    assert third["error"].endswith("ValueError: road 3 refused on purpose"), third["error"]
    others = [t for t in run.tests if t["id"] != 3]
    assert all(t["outcome"] in ("PASS", "FAIL") for t in others), [t.get("error") for t in others]



def start_script(script, **env):
    """This folder's `script` run with this Python, every stream piped."""
    return subprocess.Popen([sys.executable, os.path.join(HERE, script)], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env={**os.environ, **env})


def test_only_answers_reach_stdout_whatever_else_writes_there():
    process = start_script("noisy_executor.py")
    lines = [HELLO, road(1), road(2), {"type": "bye"}]
    stdout, stderr = process.communicate("".join(json.dumps(m) + "\n" for m in lines), timeout=60)
    assert process.returncode == 0, stderr
    assert [json.loads(line) for line in stdout.splitlines()] == [{"id": 1, "max_bolp": 0.5}, {"id": 2, "max_bolp": 0.5}]
    for said in ("print at road 2", "sys.stdout at road 2", "file descriptor 1", "closed", "after serve",
                 "after serve, file descriptor 1"):
        assert said in stderr, said


def test_sigterm_ends_serving_through_close():
    process = start_script("noisy_executor.py", SLOW_AT="2")
    process.stdin.write("".join(json.dumps(m) + "\n" for m in (HELLO, road(1), road(2))))
    process.stdin.flush()
    assert json.loads(process.stdout.readline()) == {"id": 1, "max_bolp": 0.5}
    while "slow road" not in process.stderr.readline():
        pass
    process.send_signal(signal.SIGTERM)
    stdout, stderr = process.communicate(timeout=30)
    assert process.returncode == 143 and stdout == ""
    assert "closed" in stderr
