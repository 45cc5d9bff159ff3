"""The drive as the SBST competition pipeline records it (`--execution-data`), for the pipeline's
generators in scripts/peers, which read the drive: one array of the pipeline's 17
`SimulationDataRecord` fields per sample, as `wogan simulate --execution-data` gives them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .constants import ROAD_HEIGHT_M
from .lane_monitor import LaneMonitor
from .road import lanes

# The competition pipeline's `SimulationDataRecord` fields, in its order (`--execution-data`).
RECORD_FIELDS = ("timer", "pos", "dir", "vel", "steering", "steering_input", "brake",
                 "brake_input", "throttle", "throttle_input", "wheelspeed", "vel_kmh", "is_oob",
                 "oob_counter", "max_oob_percentage", "oob_distance", "oob_percentage")


@dataclass
class ExecutionData:
    """The drive as the competition pipeline records it, one 17-field array per sample, mapped as
    `wogan simulate --execution-data` maps its own samples (crates/cli/src/files/sbst_format.rs):
    the pipeline's out-of-bound monitor run over BOLP at the tolerance, `oob_distance` the car
    centre's distance inside the nearer edge of its lane, the driver's command as both input and
    applied value. MetaDrive's steering is its action in [-1, 1]; in degrees, times the car's
    `max_steering`."""

    tolerance: float
    records: list = field(default_factory=list)
    _oob_counter: int = 0
    _was_oob: bool = False
    _max_oob: float = 0.0

    def sample(self, t: float, position: np.ndarray, heading: float, car: Any,
               monitor: LaneMonitor) -> None:
        bolp = monitor.last_bolp
        is_oob = bolp > self.tolerance
        if is_oob and not self._was_oob:  # a new out-of-bound episode starts its maximum afresh
            self._oob_counter += 1
            self._max_oob = bolp
        elif is_oob:
            self._max_oob = max(self._max_oob, bolp)
        self._was_oob = is_oob
        speed_mps = float(car.speed)
        c, s = math.cos(heading), math.sin(heading)
        steering_input = min(1.0, max(-1.0, float(car.steering)))
        throttle_brake = min(1.0, max(-1.0, float(car.throttle_brake)))
        throttle, brake = max(throttle_brake, 0.0), max(-throttle_brake, 0.0)
        oob_distance = lanes.lane_width_m / 2.0 - abs(monitor.last_lateral_m + lanes.lane_width_m / 2.0)
        self.records.append([
            round(t, 4), [float(position[0]), float(position[1]), ROAD_HEIGHT_M], [c, s, 0.0],
            [speed_mps * c, speed_mps * s, 0.0], steering_input * float(car.max_steering),
            steering_input, brake, brake, throttle, throttle, speed_mps, round(speed_mps * 3.6),
            is_oob, self._oob_counter, self._max_oob, oob_distance, bolp])
