"""wogan's road geometry and drive rules, read from the file wogan writes them to.

wogan's simulator (crates/road-sim/src) defines the road this executor drives and the rules that
end a drive. A test of wogan's (crates/cli/src/sut/protocol_schema.rs) writes those numbers to
docs/protocols/wogan-simulator-constants.json, so this executor reads them there rather than
keeping copies that could drift. WOGAN_SIMULATOR_CONSTANTS names another file (a copy beside an
installed executor, say).

The file is read once, when this module is imported. A missing, unreadable or incomplete file
stops the executor at its start with a message naming the file and the key, not at its first road.
"""
from __future__ import annotations

import json
import math
import os
from typing import Any

ENVIRONMENT_VARIABLE = "WOGAN_SIMULATOR_CONSTANTS"
# From examples/metadrive/wogan_metadrive/ to the checkout's docs/protocols/.
DEFAULT_PATH = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "docs",
                            "protocols", "wogan-simulator-constants.json")


class ConstantsError(SystemExit):
    """The constants file is missing or wrong. A SystemExit, because nothing can run without it:
    the script stops with this message alone (no traceback), and `wogan.ray`'s loader, which
    catches it too, reports it as the executor file failing to load."""


def constants_path() -> str:
    """The file to read: WOGAN_SIMULATOR_CONSTANTS when set, else the checkout's."""
    return os.path.normpath(os.environ.get(ENVIRONMENT_VARIABLE) or DEFAULT_PATH)


class ConstantsFile:
    """The file's values, each read by its key and checked to be of the kind the executor uses."""

    def __init__(self, path: str) -> None:
        self.path = path
        try:
            with open(path, encoding="utf-8") as f:
                values = json.load(f)
        except OSError as error:
            raise self.error(f"cannot be read ({error.strerror or error}); the checkout's is "
                             f"docs/protocols/wogan-simulator-constants.json, {ENVIRONMENT_VARIABLE} "
                             "names another") from None
        except ValueError as error:  # not JSON, or not UTF-8
            raise self.error(f"is not JSON ({error})") from None
        if not isinstance(values, dict):
            raise self.error("is not a JSON object")
        self.values: dict = values

    def error(self, what: str) -> ConstantsError:
        return ConstantsError(f"wogan's simulator constants: {self.path} {what}")

    def _get(self, key: str) -> Any:
        if key not in self.values:
            raise self.error(f"has no key {key!r}")
        return self.values[key]

    def number(self, key: str) -> float:
        """A finite number, as a float."""
        value = self._get(key)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise self.error(f"key {key!r}: {json.dumps(value)} is not a finite number")
        return float(value)

    def integer(self, key: str) -> int:
        """A whole number written as one (20, not 20.0), as wogan writes its counts."""
        value = self._get(key)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(f"key {key!r}: {json.dumps(value)} is not an integer")
        return value

    def integers(self, key: str, count: int) -> tuple[int, ...]:
        """A list of `count` whole numbers, as a tuple."""
        value = self._get(key)
        if (not isinstance(value, list) or len(value) != count
                or any(isinstance(v, bool) or not isinstance(v, int) for v in value)):
            raise self.error(f"key {key!r}: {json.dumps(value)} is not a list of {count} integers")
        return tuple(value)


_file = ConstantsFile(constants_path())

# Each named as in wogan's source (crates/road-sim/src unless said), where the comment points.
# The lane widths here are wogan's; `--lane-width` changes the executor's (road.py `lanes`).
ROAD_WIDTH_M = _file.number("road_width_m")  # road/geometry.rs ROAD_WIDTH_M
LANE_WIDTH_M = _file.number("lane_width_m")  # road/geometry.rs LANE_WIDTH_M
INTERPOLATION_DISTANCE_M = _file.number("interpolation_distance_m")  # road/spline.rs
MIN_SAMPLES = _file.integer("min_samples")  # road/spline.rs MIN_SAMPLES
ROUNDING_DECIMALS = _file.integer("rounding_decimals")  # road/spline.rs ROUNDING_DECIMALS
MAX_ROAD_LENGTH_M = _file.number("max_road_length_m")  # road/spline.rs MAX_LENGTH_M
START_OFFSET_M = _file.number("start_offset_m")  # sim/config.rs start_offset_m
END_DISTANCE_M = _file.number("end_distance_m")  # sim/config.rs end_distance_m
END_SEGMENTS = _file.integer("end_segments")  # sim/episode.rs END_SEGMENTS
TIMEOUT_BASE_S = _file.number("timeout_base_s")  # sim/config.rs timeout_base_s
TIMEOUT_SPEED_MPS = _file.number("timeout_speed_mps")  # sim/config.rs timeout_speed_mps
NOT_MOVING_DISTANCE_M = _file.number("not_moving_distance_m")  # sim/config.rs
NOT_MOVING_WINDOW_S = _file.number("not_moving_window_s")  # sim/config.rs
MAX_SIM_TIME_S = _file.number("max_sim_time_s")  # sim/config.rs MAX_SIM_TIME_S
LEAD_IN_M = _file.number("lead_in_m")  # sim/lane_monitor.rs LEAD_IN_M
# sim/lane_monitor.rs PROJECTION_WINDOW: the centre-line segments `project` searches behind and
# ahead of the last one.
PROJECTION_WINDOW = _file.integers("projection_window_segments", 2)
# sim/lane_monitor.rs WINDOW_BEHIND, WINDOW_AHEAD: the centre-line points of the lane window
# behind and ahead of the car's segment.
LANE_WINDOW_POINTS = _file.integers("lane_window_points", 2)
# sim/config.rs speed_limit_kmh and oob_tolerance: what the executor uses until `hello` says.
DEFAULT_SPEED_LIMIT_KMH = _file.number("default_speed_limit_kmh")
DEFAULT_OOB_TOLERANCE = _file.number("default_oob_tolerance")
# The competition level's road surface (crates/cli/src/files/sbst_format.rs ROAD_HEIGHT_M), the
# height of the positions in `--execution-data`.
ROAD_HEIGHT_M = _file.number("road_height_m")
