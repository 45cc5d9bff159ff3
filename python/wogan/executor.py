"""`wogan run --executor cmd:"..."`: a program that drives each road the search proposes in any
simulator and answers how far the car left its lane (the executor protocol, version 2,
docs/reference.md)."""

import sys
import traceback
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Tuple

from ._lines import messages, protocol_stdout, write

PROTOCOL = "wogan-executor"
VERSION = 2
OUTCOMES = ("PASS", "FAIL", "ERROR")
SIDES = ("left", "right")


@dataclass(frozen=True)
class Road:
    """A road to drive: its number in the run and its points, metres (the competition's form)."""

    id: int
    points: List[Tuple[float, float]]


@dataclass
class Answer:
    """How a drive went. `max_bolp`: the largest share of the car's body outside its lane, in
    [0, 1]. `outcome`: PASS, FAIL or ERROR (None: FAIL when `max_bolp` exceeds the run's
    tolerance). `sim_time_s`: simulated seconds, charged to the run's execution budget.
    `oob_side` ("left" or "right") and `oob_point` ((x, y), the car centre when it left): where it
    left. `min_lane_distance_m`: the smallest signed distance of the car centre to its lane's
    edges (needed by `--fitness distance`). `error`: why an ERROR. `extra`: further fields, sent
    as they are (wogan ignores what it does not know)."""

    max_bolp: float
    outcome: Optional[str] = None
    sim_time_s: Optional[float] = None
    oob_side: Optional[str] = None
    oob_point: Optional[Tuple[float, float]] = None
    min_lane_distance_m: Optional[float] = None
    error: Optional[str] = None
    extra: Dict[str, Any] = field(default_factory=dict)

    def line(self, road_id: int) -> Dict[str, Any]:
        """The answer line to road `road_id`; a ValueError names a field out of range."""
        if not isinstance(self.max_bolp, (int, float)) or not 0.0 <= self.max_bolp <= 1.0:
            raise ValueError(f"max_bolp: {self.max_bolp!r} is not a number in [0, 1]")
        if self.outcome is not None and self.outcome not in OUTCOMES:
            raise ValueError(f"outcome: {self.outcome!r} is not one of {', '.join(OUTCOMES)}")
        if self.oob_side is not None and self.oob_side not in SIDES:
            raise ValueError(f"oob_side: {self.oob_side!r} is not 'left' or 'right'")
        if self.oob_point is not None and self.oob_side is None:
            raise ValueError("oob_point: given without oob_side")
        if self.sim_time_s is not None and not self.sim_time_s >= 0.0:
            raise ValueError(f"sim_time_s: {self.sim_time_s!r} is not a number of seconds >= 0")
        line: Dict[str, Any] = {**self.extra, "id": road_id, "max_bolp": float(self.max_bolp)}
        for name in ("outcome", "sim_time_s", "oob_side", "min_lane_distance_m", "error"):
            value = getattr(self, name)
            if value is not None:
                line[name] = value
        if self.oob_point is not None:
            line["oob_point"] = [float(self.oob_point[0]), float(self.oob_point[1])]
        return line


class Executor:
    """Subclass it, implement `drive`, call `serve()`. `self.settings` holds `hello`'s fields
    (`map_size_m`, `oob_tolerance`, `speed_limit_kmh`, ...) once wogan has sent it."""

    def __init__(self) -> None:
        self.settings: Dict[str, Any] = {}

    def drive(self, road: Road) -> Answer:
        """Drives `road` and says how it went."""
        raise NotImplementedError("an Executor implements drive(self, road) -> wogan.Answer")

    def serve(self, source=None) -> None:
        """Answers wogan's roads until `bye` or the end of input. An exception raised by `drive`
        (or an answer out of range) answers that road ERROR with its message, and serving goes
        on. Anything printed meanwhile goes to stderr."""
        source = sys.stdin if source is None else source
        with protocol_stdout() as out:
            for message in messages(source):
                kind = message.get("type")
                if kind == "hello":
                    self.settings = {k: v for k, v in message.items() if k != "type"}
                elif kind == "road":
                    write(out, self._answer(message))
                elif kind == "bye":
                    return

    def _answer(self, message: Dict[str, Any]) -> Dict[str, Any]:
        road_id = message.get("id")
        try:
            points = [(float(x), float(y)) for x, y, *_ in message["road_points"]]
            return self.drive(Road(road_id, points)).line(road_id)
        except Exception as error:  # a broken road must not end the executor
            traceback.print_exc(file=sys.stderr)
            text = f"{type(error).__name__}: {error}"
            return {"id": road_id, "max_bolp": 0.0, "outcome": "ERROR", "sim_time_s": 0.0, "error": text}
