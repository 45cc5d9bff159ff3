"""`wogan run --executor cmd:"..."`: a program that drives each road the search proposes in any
simulator and answers how far the car left its lane (the executor protocol, version 2, in wogan's
docs/reference.md, "Plug points: your own simulator").

    class MyExecutor(wogan.Executor):
        def drive(self, road):
            return wogan.Answer(max_bolp=my_simulator(road.points))

    MyExecutor().serve()
"""

import logging
from dataclasses import dataclass, field
from typing import IO, Any, Dict, List, Optional

from . import _protocol
from ._protocol import Message, Point

PROTOCOL = "wogan-executor"
VERSION = 2
OUTCOMES = ("PASS", "FAIL", "ERROR")
SIDES = ("left", "right")
# The most a car centre can be from the edges of wogan's 4 m lane (the protocol's bound).
MAX_LANE_DISTANCE_M = 2.0

log = logging.getLogger("wogan")


@dataclass(frozen=True)
class Road:
    """A road to drive. `id`: the test's number in the run, from 1 (the answer names it; serve()
    does that). `points`: the road's points, `(x, y)` in metres, the competition's form (wogan's
    simulator lays its lane along the competition's spline through them). `message`: the `road`
    line as wogan wrote it, for fields a newer wogan may add."""

    id: int
    points: List[Point]
    message: Message = field(default_factory=dict, repr=False, compare=False)


_FIELDS = ("id", "max_bolp", "outcome", "sim_time_s", "oob_side", "oob_point", "min_lane_distance_m", "error")


@dataclass(frozen=True)
class Answer:
    """How the drive of a road went; checked when made (a ValueError names the field at fault).

    - `max_bolp` (required): the largest share of the car's body outside its lane, in [0, 1].
    - `outcome`: "PASS", "FAIL" or "ERROR"; None lets wogan judge: FAIL when `max_bolp` exceeds
      the run's tolerance (`settings["oob_tolerance"]`), else PASS.
    - `sim_time_s`: simulated seconds of the drive, charged to `--execution-budget` (0 if None).
    - `oob_side` ("left" or "right") and `oob_point` ((x, y) metres, where the car's centre was
      when it left its lane; only with `oob_side`): `wogan report` counts distinct failures by it.
    - `min_lane_distance_m`: the smallest signed distance of the car's centre to its lane's
      edges over the drive, at most 2 (always centred in the 4 m lane), negative once the centre
      left it; needed by `--fitness distance` (but for an ERROR).
    - `error`: why the road could not be driven (an ERROR's test record keeps it).
    - `extra`: further fields, sent as they are (wogan ignores fields it does not know; a
      pipeline's `execution_data`, say). They must be JSON, and may not reuse a field's name.
    """

    max_bolp: float
    outcome: Optional[str] = None
    sim_time_s: Optional[float] = None
    oob_side: Optional[str] = None
    oob_point: Optional[Point] = None
    min_lane_distance_m: Optional[float] = None
    error: Optional[str] = None
    extra: Dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        bolp = _protocol.number(self.max_bolp, "max_bolp")
        if not 0.0 <= bolp <= 1.0:
            raise ValueError(f"max_bolp: {self.max_bolp!r} is outside [0, 1]")
        if self.outcome is not None and self.outcome not in OUTCOMES:
            raise ValueError(f"outcome: {self.outcome!r} is not one of {', '.join(OUTCOMES)} (or None)")
        if self.sim_time_s is not None and _protocol.number(self.sim_time_s, "sim_time_s") < 0.0:
            raise ValueError(f"sim_time_s: {self.sim_time_s!r} is below 0")
        if self.oob_side is not None and self.oob_side not in SIDES:
            raise ValueError(f"oob_side: {self.oob_side!r} is not 'left' or 'right' (or None)")
        if self.oob_point is not None:
            _protocol.point(self.oob_point, "oob_point")
            if self.oob_side is None:
                raise ValueError("oob_point: given without oob_side")
        if self.min_lane_distance_m is not None:
            distance = _protocol.number(self.min_lane_distance_m, "min_lane_distance_m")
            if distance > MAX_LANE_DISTANCE_M + 1e-6:
                raise ValueError(f"min_lane_distance_m: {distance!r} is above {MAX_LANE_DISTANCE_M} m, the most "
                                 "a car centre can be from the edges of a 4 m lane")
        if self.error is not None and not isinstance(self.error, str):
            raise ValueError(f"error: {self.error!r} is not text")
        if not isinstance(self.extra, dict):
            raise ValueError(f"extra: {type(self.extra).__name__} is not a dict of further fields")
        for name in self.extra:
            if not isinstance(name, str):
                raise ValueError(f"extra: the field name {name!r} is not text")
            if name in _FIELDS:
                raise ValueError(f"extra: {name!r} is a field of the answer itself; give it as one")

    def to_message(self, road_id: int) -> Message:
        """The answer line to road `road_id`, as a dict (serve() writes it)."""
        message: Message = {"id": road_id, "max_bolp": float(self.max_bolp)}
        if self.outcome is not None:
            message["outcome"] = self.outcome
        if self.sim_time_s is not None:
            message["sim_time_s"] = float(self.sim_time_s)
        if self.min_lane_distance_m is not None:
            message["min_lane_distance_m"] = float(self.min_lane_distance_m)
        if self.oob_side is not None:
            message["oob_side"] = self.oob_side
        if self.oob_point is not None:
            message["oob_point"] = list(_protocol.point(self.oob_point, "oob_point"))
        if self.error is not None:
            message["error"] = self.error
        message.update(self.extra)
        return message


class Executor:
    """An executor: subclass it, implement `drive`, call `serve()`.

    `serve()` speaks the protocol on standard input and output: it reads `hello` (its fields are
    then in `self.settings`: `map_size_m`, `oob_tolerance`, `speed_limit_kmh`, ...), calls
    `drive(road)` for each road and writes its answer naming the road's `id`, flushed at once,
    and returns at `bye` or the end of input. An exception raised by `drive` (or an answer that
    cannot be sent) answers that road ERROR with the exception's message, its traceback goes to
    stderr, and serving goes on (`drive_failed` decides otherwise). Standard output carries
    protocol lines alone: from serve() on, `print` and anything else written there (native code
    too) go to stderr.

    Hooks besides `drive`, all optional: `hello(settings)` when wogan's `hello` arrives,
    `drive_failed(road, error)`, `close()` when serving ends.
    """

    def __init__(self) -> None:
        self.settings: Dict[str, Any] = {}

    def hello(self, settings: Dict[str, Any]) -> None:
        """wogan's `hello` arrived; `settings` (also `self.settings`) holds its fields."""

    def drive(self, road: Road) -> Answer:
        """Drives `road` and says how it went."""
        raise NotImplementedError("an Executor implements drive(self, road) -> wogan.Answer")

    def drive_failed(self, road: Road, error: Exception) -> Answer:
        """The answer to `road` when `drive` raised `error` (or its answer could not be sent): by
        default ERROR with the exception's type and message. Raise to stop serving instead."""
        return Answer(max_bolp=0.0, outcome="ERROR", sim_time_s=0.0, error=f"{type(error).__name__}: {error}")

    def close(self) -> None:
        """Serving ends (after `bye`, at the end of input, or on an exception leaving serve())."""

    def serve(self, input: Optional[IO[Any]] = None, output: Optional[IO[str]] = None) -> None:
        """Answers wogan's roads until `bye` or the end of `input`, then calls `close()`.
        `input` and `output` default to standard input and output (see the class); streams
        given (a named pipe, a socket's file) are used as they are."""
        try:
            with _protocol.session(input, output) as (source, out):
                _protocol.exchange(source, PROTOCOL, VERSION, {"road": lambda m: self._answer(m, out)},
                                   self._hello)
        finally:
            self.close()

    def _hello(self, settings: Dict[str, Any]) -> None:
        self.settings = settings
        self.hello(settings)

    def _answer(self, message: Message, out: _protocol.Output) -> bool:
        """Drives the road of one `road` line and writes its answer; False once `out` is gone."""
        road_id = message.get("id")
        if isinstance(road_id, bool) or not isinstance(road_id, int) or road_id < 0:
            log.error("%s: a road without a road number cannot be answered: id %r", PROTOCOL, road_id)
            return True
        try:
            points = message.get("road_points")
            if not isinstance(points, list):
                raise ValueError(f"road_points: {points!r} is not a list of [x, y] points")
            road = Road(road_id, [_protocol.point(p, f"road_points[{i}]") for i, p in enumerate(points)], message)
        except ValueError as error:
            # Not a road: nothing to drive (drive_failed is for the executor's own faults).
            log.error("road %d: %s", road_id, error)
            return out.write(Answer(0.0, "ERROR", 0.0, error=f"not a road: {error}").to_message(road_id))
        try:
            answer = self.drive(road)
            if not isinstance(answer, Answer):
                raise TypeError(f"drive() returned {type(answer).__name__}, not a wogan.Answer")
            return out.write(answer.to_message(road_id))
        except Exception as error:  # one road's fault does not end the executor
            failed = self.drive_failed(road, error)  # which may raise: serving ends
            log.error("road %d: drive failed: %s: %s", road_id, type(error).__name__, error, exc_info=True)
            if not isinstance(failed, Answer):
                raise TypeError(f"drive_failed() returned {type(failed).__name__}, not a wogan.Answer") from error
            return out.write(failed.to_message(road_id))
