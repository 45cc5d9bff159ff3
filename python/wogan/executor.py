"""`wogan run --executor cmd:"..."`: a program that drives each road the search proposes in any
simulator and answers how far the car left its lane (the executor protocol, version 3, in wogan's
docs/reference.md, "Plug points: your own simulator").

    class MyExecutor(wogan.Executor):
        def drive(self, road):
            return wogan.Answer(max_bolp=my_simulator(road.points))

    MyExecutor().serve()

Version 3: the executor answers wogan's `hello` with one line, once it is ready to drive, before
any road (`serve()` does that, describing the executor: `Executor.name`, `version`,
`reported_settings()`). Version 2 had no such reply; a `hello` of version 2 (an older wogan) is
still served, without a reply, which that wogan would take for road 1's answer.
"""

import logging
import numbers
from dataclasses import dataclass, field
from typing import IO, Any, Dict, List, Optional

from . import _protocol
from ._protocol import Message, Point

PROTOCOL = "wogan-executor"
VERSION = 3
# The oldest version served: a hello of version 2 gets no reply (that wogan would take the reply
# for road 1's answer); roads and answers are those of version 3.
OLDEST_VERSION = 2
# The first version whose hello the executor answers.
REPLY_SINCE_VERSION = 3
OUTCOMES = ("PASS", "FAIL", "ERROR")
SIDES = ("left", "right")
# The most a car centre can be from the edges of wogan's 4 m lane (the protocol's bound).
MAX_LANE_DISTANCE_M = 2.0
# The longest drive, simulated seconds, as for wogan's own simulator (the protocol's bound).
MAX_SIM_TIME_S = 3600.0
# The farthest from the map's origin a point (`oob_point`) or a lane distance may be, metres: the
# longest road (the protocol's bound).
MAX_COORDINATE_M = 20_000.0

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
    - `sim_time_s`: simulated seconds of the drive, charged to `--execution-budget` (0 if None),
      at most 3600 (the longest drive).
    - `oob_side` ("left" or "right") and `oob_point` ((x, y) metres, where the car's centre was
      when it left its lane, each within 20,000 m of the origin; only with `oob_side`): `wogan
      report` counts distinct failures by it.
    - `min_lane_distance_m`: the smallest signed distance of the car's centre to its lane's
      edges over the drive, at most 2 (always centred in the 4 m lane), negative once the centre
      left it (not below -20,000); needed by `--fitness distance` (but for an ERROR).
    - `error`: why the road could not be driven (an ERROR's test record keeps it).
    - `extra`: further fields, sent as they are (wogan ignores fields it does not know; a
      pipeline's `execution_data`, say). They must be JSON (no NaN or infinity; checked when
      made), and may not reuse a field's name.

    Numbers are any real numbers (int, float, Fraction, ...) that a float holds: NaN, infinities
    and those beyond a float's range (10**400) are refused. `oob_point` is kept as the checked
    tuple of floats.
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
            raise ValueError(f"max_bolp: {_protocol.shown(self.max_bolp)} is outside [0, 1]")
        if self.outcome is not None and self.outcome not in OUTCOMES:
            raise ValueError(f"outcome: {_protocol.shown(self.outcome)} is not one of {', '.join(OUTCOMES)} "
                             "(or None)")
        if self.sim_time_s is not None and not 0.0 <= _protocol.number(self.sim_time_s, "sim_time_s") <= MAX_SIM_TIME_S:
            raise ValueError(f"sim_time_s: {_protocol.shown(self.sim_time_s)} is outside [0, {MAX_SIM_TIME_S:g}] s "
                             "(the longest drive)")
        if self.oob_side is not None and self.oob_side not in SIDES:
            raise ValueError(f"oob_side: {_protocol.shown(self.oob_side)} is not 'left' or 'right' (or None)")
        if self.oob_point is not None:
            # Kept as checked: an iterator given is read once, here.
            object.__setattr__(self, "oob_point", _protocol.point(self.oob_point, "oob_point"))
            if self.oob_side is None:
                raise ValueError("oob_point: given without oob_side")
            if not all(abs(v) <= MAX_COORDINATE_M for v in self.oob_point):
                raise ValueError(f"oob_point: {self.oob_point!r} is farther than {MAX_COORDINATE_M:g} m from the "
                                 "origin (the longest road)")
        if self.min_lane_distance_m is not None:
            distance = _protocol.number(self.min_lane_distance_m, "min_lane_distance_m")
            if distance > MAX_LANE_DISTANCE_M + 1e-6:
                raise ValueError(f"min_lane_distance_m: {distance!r} is above {MAX_LANE_DISTANCE_M} m, the most "
                                 "a car centre can be from the edges of a 4 m lane")
            if distance < -MAX_COORDINATE_M:
                raise ValueError(f"min_lane_distance_m: {distance!r} is below -{MAX_COORDINATE_M:g} m (the "
                                 "longest road)")
        if self.error is not None and not isinstance(self.error, str):
            raise ValueError(f"error: {_protocol.shown(self.error)} is not text")
        if not isinstance(self.extra, dict):
            raise ValueError(f"extra: {type(self.extra).__name__} is not a dict of further fields")
        for name in self.extra:
            if not isinstance(name, str):
                raise ValueError(f"extra: the field name {_protocol.shown(name)} is not text")
            if name in _FIELDS:
                raise ValueError(f"extra: {name!r} is a field of the answer itself; give it as one")
        _protocol.json_object(self.extra, "extra")

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
            message["oob_point"] = list(self.oob_point)
        if self.error is not None:
            message["error"] = self.error
        message.update(self.extra)
        return message


class Executor:
    """An executor: subclass it, implement `drive`, call `serve()`.

    `serve()` speaks the protocol on standard input and output: it reads `hello` (its fields are
    then in `self.settings`: `map_size_m`, `oob_tolerance`, `speed_limit_kmh`, ...), calls the
    `hello(settings)` hook, and then answers `hello` with one line saying the executor is ready;
    it calls `drive(road)` for each road and writes its answer naming the road's `id`, flushed at
    once, and returns at `bye` or the end of input. An exception raised by `drive` (or an answer
    that cannot be sent) answers that road ERROR with the exception's message, its traceback goes
    to stderr, and serving goes on (`drive_failed` decides otherwise). Standard output carries
    protocol lines alone: from serve() on, `print` and anything else written there (native code
    too) go to stderr.

    The reply to `hello` is written once `hello(settings)` returns: start a slow simulator there,
    so that wogan's timeout for the reply covers its start and a start that fails (an exception
    leaves serve() and ends the program with its traceback, before any reply) is seen before any
    road is sent. The reply describes the executor:

    - `name`: the executor's name (text); None, the default, names it by its class.
    - `version`: its version (text); None, the default, says none.
    - `reported_settings()`: its own settings (a dict, JSON: a policy, a speed, a simulator's
      version...), called after `hello(settings)`; None, the default, says none.

    A bad description (a name that is not text, settings that are not JSON) is a ValueError
    naming it, raised from serve() before the reply. A `hello` of protocol version 2 (an older
    wogan, which would take any line written before road 1's answer for it) gets no reply; roads
    are served as in version 3.

    Hooks besides `drive`, all optional: `hello(settings)` when wogan's `hello` arrives,
    `drive_failed(road, error)`, `close()` when serving ends.
    """

    name: Optional[str] = None
    version: Optional[str] = None

    def __init__(self) -> None:
        self.settings: Dict[str, Any] = {}

    def hello(self, settings: Dict[str, Any]) -> None:
        """wogan's `hello` arrived; `settings` (also `self.settings`) holds its fields. Get ready
        to drive here: the reply to `hello` follows when this returns."""

    def reported_settings(self) -> Optional[Dict[str, Any]]:
        """The executor's own settings, reported in the reply to `hello` (called after
        `hello(settings)`): a dict that JSON carries, or None (the default) to report none."""
        return None

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
        """Answers wogan's `hello` and roads until `bye` or the end of `input`, then calls
        `close()`. `input` and `output` default to standard input and output (see the class);
        streams given (a named pipe, a socket's file) are used as they are."""
        try:
            with _protocol.session(input, output) as (source, out):
                _protocol.exchange(source, PROTOCOL, VERSION, {"road": lambda m: self._answer(m, out)},
                                   lambda settings: self._hello(settings, out), oldest=OLDEST_VERSION)
        finally:
            self.close()

    def _description(self) -> Dict[str, Any]:
        """The `executor` object of the reply to `hello`: `name` (this class's name unless `name`
        is set), `version` and `settings` (`reported_settings()`) when given. A ValueError names
        a field that is not text, or settings that are not JSON."""
        name = type(self).__name__ if self.name is None else self.name
        if not isinstance(name, str):
            raise ValueError(f"name: {_protocol.shown(name)} is not text (the executor's name)")
        described: Dict[str, Any] = {"name": name}
        if self.version is not None:
            if not isinstance(self.version, str):
                raise ValueError(f"version: {_protocol.shown(self.version)} is not text (the executor's version)")
            described["version"] = self.version
        settings = self.reported_settings()
        if settings is not None:
            if isinstance(settings, dict) and not all(isinstance(key, str) for key in settings):
                raise ValueError("reported_settings(): a setting's name is not text")
            _protocol.json_object(settings, "reported_settings()")
            described["settings"] = settings
        return described

    def _ready(self, settings: Dict[str, Any]) -> None:
        """wogan's `hello` arrived: its settings kept, then the hook (which may start a simulator)."""
        self.settings = settings
        self.hello(settings)

    def _hello(self, settings: Dict[str, Any], out: _protocol.Output) -> bool:
        """wogan's `hello`: the hook, then the reply (not to a hello of a version before 3);
        False once `out` is gone."""
        self._ready(settings)
        if not replies_to(settings):
            return True
        return out.write({"type": "hello", "protocol": PROTOCOL, "version": VERSION,
                          "executor": self._description()})

    def _answer(self, message: Message, out: _protocol.Output) -> bool:
        """Drives the road of one `road` line and writes its answer; False once `out` is gone."""
        answer = self._answer_to(message)
        return True if answer is None else out.write(answer)

    def _answer_to(self, message: Message) -> Optional[Message]:
        """The answer line to one `road` line, as a dict that JSON carries: the drive's answer, or
        ERROR with the reason when the line holds no road, when `drive` raises or when its answer
        cannot be sent (`drive_failed` says how; it may raise, to stop serving). None for a line
        without a road number, which no answer could name. Both `serve()` and the Ray pool
        (`python -m wogan.ray`, where each actor's executor drives its roads) answer with it."""
        road_id = road_number(message)
        if road_id is None:
            log.error("%s: a road without a road number cannot be answered: id %r", PROTOCOL, message.get("id"))
            return None
        try:
            points = message.get("road_points")
            if not isinstance(points, list):
                raise ValueError(f"road_points: {points!r} is not a list of [x, y] points")
            road = Road(road_id, [_protocol.point(p, f"road_points[{i}]") for i, p in enumerate(points)], message)
        except ValueError as error:
            # Not a road: nothing to drive (drive_failed is for the executor's own faults).
            log.error("road %d: %s", road_id, error)
            return Answer(0.0, "ERROR", 0.0, error=f"not a road: {error}").to_message(road_id)
        try:
            answer = self.drive(road)
            if not isinstance(answer, Answer):
                raise TypeError(f"drive() returned {type(answer).__name__}, not a wogan.Answer")
            return _protocol.sendable(answer.to_message(road_id))
        except Exception as error:  # one road's fault does not end the executor
            failed = self.drive_failed(road, error)  # which may raise: serving ends
            log.error("road %d: drive failed: %s: %s", road_id, type(error).__name__, error, exc_info=True)
            if not isinstance(failed, Answer):
                raise TypeError(f"drive_failed() returned {type(failed).__name__}, not a wogan.Answer") from error
            return _protocol.sendable(failed.to_message(road_id))


def road_number(message: Message) -> Optional[int]:
    """The `id` of a `road` line when it is a road number (a whole number, not negative), else
    None: such a line cannot be answered, as no answer could name it."""
    road_id = message.get("id")
    if isinstance(road_id, bool) or not isinstance(road_id, int) or road_id < 0:
        return None
    return road_id


def replies_to(settings: Dict[str, Any]) -> bool:
    """Whether wogan's `hello` (its fields, `settings`) is answered: not one of a version before 3
    (an older wogan, which would take the reply for road 1's answer)."""
    said = settings.get("version")
    if isinstance(said, numbers.Real) and not isinstance(said, bool) and said < REPLY_SINCE_VERSION:
        log.info("%s: hello of version %r (an older wogan): not answered", PROTOCOL, said)
        return False
    return True
