"""`--oracle cmd:"..."`: a program that steers wogan's own car, told at each control step what a
lane keeper sees (the controller protocol, version 2, docs/reference.md)."""

import sys
import traceback
from dataclasses import dataclass
from typing import Any, Dict, List, Optional, Tuple

from ._lines import messages, protocol_stdout, write

PROTOCOL = "wogan-controller"
VERSION = 2


@dataclass(frozen=True)
class DriveRoad:
    """The road of the drive about to begin: its control points, the right lane's centre line (a
    point per metre or so), the speed limit (m/s) and what a steering of 1 means (radians)."""

    points: List[Tuple[float, float]]
    lane_centre: List[Tuple[float, float]]
    speed_limit_mps: float
    max_steering_rad: float


@dataclass(frozen=True)
class Observation:
    """What the car sees at one control step. Angles in radians, counter-clockwise; `ahead`: lane
    centre points ahead in the car's frame (x forward, y left, metres); `camera`: the gray frame
    (`width`, `height`, `gray` row-major, top row first) when the run asked for it."""

    step: int
    t: float
    speed_mps: float
    x: float
    y: float
    heading_rad: float
    lateral_offset_m: float
    heading_error_rad: float
    ahead: List[Tuple[float, float]]
    camera: Optional[Dict[str, Any]] = None


@dataclass(frozen=True)
class Control:
    """The car's controls: steering in [-1, 1] of its largest angle, positive to the left;
    throttle and brake in [0, 1] (brake wins when both are positive)."""

    steering: float
    throttle: float
    brake: float = 0.0

    def line(self, step: int) -> Dict[str, Any]:
        """The reply to step `step`; a ValueError names a control out of range."""
        for name, low in (("steering", -1.0), ("throttle", 0.0), ("brake", 0.0)):
            value = getattr(self, name)
            if not isinstance(value, (int, float)) or not low <= value <= 1.0:
                raise ValueError(f"{name}: {value!r} is not a number in [{low:g}, 1]")
        return {"step": step, "steering": float(self.steering), "throttle": float(self.throttle),
                "brake": float(self.brake)}


class Controller:
    """Subclass it, implement `step` (and, if useful, `begin` and `end`), call `serve()`.
    `self.settings` holds `hello`'s fields (`control_hz`, `camera`). An exception in a hook ends
    the controller with its traceback on stderr: wogan ends that drive `ERROR` (`driver_failed`),
    with the traceback's last lines in the result, and starts a new controller for the next."""

    def __init__(self) -> None:
        self.settings: Dict[str, Any] = {}

    def begin(self, road: DriveRoad) -> None:
        """A drive begins on `road`."""

    def step(self, observation: Observation) -> Control:
        """The controls for this step."""
        raise NotImplementedError("a Controller implements step(self, observation) -> wogan.Control")

    def end(self) -> None:
        """The drive ended."""

    def serve(self, source=None) -> None:
        """Steers wogan's car until `bye` or the end of input."""
        source = sys.stdin if source is None else source
        with protocol_stdout() as out:
            try:
                for message in messages(source):
                    kind = message.get("type")
                    if kind == "hello":
                        self.settings = {k: v for k, v in message.items() if k != "type"}
                    elif kind == "road":
                        self.begin(DriveRoad(
                            points=[(p[0], p[1]) for p in message["road_points"]],
                            lane_centre=[(p[0], p[1]) for p in message["lane_centre"]],
                            speed_limit_mps=message["speed_limit_mps"],
                            max_steering_rad=message["max_steering_rad"],
                        ))
                    elif kind == "step":
                        write(out, self.step(observation_of(message)).line(message["step"]))
                    elif kind == "end":
                        self.end()
                    elif kind == "bye":
                        return
            except Exception:
                traceback.print_exc(file=sys.stderr)
                sys.exit(1)


def observation_of(message: Dict[str, Any]) -> Observation:
    """A `step` line as an Observation."""
    return Observation(
        step=message["step"], t=message["t"], speed_mps=message["speed_mps"], x=message["x"],
        y=message["y"], heading_rad=message["heading_rad"],
        lateral_offset_m=message["lateral_offset_m"], heading_error_rad=message["heading_error_rad"],
        ahead=[(p[0], p[1]) for p in message.get("ahead", [])], camera=message.get("camera"),
    )
