"""The lane monitor: BOLP and the ends of a drive, measured as wogan's simulator measures them
(crates/road-sim/src/sim/lane_monitor.rs and episode.rs), on the car's samples.

BOLP is the share of the car's box outside the right lane's polygon, a window of the lane around the
car's projection on the centre line (extended straight back behind the first point), intersected
with the box by shapely. A drive ends FAIL out of lane past the tolerance, PASS near the road's
end, FAIL when the car stops moving or at the time limit, as wogan's does.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from .constants import (END_DISTANCE_M, END_SEGMENTS, LANE_WINDOW_POINTS, LEAD_IN_M, MAX_SIM_TIME_S, NOT_MOVING_DISTANCE_M,
                        NOT_MOVING_WINDOW_S, PROJECTION_WINDOW)
from .road import Road, lanes, timeout_s

# The centre-line points of the lane window behind and ahead of the car's segment
# (sim/lane_monitor.rs WINDOW_BEHIND, WINDOW_AHEAD).
WINDOW_BEHIND, WINDOW_AHEAD = LANE_WINDOW_POINTS


def footprint(center: np.ndarray, heading: float, length: float, width: float) -> np.ndarray:
    """The four corners of the car's box (wogan's sim/vehicle.rs `footprint`)."""
    s, c = math.sin(heading), math.cos(heading)
    hl, hw = length / 2.0, width / 2.0
    return np.array([[center[0] + f * c - l * s, center[1] + f * s + l * c]
                     for f, l in ((hl, hw), (hl, -hw), (-hl, -hw), (-hl, hw))])


def lane_window(road: Road, right_edge: np.ndarray, lead_in: np.ndarray, segment: int) -> np.ndarray:
    """The right lane's polygon around centre-line segment `segment` (wogan's sim/lane_monitor.rs):
    points WINDOW_BEHIND before to WINDOW_AHEAD after it, the centre line forward and the right edge
    back; near the start, extended LEAD_IN_M straight back behind the first point."""
    n = len(road.centre)
    first = max(segment - WINDOW_BEHIND, 0)
    last = min(segment + 1 + WINDOW_AHEAD, n - 1)
    parts = [road.centre[first:last + 1], right_edge[first:last + 1][::-1]]
    if first == 0:
        parts = [lead_in[:1], *parts, lead_in[1:]]
    return np.vstack(parts)


def lead_in_points(road: Road, right_edge: np.ndarray) -> np.ndarray:
    """The centre line's and the right edge's points LEAD_IN_M straight back behind the start."""
    back = road.centre[0] - road.centre[1]
    back = back / math.hypot(back[0], back[1]) * LEAD_IN_M
    return np.array([road.centre[0] + back, right_edge[0] + back])


@dataclass
class Verdict:
    """How and when a drive ended."""

    outcome: str  # PASS, FAIL or ERROR
    reason: Optional[str]  # None for PASS; out_of_lane, not_moving, timeout, sim_time_limit
    t_s: float
    side: Optional[str] = None  # "left" or "right" for out_of_lane
    point: Optional[tuple] = None  # the car centre (wogan's frame) at the exit, for out_of_lane


@dataclass
class LaneMonitor:
    """Measures the car against the right lane at each sample and says when the drive ends."""

    road: Road
    car_length_m: float
    car_width_m: float
    tolerance: float
    max_bolp: float = 0.0
    # The smallest signed distance of the car centre to the right lane's edges, metres (wogan's
    # `min_lane_distance_m`: 2 when centred, negative outside); half the lane's width when unsampled.
    min_lane_distance_m: float = field(init=False)
    last_bolp: float = 0.0
    last_lateral_m: float = 0.0  # of the car centre from the centre line, positive left
    verdict: Optional[Verdict] = None
    samples: int = 0
    _segment: int = 0
    _anchor: Optional[np.ndarray] = None
    _anchor_t: float = 0.0
    _right_edge: np.ndarray = field(default=None, repr=False)
    _lead_in: np.ndarray = field(default=None, repr=False)
    _timeout_s: float = 0.0

    def __post_init__(self) -> None:
        self.min_lane_distance_m = lanes.lane_width_m / 2.0  # read here: `--lane-width` sets it
        self._right_edge = self.road.offset_line(-lanes.road_width_m / 2.0)
        self._lead_in = lead_in_points(self.road, self._right_edge)
        self._timeout_s = timeout_s(self.road)

    def bolp(self, center: np.ndarray, heading: float, segment: int) -> float:
        """Share of the car's box outside the lane's window around `segment`, in [0, 1]."""
        import shapely

        box = shapely.Polygon(footprint(center, heading, self.car_length_m, self.car_width_m))
        lane = shapely.Polygon(lane_window(self.road, self._right_edge, self._lead_in, segment))
        if not lane.is_valid:
            lane = shapely.make_valid(lane)
        inside = lane.intersection(box).area
        return min(1.0, max(0.0, 1.0 - inside / box.area))

    def project(self, p: np.ndarray) -> tuple[int, float]:
        """The centre-line segment nearest `p` near the last one, and the signed offset of `p` from
        the centre line, positive left (wogan's road/polyline.rs `project`, window of
        sim/lane_monitor.rs)."""
        c = self.road.centre
        segments = len(c) - 1
        first = min(max(self._segment - PROJECTION_WINDOW[0], 0), segments)
        last = min(self._segment + PROJECTION_WINDOW[1], segments)
        if last <= first:
            return self._segment, 0.0
        a, b = c[first:last], c[first + 1:last + 1]
        d = b - a
        length_sq = np.einsum("ij,ij->i", d, d)
        along = np.clip(np.einsum("ij,ij->i", p - a, d) / length_sq, 0.0, 1.0)
        distance = np.hypot(a[:, 0] + along * d[:, 0] - p[0], a[:, 1] + along * d[:, 1] - p[1])
        k = int(np.argmin(distance))  # the first of equals, as wogan's strict `<`
        lateral = float((d[k, 0] * (p[1] - a[k, 1]) - d[k, 1] * (p[0] - a[k, 0])) / math.sqrt(length_sq[k]))
        self._segment = first + k
        return self._segment, lateral

    def sample(self, t: float, center: np.ndarray, heading: float) -> Optional[Verdict]:
        """Measures one sample at simulated time `t`; the verdict when the drive ends here."""
        if self.verdict is not None:
            return self.verdict
        self.samples += 1
        segment, lateral = self.project(center)
        bolp = self.bolp(center, heading, segment)
        self.max_bolp = max(self.max_bolp, bolp)
        # The right lane's centre is half a lane right of the centre line (sim/lane_monitor.rs).
        lane_distance = lanes.lane_width_m / 2.0 - abs(lateral + lanes.lane_width_m / 2.0)
        self.min_lane_distance_m = min(self.min_lane_distance_m, lane_distance)
        self.last_bolp, self.last_lateral_m = bolp, lateral
        if bolp > self.tolerance:
            # wogan's side: left when nearer the lane's left edge (the centre line) than its right.
            dist_left, dist_right = -lateral, lateral + lanes.road_width_m / 2.0
            side = "left" if dist_left < dist_right else "right"
            point = (round(float(center[0]), 3), round(float(center[1]), 3))
            self.verdict = Verdict("FAIL", "out_of_lane", t, side, point)
            return self.verdict
        end = self.road.centre[-1]
        near_end_along = segment + END_SEGMENTS >= len(self.road.centre)
        if near_end_along and math.hypot(center[0] - end[0], center[1] - end[1]) <= END_DISTANCE_M:
            self.verdict = Verdict("PASS", None, t)
            return self.verdict
        if self._anchor is None:
            self._anchor = np.array(center, dtype=float)
        moved = math.hypot(center[0] - self._anchor[0], center[1] - self._anchor[1])
        if moved >= NOT_MOVING_DISTANCE_M:
            self._anchor, self._anchor_t = np.array(center, dtype=float), t
        elif t - self._anchor_t >= NOT_MOVING_WINDOW_S:
            self.verdict = Verdict("FAIL", "not_moving", t)
            return self.verdict
        if t >= self._timeout_s:
            self.verdict = Verdict("FAIL", "timeout", t)
        elif t >= MAX_SIM_TIME_S:
            self.verdict = Verdict("ERROR", "sim_time_limit", t)
        return self.verdict
