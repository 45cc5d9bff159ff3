"""wogan.Controller, Observation, Frame and Control: in-process over given streams, and a
controller written with the class driving real searches and drives."""

import fractions
import io
import json

import pytest
from helpers import ROADS, command, wogan_cli

import wogan

HELLO = {"type": "hello", "protocol": "wogan-controller", "version": 2, "units": "metres, seconds, radians",
         "control_hz": 20.0, "camera": True}
ROAD = {"type": "road", "road_points": [[100.0, 10.0], [100.0, 60.0]], "lane_centre": [[102.0, 10.0], [102.0, 11.0]],
        "speed_limit_mps": 19.44, "max_steering_rad": 0.61}


def step(n, **more):
    return {"type": "step", "step": n, "t": 0.05 * (n - 1), "speed_mps": 3.0, "x": 102.0, "y": 12.0,
            "heading_rad": 1.57, "lateral_offset_m": -0.1, "heading_error_rad": 0.02,
            "ahead": [[3.0, 0.1], [6.0, 0.3]], **more}


class Recorder(wogan.Controller):
    def __init__(self):
        super().__init__()
        self.events = []

    def begin(self, road):
        self.events.append(("begin", road.points, road.lane_centre[0], road.speed_limit_mps, road.max_steering_rad))

    def step(self, seen):
        self.events.append(("step", seen.step, seen.ahead, seen.camera and seen.camera.row(1)))
        return wogan.Control(steering=-0.5, throttle=1, brake=0)

    def end(self):
        self.events.append(("end",))


def test_each_step_is_replied_to_by_its_number_and_the_hooks_mark_the_drives():
    frame = {"width": 3, "height": 2, "gray": [0, 1, 2, 10, 11, 12]}
    lines = [HELLO, ROAD, step(1, camera=frame), step(2, camera=frame), {"type": "end"}, {"type": "odd"},
             ROAD, step(1, camera=frame), {"type": "end"}, {"type": "bye"}, step(9)]
    out = io.StringIO()
    controller = Recorder()
    controller.serve(io.StringIO("".join(json.dumps(m) + "\n" for m in lines)), out)
    replies = [json.loads(line) for line in out.getvalue().splitlines()]
    assert replies == [{"step": n, "steering": -0.5, "throttle": 1.0, "brake": 0.0} for n in (1, 2, 1)]
    assert controller.settings["control_hz"] == 20.0 and controller.settings["camera"] is True
    begin = ("begin", [(100.0, 10.0), (100.0, 60.0)], (102.0, 10.0), 19.44, 0.61)
    seen = [(3.0, 0.1), (6.0, 0.3)]
    assert controller.events == [begin, ("step", 1, seen, [10, 11, 12]), ("step", 2, seen, [10, 11, 12]), ("end",),
                                 begin, ("step", 1, seen, [10, 11, 12]), ("end",)]


def test_controls_are_checked_or_clamped():
    for fields, says in [({"steering": 1.2, "throttle": 0}, "steering: 1.2 is outside"),
                         ({"steering": 0, "throttle": -0.1}, "throttle: -0.1 is outside"),
                         ({"steering": 0, "throttle": 0, "brake": float("nan")}, "brake: nan is not a finite")]:
        with pytest.raises(ValueError, match=says):
            wogan.Control(**fields)
    assert wogan.Control.clamped(-3.0, 2.0, -1.0) == wogan.Control(-1.0, 1.0, 0.0)
    with pytest.raises(ValueError, match="steering"):
        wogan.Control.clamped(float("inf"), 0.0)
    # Numbers beyond a float's range: refused by name when made, clamped by clamped().
    for fields, says in [({"steering": 10**400, "throttle": 0}, "steering: 1000"),
                         ({"steering": 0, "throttle": fractions.Fraction(-10**400, 7)}, r"throttle: Fraction\(-1000"),
                         ({"steering": 0, "throttle": 0, "brake": 10**5000}, "brake: <int too large to show>")]:
        with pytest.raises(ValueError, match=f"{says}.* beyond a float's range"):
            wogan.Control(**fields)
    assert wogan.Control.clamped(steering=10**400, throttle=0) == wogan.Control(1.0, 0.0, 0.0)
    assert wogan.Control.clamped(-10**400, fractions.Fraction(10**400, 3), 10**5000) == wogan.Control(-1.0, 1.0, 1.0)
    assert wogan.Control.clamped(fractions.Fraction(1, 10**400), -10**400) == wogan.Control(0.0, 0.0, 0.0)
    for steering in (float("nan"), float("-inf"), "1", None, True):
        with pytest.raises(ValueError, match="steering: .* not a finite number"):
            wogan.Control.clamped(steering, 0.0)
    frame = wogan.Frame(3, 2, [0, 1, 2, 10, 11, 12])
    assert (frame.pixel(2, 1), frame.row(0)) == (12, [0, 1, 2])
    with pytest.raises(IndexError):
        frame.row(2)


def test_a_controller_written_with_the_class_drives_a_search():
    run = wogan.run(["--max-tests", "20", "--seed", "1", "--oracle", command("lane_controller.py")])
    assert run.header["oracle"] == "controller"
    assert len(run.tests) == 20 and run.summary["executed"] == 20
    # Every drive steered by the controller to its end: none broke (a stray stdout line would).
    assert all(t["outcome"] in ("PASS", "FAIL") for t in run.tests), [t.get("error") for t in run.tests]
    assert all(t["sim_time_s"] > 5.0 for t in run.tests)
    assert sum(t["outcome"] == "PASS" for t in run.tests) >= 15, [t["max_bolp"] for t in run.tests]


def test_a_step_that_raises_fails_its_drive_and_a_new_controller_drives_the_next(monkeypatch):
    monkeypatch.setenv("RAISE_AT", "2:5")
    roads = "".join(json.dumps({"road_points": r}) + "\n" for r in ROADS)
    done = wogan_cli("simulate", "--oracle", command("lane_controller.py"), input=roads)
    assert done.returncode == 0, done.stderr
    results = [json.loads(line) for line in done.stdout.splitlines()]
    assert [r["outcome"] for r in results] == ["PASS", "ERROR", "PASS"], results
    assert results[1]["reason"] == "driver_failed"
    assert "RuntimeError: step 5 of drive 2 refused on purpose" in results[1]["error"]
