"""wogan.Executor and wogan.Answer: in-process over given streams, and executors written with the
class driving real `wogan run --executor` searches."""

import fractions
import io
import json
import math
import os
import re
import signal
import subprocess
import sys

import pytest
from geometric_executor import bolp_of
from helpers import HERE, command

import wogan

HELLO = {"type": "hello", "protocol": "wogan-executor", "version": 3, "units": "metres, seconds",
         "map_size_m": 200.0, "oob_tolerance": 0.85, "speed_limit_kmh": 70.0}
HELLO_2 = {**HELLO, "version": 2}  # an older wogan's


def written(executor, *messages, out=None):
    """Every line `executor` writes to `messages` (dicts, or raw lines as str)."""
    lines = "".join((m if isinstance(m, str) else json.dumps(m)) + "\n" for m in messages)
    out = io.StringIO() if out is None else out
    executor.serve(io.StringIO(lines), out)
    return [json.loads(line) for line in out.getvalue().splitlines()]


def reply(name, **more):
    """The reply to a version-3 hello of an executor named `name`."""
    return {"type": "hello", "protocol": "wogan-executor", "version": 3, "executor": {"name": name, **more}}


def serve(executor, *messages):
    """The answers `executor` writes to `messages`: every line after its one reply to `hello`
    (none when the messages hold no hello)."""
    lines = written(executor, *messages)
    if messages and messages[0] == HELLO:
        assert lines[0] == reply(type(executor).__name__), lines[:1]
        lines = lines[1:]
    assert all(line.get("type") != "hello" for line in lines), lines
    return lines


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
    assert "ValueError: extra: not JSON" in answers[1]["error"]  # refused when made, in drive

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
        ({"max_bolp": 0.5, "sim_time_s": -1}, "sim_time_s: -1 is outside [0, 3600] s"),
        ({"max_bolp": 0.5, "sim_time_s": 1e308}, "sim_time_s: 1e+308 is outside [0, 3600] s"),
        ({"max_bolp": 0.5, "oob_side": "left", "oob_point": (1e308, 0)}, "oob_point: (1e+308, 0.0) is farther"),
        ({"max_bolp": 0.5, "oob_side": "left", "oob_point": (0, -20000.5)}, "oob_point: (0.0, -20000.5) is farther"),
        ({"max_bolp": 0.5, "min_lane_distance_m": -1e308}, "min_lane_distance_m: -1e+308 is below -20000 m"),
        ({"max_bolp": 0.5, "oob_side": "up"}, "oob_side: 'up' is not 'left' or 'right'"),
        ({"max_bolp": 0.5, "oob_point": (1, 2)}, "oob_point: given without oob_side"),
        ({"max_bolp": 0.5, "oob_side": "left", "oob_point": (1,)}, "oob_point: (1,) is not a point"),
        ({"max_bolp": 0.5, "min_lane_distance_m": 2.5}, "min_lane_distance_m: 2.5 is above 2.0 m"),
        ({"max_bolp": 0.5, "error": 3}, "error: 3 is not text"),
        ({"max_bolp": 0.5, "extra": {"id": 4}}, "extra: 'id' is a field of the answer itself"),
    ]:
        with pytest.raises(ValueError, match=re.escape(says)):
            wogan.Answer(**fields)
    full = wogan.Answer(0.9, "FAIL", 6.0, "right", (3, 4), -0.25, None, {"reason": "out_of_lane"})
    assert full.to_message(5) == {"id": 5, "max_bolp": 0.9, "outcome": "FAIL", "sim_time_s": 6.0,
                                  "min_lane_distance_m": -0.25, "oob_side": "right", "oob_point": [3.0, 4.0],
                                  "reason": "out_of_lane"}


# Version 3: the reply to hello, from the executor's end.

class Ready(wogan.Executor):
    """Notes what it had written when its hello hook ran, and reports its settings."""
    name = "ready-executor"
    version = "1.2"

    def __init__(self, out):
        super().__init__()
        self.out, self.written_at_hello = out, None

    def hello(self, settings):
        self.written_at_hello = self.out.getvalue()
        self.speed = settings["speed_limit_kmh"] / 2

    def reported_settings(self):
        return {"policy": "idm", "speed_kmh": self.speed, "nested": {"hz": [10, 50]}}

    def drive(self, road):
        return wogan.Answer(max_bolp=0.1)


def test_hello_is_answered_once_the_hook_returned_and_before_any_answer():
    out = io.StringIO()
    executor = Ready(out)
    lines = written(executor, HELLO, road(1), road(2), {"type": "bye"}, out=out)
    assert executor.written_at_hello == ""  # the hook ran before the reply
    assert lines == [reply("ready-executor", version="1.2",
                           settings={"policy": "idm", "speed_kmh": 35.0, "nested": {"hz": [10, 50]}}),
                     {"id": 1, "max_bolp": 0.1}, {"id": 2, "max_bolp": 0.1}]
    assert executor.settings["version"] == 3


def test_the_reply_names_the_class_by_default_and_omits_what_is_not_given():
    assert written(Recorder(), HELLO) == [reply("Recorder")]

    class Versioned(wogan.Executor):
        version = "0.1"

    class Named(wogan.Executor):
        def __init__(self):
            super().__init__()
            self.name = "set in __init__"

    assert written(Versioned(), HELLO) == [reply("Versioned", version="0.1")]
    assert written(Named(), HELLO) == [reply("set in __init__")]


def test_a_version_2_hello_is_served_without_a_reply():
    # An older wogan would take a reply for road 1's answer.
    executor = Recorder()
    assert written(executor, HELLO_2, road(1), {"type": "bye"}) == [
        {"id": 1, "max_bolp": 0.25, "sim_time_s": 3.5, "note": "road 1"}]
    assert executor.hellos == [{k: v for k, v in HELLO_2.items() if k != "type"}]
    # A newer wogan's hello is answered (this client's version in the reply), as is each hello.
    assert written(Recorder(), {**HELLO, "version": 4}, HELLO) == [reply("Recorder")] * 2


def test_a_bad_description_or_a_failing_hello_raises_before_any_reply():
    class Bad(wogan.Executor):
        def __init__(self, **fields):
            super().__init__()
            self.fields, self.closed = fields, 0
            for key in ("name", "version"):
                if key in fields:
                    setattr(self, key, fields[key])

        def hello(self, settings):
            if "hello" in self.fields:
                raise self.fields["hello"]

        def reported_settings(self):
            return self.fields.get("settings")

        def close(self):
            self.closed += 1

    for fields, error, says in [
        ({"name": 3}, ValueError, "name: 3 is not text"),
        ({"version": 1.2}, ValueError, "version: 1.2 is not text"),
        ({"settings": ["idm"]}, ValueError, r"reported_settings\(\): list is not a dict"),
        ({"settings": {"speed": math.nan}}, ValueError, r"reported_settings\(\): not JSON"),
        ({"settings": {1: "a"}}, ValueError, r"reported_settings\(\): a setting's name is not text"),
        ({"hello": RuntimeError("the simulator did not start")}, RuntimeError, "the simulator did not start"),
    ]:
        executor, out = Bad(**fields), io.StringIO()
        with pytest.raises(error, match=says):
            executor.serve(io.StringIO(json.dumps(HELLO) + "\n" + json.dumps(road(1)) + "\n"), out)
        assert out.getvalue() == "" and executor.closed == 1, fields


@pytest.mark.parametrize("fields, says", [
    ({"max_bolp": 10**400}, "max_bolp: 1000"),
    ({"max_bolp": -10**400}, "max_bolp: -1000"),
    ({"max_bolp": 10**5000}, "max_bolp: <int too large to show>"),
    ({"max_bolp": fractions.Fraction(10**400, 3)}, r"max_bolp: Fraction\(1000"),
    ({"max_bolp": 0.5, "sim_time_s": 10**400}, "sim_time_s: 1000"),
    ({"max_bolp": 0.5, "oob_side": "left", "oob_point": (10**400, 0)}, "oob_point: x: 1000"),
    ({"max_bolp": 0.5, "oob_side": "left", "oob_point": (0, -10**400)}, "oob_point: y: -1000"),
    ({"max_bolp": 0.5, "min_lane_distance_m": -10**400}, "min_lane_distance_m: -1000"),
])
def test_numbers_beyond_a_floats_range_are_value_errors_naming_the_field(fields, says):
    with pytest.raises(ValueError, match=says) as raised:
        wogan.Answer(**fields)
    assert "beyond a float's range" in str(raised.value) and len(str(raised.value)) < 200


def test_an_answer_is_refused_when_made_not_when_sent():
    # An iterator is read once, when checked: the answer keeps the point.
    answer = wogan.Answer(max_bolp=0.5, oob_side="left", oob_point=iter([1, 2]))
    assert answer.oob_point == (1.0, 2.0)
    assert answer.to_message(3)["oob_point"] == [1.0, 2.0] == answer.to_message(4)["oob_point"]
    assert wogan.Answer(fractions.Fraction(1, 3)).to_message(1)["max_bolp"] == pytest.approx(1 / 3)
    deep = []
    for _ in range(100000):
        deep = [deep]
    cyclic = {}
    cyclic["self"] = cyclic
    for extra, says in [({"x": math.nan}, "Out of range float"), ({"x": [math.inf]}, "Out of range float"),
                        ({"x": {1, 2}}, "set is not JSON serializable"), ({"x": object()}, "object is not"),
                        ({"x": deep}, "recursion"), ({"x": cyclic}, "Circular reference")]:
        with pytest.raises(ValueError, match=f"extra: not JSON: .*{says}"):
            wogan.Answer(max_bolp=0.5, extra=extra)


def test_an_executor_written_with_the_class_drives_a_search():
    run = wogan.run(["--max-tests", "20", "--seed", "1", "--executor", command("geometric_executor.py")])
    # The header names the executor: its command and what it said of itself in its hello reply.
    assert run.header["oracle"] == "executor" and "driver" not in run.header["config"]
    recorded = run.header["config"]["executor"]
    assert recorded["command"].endswith("geometric_executor.py")
    assert recorded["name"] == "Geometric" and recorded["version"] == "1.0", recorded
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


def test_the_binary_says_hello_of_version_3_and_reads_the_reply_before_any_road(monkeypatch, tmp_path):
    """Needs the binary's side of version 3 (a version-2 binary says hello of version 2, and keeps
    no description)."""
    monkeypatch.setenv("HELLO_TO", str(tmp_path / "hellos.jsonl"))
    run = wogan.run(["--max-tests", "12", "--seed", "5", "--jobs", "2", "--executor", command("geometric_executor.py")])
    hellos = [json.loads(line) for line in (tmp_path / "hellos.jsonl").read_text().splitlines()]
    assert hellos and all(h["protocol"] == "wogan-executor" and h["version"] == 3 for h in hellos), hellos
    assert all(h["oob_tolerance"] == 0.85 and h["map_size_m"] > 0 and h["speed_limit_kmh"] > 0 for h in hellos)
    # The reply was read as such: every road was answered with its own answer, none was taken for
    # the reply or the reply for an answer.
    assert [t["id"] for t in run.tests] == list(range(1, 13)) and run.status == 0
    # The first executor's description is kept in the summary, with the roads it drives at once.
    assert run.summary["executor"] == {"name": "Geometric", "version": "1.0",
                                       "settings": {"bolp": "sharpest turn / 0.8 rad"}, "roads_at_once": 1}
    assert all(t["outcome"] in ("PASS", "FAIL") and t["max_bolp"] == pytest.approx(bolp_of(t["road_points"]),
                                                                                    abs=1e-12) for t in run.tests)

def test_a_hello_hook_that_raises_ends_the_run_before_any_road_is_driven(monkeypatch):
    """The first executor answers hello before the run begins: one whose hello hook raises ends the
    run before any test, with its traceback (from stderr) in the summary."""
    monkeypatch.setenv("HELLO_RAISES", "1")
    run = wogan.run(["--max-tests", "10", "--seed", "1", "--executor", command("geometric_executor.py")],
                    check=False)
    assert run.status == 1 and run.tests == [], run.status
    assert run.header["config"]["executor"]["command"].endswith("geometric_executor.py")
    assert "hello" in run.summary["error"]
    assert "RuntimeError: the simulator did not start" in run.summary["error"]


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
    assert [json.loads(line) for line in stdout.splitlines()] == [reply("Noisy"), {"id": 1, "max_bolp": 0.5},
                                                                   {"id": 2, "max_bolp": 0.5}]
    for said in ("print at road 2", "sys.stdout at road 2", "file descriptor 1", "closed", "after serve",
                 "after serve, file descriptor 1"):
        assert said in stderr, said


def test_sigterm_ends_serving_through_close():
    process = start_script("noisy_executor.py", SLOW_AT="2")
    process.stdin.write("".join(json.dumps(m) + "\n" for m in (HELLO, road(1), road(2))))
    process.stdin.flush()
    assert json.loads(process.stdout.readline()) == reply("Noisy")
    assert json.loads(process.stdout.readline()) == {"id": 1, "max_bolp": 0.5}
    while "slow road" not in process.stderr.readline():
        pass
    process.send_signal(signal.SIGTERM)
    stdout, stderr = process.communicate(timeout=30)
    assert process.returncode == 143 and stdout == ""
    assert "closed" in stderr
