"""The road as wogan builds it from `road_points` (crates/road-sim/src/road): the competition's
spline through the points, the lanes either side of it, the car's start and the time limit.

The lane width is the one setting here that can differ from wogan's (`--lane-width`): it is kept
in `lanes`, which every user reads when it needs the width, so that a change reaches them all.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .constants import (INTERPOLATION_DISTANCE_M, LANE_WIDTH_M, MAX_ROAD_LENGTH_M, MIN_SAMPLES, ROAD_WIDTH_M,
                        ROUNDING_DECIMALS, START_OFFSET_M, TIMEOUT_BASE_S, TIMEOUT_SPEED_MPS)


@dataclass
class LaneWidths:
    """The width of each of the road's two lanes and of the road, metres."""

    lane_width_m: float
    road_width_m: float


# The executor's lanes: wogan's until `--lane-width` (set_lane_width) says otherwise. The road,
# the start, the scenario, the lane monitor, the execution records and the expert's navigation all
# read them here.
lanes = LaneWidths(lane_width_m=LANE_WIDTH_M, road_width_m=ROAD_WIDTH_M)


def set_lane_width(metres: float) -> None:
    """Each lane `metres` wide, the road twice that (`--lane-width`)."""
    lanes.lane_width_m, lanes.road_width_m = float(metres), 2.0 * float(metres)


class RoadError(ValueError):
    """The road points do not make a road (the message says why)."""


@dataclass
class Road:
    """A road: its points, the interpolated centre line and the left normal at each of its points."""

    points: np.ndarray
    centre: np.ndarray
    left_normals: np.ndarray

    @property
    def length_m(self) -> float:
        return float(np.sum(np.hypot(*np.diff(self.centre, axis=0).T)))

    def offset_line(self, offset_m: float) -> np.ndarray:
        """The line `offset_m` to the left of the centre line (negative: right)."""
        return self.centre + offset_m * self.left_normals


def parse_points(raw: Any) -> np.ndarray:
    """`[[x, y], ...]` as an array, refusing anything else."""
    try:
        points = np.asarray(raw, dtype=float)
    except (TypeError, ValueError) as error:
        raise RoadError(f"road_points is not a list of [x, y] pairs: {error}") from None
    if points.ndim != 2 or points.shape[1] != 2:
        raise RoadError(f"road_points is not a list of [x, y] pairs (shape {points.shape})")
    if len(points) < 2:
        raise RoadError(f"at least 2 points are needed to interpolate, got {len(points)}")
    if not np.all(np.isfinite(points)):
        raise RoadError("a road point has a non-finite coordinate")
    return points


def interpolate(points: np.ndarray) -> np.ndarray:
    """The competition's interpolation (wogan's road/spline.rs): a chord-length spline through the
    points sampled at numpy's `arange(0, 1 + 1/n, 1/n)`, n = max(int(length), 20), rounded."""
    from scipy.interpolate import splev, splprep

    chords = np.hypot(*np.diff(points, axis=0).T)
    if np.any(chords == 0.0):
        i = int(np.argmax(chords == 0.0))
        raise RoadError(f"points {i} and {i + 1} coincide")
    length = float(np.sum(chords))
    if length > MAX_ROAD_LENGTH_M:
        raise RoadError(f"the points span {length} m, more than the {MAX_ROAD_LENGTH_M} m a road may")
    degree = min(3, len(points) - 1)
    tck, _ = splprep([points[:, 0], points[:, 1]], s=0, k=degree)
    step = 1.0 / max(int(length / INTERPOLATION_DISTANCE_M), MIN_SAMPLES)
    x, y = splev(np.arange(0.0, 1.0 + step, step), tck)
    return np.round(np.column_stack([x, y]), ROUNDING_DECIMALS)


def build_road(raw_points: Any) -> Road:
    """The road of `road_points`, or RoadError saying why there is none."""
    points = parse_points(raw_points)
    centre = interpolate(points)
    deltas = np.diff(centre, axis=0)
    lengths = np.hypot(deltas[:, 0], deltas[:, 1])
    if np.any(lengths == 0.0) or not np.all(np.isfinite(lengths)):
        i = int(np.argmax((lengths == 0.0) | ~np.isfinite(lengths)))
        raise RoadError(f"interpolated points {i} and {i + 1} coincide")
    normals = np.column_stack([-deltas[:, 1] / lengths, deltas[:, 0] / lengths])
    normals = np.vstack([normals, normals[-1:]])  # the last point uses the last segment's
    return Road(points=points, centre=centre, left_normals=normals)


def start_pose(road: Road, offset_m: float = START_OFFSET_M) -> tuple[np.ndarray, float, int]:
    """wogan's start (sim/episode.rs `start_pose`): on the right lane's centre `offset_m` along the
    centre line, heading along it. Returns the position, the heading and the segment it lies on."""
    remaining = max(offset_m, 0.0)
    c = road.centre
    for i in range(len(c) - 1):
        a, b = c[i], c[i + 1]
        d = b - a
        length = float(math.hypot(d[0], d[1]))
        if remaining <= length or i + 2 == len(c):
            t = remaining / length
            position = a + t * d - (lanes.lane_width_m / 2.0) * road.left_normals[i]
            return position, math.atan2(d[1], d[0]), i
        remaining -= length
    raise RoadError("a road has at least two interpolated points")


def timeout_s(road: Road) -> float:
    """wogan's time limit (sim/config.rs `timeout_s`)."""
    return TIMEOUT_BASE_S + road.length_m / TIMEOUT_SPEED_MPS
