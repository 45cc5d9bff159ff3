"""`--oracle cmd:"..."`: a program that steers wogan's own car, told at each control step what a
lane keeper sees (the controller protocol, version 2, in wogan's docs/reference.md, "Plug points:
your own lane keeper").

    class MyKeeper(wogan.Controller):
        def step(self, seen):
            return wogan.Control(steering=..., throttle=0.5, brake=0.0)

    MyKeeper().serve()
"""

from dataclasses import dataclass, field
from typing import IO, Any, Dict, List, Optional

from . import _protocol
from ._protocol import Message, Point

PROTOCOL = "wogan-controller"
VERSION = 2


@dataclass(frozen=True)
class DriveRoad:
    """The road of a drive about to begin: its control points (`points`), the right lane's centre
    line, where the car should drive (`lane_centre`, about a point per metre), the speed limit
    (m/s) and the car's largest steering angle, what a steering of 1 means (radians). `message`:
    the `road` line as wogan wrote it."""

    points: List[Point]
    lane_centre: List[Point]
    speed_limit_mps: float
    max_steering_rad: float
    message: Message = field(default_factory=dict, repr=False, compare=False)


@dataclass(frozen=True)
class Frame:
    """A camera frame: `width` x `height` gray values in [0, 255], row by row from the top row
    (wogan's is the 66 x 200 frame of DAVE-2's camera)."""

    width: int
    height: int
    gray: List[int] = field(repr=False)

    def row(self, y: int) -> List[int]:
        """Row `y`, from 0 at the top."""
        if not 0 <= y < self.height:
            raise IndexError(f"row {y} of a frame {self.height} rows high")
        return self.gray[y * self.width:(y + 1) * self.width]

    def pixel(self, x: int, y: int) -> int:
        """The gray value at column `x`, row `y` (0, 0: top left)."""
        if not (0 <= x < self.width and 0 <= y < self.height):
            raise IndexError(f"pixel ({x}, {y}) of a {self.width} x {self.height} frame")
        return self.gray[y * self.width + x]


@dataclass(frozen=True)
class Observation:
    """What the car sees at one control step. `step`: its number in the drive, from 1; `t`:
    simulated seconds since the drive began; `x`, `y`: the car's centre (metres); `heading_rad`:
    counter-clockwise from east; `lateral_offset_m`: from the lane's centre, positive when the car
    is left of it; `heading_error_rad`: the car's heading minus the lane's, in (-pi, pi], positive
    to the left; `ahead`: lane-centre points ahead in the car's frame (x forward, y left, metres);
    `camera`: the frame, when the run asked for it (`{"driver": {"camera": true}}`), else None.
    `message`: the `step` line as wogan wrote it."""

    step: int
    t: float
    speed_mps: float
    x: float
    y: float
    heading_rad: float
    lateral_offset_m: float
    heading_error_rad: float
    ahead: List[Point]
    camera: Optional[Frame] = None
    message: Message = field(default_factory=dict, repr=False, compare=False)


@dataclass(frozen=True)
class Control:
    """The car's controls for one step, checked when made (a ValueError names the one at fault):
    `steering` in [-1, 1], a share of the car's largest angle, positive to the left; `throttle`
    and `brake` in [0, 1] (brake wins when both are positive). `Control.clamped(...)` clamps
    finite values into their ranges instead."""

    steering: float
    throttle: float
    brake: float = 0.0

    def __post_init__(self) -> None:
        for name, low in (("steering", -1.0), ("throttle", 0.0), ("brake", 0.0)):
            value = _protocol.number(getattr(self, name), name)
            if not low <= value <= 1.0:
                raise ValueError(f"{name}: {_protocol.shown(getattr(self, name))} is outside [{low:g}, 1]")

    @classmethod
    def clamped(cls, steering: float, throttle: float, brake: float = 0.0) -> "Control":
        """The controls, each clamped into its range: any finite real number, one too large for a
        float too (10**400 is 1). NaN, an infinity or what is not a number is still a
        ValueError naming the control."""
        return cls(_protocol.clamped(steering, "steering", -1.0, 1.0),
                   _protocol.clamped(throttle, "throttle", 0.0, 1.0),
                   _protocol.clamped(brake, "brake", 0.0, 1.0))

    def to_message(self, step: int) -> Message:
        """The reply line to step `step`, as a dict (serve() writes it)."""
        return {"step": step, "steering": float(self.steering), "throttle": float(self.throttle),
                "brake": float(self.brake)}


class Controller:
    """A controller: subclass it, implement `step`, call `serve()`.

    `serve()` speaks the protocol on standard input and output: it reads `hello` (its fields are
    then in `self.settings`: `control_hz`, `camera`), calls `begin(road)` when a drive begins,
    `step(observation)` at each control step, writing its Control as the reply naming the step,
    flushed at once, and `end()` when the drive ends; it returns at `bye` or the end of input.
    Standard output carries protocol lines alone: from serve() on, `print` and anything else
    written there (native code too) go to stderr.

    The protocol has no way to answer a step with an error: an exception raised in a hook (or a
    Control out of range) leaves serve() and ends the program with its traceback on stderr; wogan
    ends that drive ERROR (`driver_failed`, with the last stderr lines in the result's `error`) and
    starts a new controller for the next drive.

    Hooks besides `step`, all optional: `hello(settings)`, `begin(road)`, `end()`, `close()` when
    serving ends.
    """

    def __init__(self) -> None:
        self.settings: Dict[str, Any] = {}

    def hello(self, settings: Dict[str, Any]) -> None:
        """wogan's `hello` arrived; `settings` (also `self.settings`) holds its fields."""

    def begin(self, road: DriveRoad) -> None:
        """A drive begins on `road`."""

    def step(self, observation: Observation) -> Control:
        """The controls for this step."""
        raise NotImplementedError("a Controller implements step(self, observation) -> wogan.Control")

    def end(self) -> None:
        """The drive ended (the car reached the road's end, left its lane, stopped or ran out of
        time)."""

    def close(self) -> None:
        """Serving ends (after `bye`, at the end of input, or on an exception leaving serve())."""

    def serve(self, input: Optional[IO[Any]] = None, output: Optional[IO[str]] = None) -> None:
        """Steers wogan's car until `bye` or the end of `input`, then calls `close()`. `input` and
        `output` default to standard input and output (see the class); streams given are used as
        they are."""
        try:
            with _protocol.session(input, output) as (source, out):
                _protocol.exchange(source, PROTOCOL, VERSION, {
                    "step": lambda m: self._step(m, out),
                    "road": lambda m: self.begin(road_of(m)),
                    "end": lambda m: self.end(),
                }, self._hello)
        finally:
            self.close()

    def _hello(self, settings: Dict[str, Any]) -> None:
        self.settings = settings
        self.hello(settings)

    def _step(self, message: Message, out: _protocol.Output) -> bool:
        """Answers one `step` line with `step()`'s controls; False once `out` is gone."""
        observation = observation_of(message)
        control = self.step(observation)
        if not isinstance(control, Control):
            raise TypeError(f"step() returned {type(control).__name__}, not a wogan.Control")
        return out.write(control.to_message(observation.step))


def _points(value: Any, name: str) -> List[Point]:
    if not isinstance(value, list):
        raise ValueError(f"{name}: {value!r} is not a list of points")
    return [_protocol.point(p, f"{name}[{i}]") for i, p in enumerate(value)]


def road_of(message: Message) -> DriveRoad:
    """A `road` line as a DriveRoad; a ValueError names a field wogan did not send right."""
    return DriveRoad(
        points=_points(message.get("road_points"), "road_points"),
        lane_centre=_points(message.get("lane_centre"), "lane_centre"),
        speed_limit_mps=_protocol.number(message.get("speed_limit_mps"), "speed_limit_mps"),
        max_steering_rad=_protocol.number(message.get("max_steering_rad"), "max_steering_rad"),
        message=message,
    )


def observation_of(message: Message) -> Observation:
    """A `step` line as an Observation; a ValueError names a field wogan did not send right."""
    step = message.get("step")
    if isinstance(step, bool) or not isinstance(step, int) or step < 0:
        raise ValueError(f"step: {step!r} is not a step number")
    camera = message.get("camera")
    frame = None
    if camera is not None:
        try:
            width, height, gray = int(camera["width"]), int(camera["height"]), camera["gray"]
        except (KeyError, TypeError, ValueError):
            raise ValueError("camera: not a frame {width, height, gray}") from None
        if not isinstance(gray, list) or len(gray) != width * height:
            raise ValueError(f"camera: gray does not hold {width} x {height} values")
        frame = Frame(width, height, gray)
    number = _protocol.number
    return Observation(
        step=step, t=number(message.get("t"), "t"), speed_mps=number(message.get("speed_mps"), "speed_mps"),
        x=number(message.get("x"), "x"), y=number(message.get("y"), "y"),
        heading_rad=number(message.get("heading_rad"), "heading_rad"),
        lateral_offset_m=number(message.get("lateral_offset_m"), "lateral_offset_m"),
        heading_error_rad=number(message.get("heading_error_rad"), "heading_error_rad"),
        ahead=_points(message.get("ahead", []), "ahead"), camera=frame, message=message,
    )

