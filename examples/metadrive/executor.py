#!/usr/bin/env python3
"""A wogan executor that drives each road in MetaDrive (metadrive-simulator 0.4.3, Bullet physics,
headless, no GPU, no assets): `wogan run --executor cmd:"PYTHON executor.py --policy idm"`.

It is a `wogan.Executor` (the `wogan` Python package, python/README.md), which speaks the executor
protocol, version 3 (wogan's docs/reference.md, "Plug points: your own simulator"): JSON lines on
standard input (`hello`, one `road` per test, `bye`), on standard output one reply to `hello` (the
executor's name and its settings: policy, speed limit, tolerance, MetaDrive's version...) and one
answer line per road, nothing else there (MetaDrive's own output goes to standard error with the
logs). Set up by `examples/metadrive/setup.sh`, which makes `target/metadrive-venv`.

The road, as wogan's simulator has it (crates/road-sim/src):
- The centre line is the competition's spline through `road_points` (FITPACK's `splprep(s=0)`, a
  line through 2 points, a parabola through 3, the not-a-knot cubic through more), sampled about
  every metre and rounded to 3 decimals (road/spline.rs). The road is two 4 m lanes either side of
  it (road/geometry.rs; `--lane-width` makes them narrower or wider); the car drives in the right
  one.
- The car starts at rest on the right lane's centre 2.5 m along the centre line from the first
  point, heading along the road (sim/config.rs `start_offset_m`, sim/episode.rs `start_pose`).

In MetaDrive that road is a scenario description given to `ScenarioOnlineEnv.set_scenario`: two
lanes (the right lane's centre line forward, the left lane's backward, each with its 4 m polygon), a
solid yellow centre line, the two road edges, and the ego track (the car's route, which MetaDrive's
policies follow): the start pose, then the right lane's centre to the road's end. The scenario is
laid in a frame whose origin is the start (MetaDrive moves its origin there anyway), so a MetaDrive
position plus the start is a point of wogan's map. No traffic, no lights, a new map per road.

The driver (`--policy`):
- `idm`: MetaDrive's `IDMPolicy` (a PID steering onto the route, IDM throttle) with its target speed
  set to the speed limit of `hello` and lane changes off. Control at 10 Hz (MetaDrive's
  `decision_repeat` 5 of 0.02 s physics steps).
- `expert`: MetaDrive's PPO expert (`metadrive.examples.ppo_expert`, weights shipped in the
  package, numpy inference), its mean action (deterministic), the throttle cut above the speed
  limit. The expert wants the 275-value LiDAR-state observation of MetaDrive's procedural (PG)
  maps: 9 ego values, 10 navigation values (two checkpoints of 5), 240 LiDAR rays and 16 values of
  the 4 nearest cars. `ScenarioOnlineEnv`'s navigation (`TrajectoryNavigation`) gives 22
  navigation values, so this executor gives the car `ExpertNavigation`: the route cut into pieces
  that turn one way (as a PG map's blocks are straights and arcs), each described as a PG block
  (checkpoint at its end, bend radius, direction, angle), the road one 4 m lane wide.

The measures, sampled at every physics step (50 Hz):
- BOLP: the share of the car's footprint (MetaDrive's car: its box, `LENGTH` x `WIDTH`, at its
  position and heading) outside the right lane's polygon, as wogan's lane monitor measures it
  (sim/lane_monitor.rs): the lane's window from 6 centre-line points behind the car's projection to
  7 ahead (centre line forward, right edge back), extended 10 m straight back behind the first
  point, intersected with the box by shapely. `max_bolp` is its largest value.
- The drive ends as wogan's (sim/episode.rs): FAIL `out_of_lane` when BOLP exceeds the tolerance of
  `hello` (`oob_side` "left" when the car's centre is nearer the centre line than the road's
  outer edge, i.e. left of the right lane's centre, else "right"); PASS when the car centre is
  within 8 m of the road's last point having got within 25 centre-line points of it along the road;
  FAIL `not_moving` when the car has moved less than 1 m in 10 s; FAIL `timeout` after
  20 s + length / (2 m/s). MetaDrive's own ends (arrival, out of road) are ignored.
- `sim_time_s`: simulated seconds until the end.

Answers carry `id`, `max_bolp`, `outcome`, `sim_time_s`, `min_lane_distance_m` (the smallest
signed distance of the car centre to the right lane's edges over the samples, as wogan's lane
monitor measures it, so that `--fitness distance` searches MetaDrive), `oob_side` and `oob_point`
(FAIL out of lane only: the side, and the car centre in wogan's frame at the first sample past the tolerance),
`error` (ERROR only: kept in the test record) and, for people reading them (wogan ignores them),
`reason`, `policy` and `wall_s`. With `--execution-data` (for the SBST pipeline's generators in
scripts/peers, which read the drive) an answer also carries `execution_data`: one array per sample
of the pipeline's 17 `SimulationDataRecord` fields, as `wogan simulate --execution-data` gives.

Faults: a road whose geometry cannot be built, or a MetaDrive exception while building or driving
it, answers that road `ERROR` with the message in `error`; MetaDrive is then closed, and started
again for the next road. A road taking longer than `--road-wall-timeout` seconds of wall time (a
hang in Python code) is answered the same way. A crash of the process, or a hang inside native
code, is left to wogan: `--executor-timeout`, then a new executor. `bye`, end of input, SIGTERM and
SIGINT close MetaDrive and exit; MetaDrive starts no other process.
"""
from __future__ import annotations

import argparse
import logging
import math
import os
import pickle
import shutil
import signal
import sys
import tempfile
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Optional

import numpy as np

# Without `pip install .` (wogan's wheel), the package is found in this checkout's python/ folder.
sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import wogan  # noqa: E402

# wogan's road and episode (crates/road-sim/src); the competition's numbers where wogan took them.
ROAD_WIDTH_M = 8.0  # road/geometry.rs ROAD_WIDTH_M (`--lane-width` sets both)
LANE_WIDTH_M = ROAD_WIDTH_M / 2.0  # road/geometry.rs LANE_WIDTH_M
INTERPOLATION_DISTANCE_M = 1.0  # road/spline.rs INTERPOLATION_DISTANCE_M
MIN_SAMPLES = 20  # road/spline.rs MIN_SAMPLES
ROUNDING_DECIMALS = 3  # road/spline.rs ROUNDING_DECIMALS
MAX_ROAD_LENGTH_M = 20_000.0  # road/spline.rs MAX_LENGTH_M
START_OFFSET_M = 2.5  # sim/config.rs start_offset_m
END_DISTANCE_M = 8.0  # sim/config.rs end_distance_m
END_SEGMENTS = 25  # sim/episode.rs END_SEGMENTS
TIMEOUT_BASE_S = 20.0  # sim/config.rs timeout_base_s
TIMEOUT_SPEED_MPS = 2.0  # sim/config.rs timeout_speed_mps
NOT_MOVING_DISTANCE_M = 1.0  # sim/config.rs not_moving_distance_m
NOT_MOVING_WINDOW_S = 10.0  # sim/config.rs not_moving_window_s
MAX_SIM_TIME_S = 3600.0  # sim/config.rs MAX_SIM_TIME_S
LEAD_IN_M = 10.0  # sim/lane_monitor.rs LEAD_IN_M
PROJECTION_WINDOW = (4, 30)  # sim/lane_monitor.rs `project`: segments searched behind/ahead
WINDOW_BEHIND, WINDOW_AHEAD = 6, 7  # sim/lane_monitor.rs: centre-line points of the lane window

DEFAULT_SPEED_LIMIT_KMH = 70.0  # wogan's default for beamng-ai-proxy and executors
DEFAULT_OOB_TOLERANCE = 0.85

log = logging.getLogger("metadrive-executor")


class RoadError(ValueError):
    """The road points do not make a road (the message says why)."""


class WallTimeout(Exception):
    """A road took more wall time than --road-wall-timeout."""


# ----------------------------------------------------------------------------------------------
# The road, as wogan builds it
# ----------------------------------------------------------------------------------------------

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
            position = a + t * d - (LANE_WIDTH_M / 2.0) * road.left_normals[i]
            return position, math.atan2(d[1], d[0]), i
        remaining -= length
    raise RoadError("a road has at least two interpolated points")


def timeout_s(road: Road) -> float:
    """wogan's time limit (sim/config.rs `timeout_s`)."""
    return TIMEOUT_BASE_S + road.length_m / TIMEOUT_SPEED_MPS


# ----------------------------------------------------------------------------------------------
# The road as a MetaDrive scenario
# ----------------------------------------------------------------------------------------------

# MetaDrive's default car (metadrive/component/vehicle/vehicle_type.py DefaultVehicle). The scenario
# must give a size; the default car keeps its own whatever is given.
CAR_LENGTH_M, CAR_WIDTH_M, CAR_HEIGHT_M = 4.515, 1.852, 1.19


def headings_of(line: np.ndarray) -> np.ndarray:
    """The heading of each point of a polyline: of the segment that starts there (the last point:
    of the segment that ends there)."""
    d = np.diff(line, axis=0)
    h = np.arctan2(d[:, 1], d[:, 0])
    return np.append(h, h[-1])


def scenario_of(road: Road, scenario_id: str) -> tuple[dict, np.ndarray]:
    """The MetaDrive scenario description of `road`, laid with the car's start at the origin, and
    that start (in wogan's frame)."""
    from metadrive.type import MetaDriveType

    start, heading, segment = start_pose(road)
    centre = road.centre - start
    shifted = Road(points=road.points - start, centre=centre, left_normals=road.left_normals)
    right_centre = shifted.offset_line(-LANE_WIDTH_M / 2.0)
    left_centre = shifted.offset_line(LANE_WIDTH_M / 2.0)
    right_edge = shifted.offset_line(-ROAD_WIDTH_M / 2.0)
    left_edge = shifted.offset_line(ROAD_WIDTH_M / 2.0)

    # The car's route: the start, then the right lane's centre from the next centre-line point on.
    track = np.vstack([np.zeros((1, 2)), right_centre[segment + 1:]])
    if len(track) < 2:  # a start on the last segment: reach the end of the lane
        track = np.vstack([track, right_centre[-1:]])
    steps = len(track)
    track_headings = headings_of(track)
    track_headings[0] = heading
    position = np.zeros((steps, 3))
    position[:, :2] = track

    def polygon(forward: np.ndarray, back: np.ndarray) -> np.ndarray:
        return np.vstack([forward, back[::-1]])

    scenario = {
        "id": scenario_id,
        "version": "wogan-metadrive-executor",
        "length": steps,
        "metadata": {
            "ts": np.arange(steps, dtype=float) * 0.1,
            "metadrive_processed": False,
            "coordinate": "metadrive",
            "sdc_id": "ego",
            "dataset": "wogan",
            "scenario_id": scenario_id,
        },
        "tracks": {
            "ego": {
                "type": MetaDriveType.VEHICLE,
                "state": {
                    "position": position,
                    "heading": track_headings,
                    "velocity": np.zeros((steps, 2)),
                    "valid": np.ones(steps, dtype=bool),
                    "length": np.full(steps, CAR_LENGTH_M),
                    "width": np.full(steps, CAR_WIDTH_M),
                    "height": np.full(steps, CAR_HEIGHT_M),
                },
                "metadata": {"type": MetaDriveType.VEHICLE, "track_length": steps, "object_id": "ego"},
            }
        },
        "dynamic_map_states": {},
        "map_features": {
            "right_lane": {
                "type": MetaDriveType.LANE_SURFACE_STREET,
                "polyline": right_centre,
                "polygon": polygon(centre, right_edge),
            },
            "left_lane": {
                "type": MetaDriveType.LANE_SURFACE_STREET,
                "polyline": left_centre[::-1].copy(),
                "polygon": polygon(left_edge, centre),
            },
            "centre_line": {"type": MetaDriveType.LINE_SOLID_SINGLE_YELLOW, "polyline": centre},
            "right_edge": {"type": MetaDriveType.BOUNDARY_LINE, "polyline": right_edge},
            "left_edge": {"type": MetaDriveType.BOUNDARY_LINE, "polyline": left_edge},
        },
    }
    return scenario, start


# ----------------------------------------------------------------------------------------------
# The lane monitor: BOLP and the episode's ends, as wogan's
# ----------------------------------------------------------------------------------------------

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
    # `min_lane_distance_m`: 2 when centred, negative outside); a lane-width half when unsampled.
    min_lane_distance_m: float = LANE_WIDTH_M / 2.0
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
        self.min_lane_distance_m = LANE_WIDTH_M / 2.0  # the lane of `--lane-width`
        self._right_edge = self.road.offset_line(-ROAD_WIDTH_M / 2.0)
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
        lane_distance = LANE_WIDTH_M / 2.0 - abs(lateral + LANE_WIDTH_M / 2.0)
        self.min_lane_distance_m = min(self.min_lane_distance_m, lane_distance)
        self.last_bolp, self.last_lateral_m = bolp, lateral
        if bolp > self.tolerance:
            # wogan's side: left when nearer the lane's left edge (the centre line) than its right.
            dist_left, dist_right = -lateral, lateral + ROAD_WIDTH_M / 2.0
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


# ----------------------------------------------------------------------------------------------
# MetaDrive: the policies, the expert's navigation, the sampler, the environment
# ----------------------------------------------------------------------------------------------

def make_idm_policy(speed_limit_kmh: float) -> type:
    """MetaDrive's IDMPolicy holding the speed limit, lane changes off."""
    from metadrive.policy.idm_policy import IDMPolicy

    class WoganIDMPolicy(IDMPolicy):
        NORMAL_SPEED = speed_limit_kmh  # IDM's target speed, km/h (MetaDrive's default: 30)

        def __init__(self, *args: Any, **kwargs: Any) -> None:
            super().__init__(*args, **kwargs)
            self.enable_lane_change = False

    return WoganIDMPolicy


# The expert's sensors (metadrive/examples/ppo_expert/numpy_expert.py `expert`).
EXPERT_SENSORS = dict(
    lidar=dict(num_lasers=240, distance=50, num_others=4, gaussian_noise=0.0, dropout_prob=0.0),
    side_detector=dict(num_lasers=0, distance=50, gaussian_noise=0.0, dropout_prob=0.0),
    lane_line_detector=dict(num_lasers=0, distance=20, gaussian_noise=0.0, dropout_prob=0.0),
)


def make_expert_policy(speed_limit_kmh: float) -> type:
    """MetaDrive's PPO expert, its mean action, no throttle above the speed limit.

    The forward pass and observation are `numpy_expert.expert(deterministic=True)`'s, with two
    costs of that function taken out (each about a quarter of a drive's wall time): it reads its
    weights from the compressed `.npz` at every call (a lazy `NpzFile`), and it swaps the car's
    settings to the expert's and back at every call (deep copies). Here the weights are read once,
    and the car is given the expert's observation settings once, at the start (`_config`)."""
    from metadrive.engine.engine_utils import get_global_config
    from metadrive.examples.ppo_expert import numpy_expert
    from metadrive.obs.state_obs import LidarStateObservation
    from metadrive.policy.base_policy import BasePolicy

    with np.load(numpy_expert.ckpt_path) as archive:
        weights = {name: archive[name] for name in archive.files}
    layers = [(weights[f"default_policy/{name}/kernel"], weights[f"default_policy/{name}/bias"])
              for name in ("fc_1", "fc_2", "fc_out")]
    observation: list = []  # built at the first step, when MetaDrive's engine exists

    class WoganExpertPolicy(BasePolicy):
        def act(self, agent_id: Any = None) -> list:
            vehicle = self.control_object
            if not observation:
                config = get_global_config().copy()
                config["vehicle_config"].update(dict(EXPERT_SENSORS, random_agent_model=False))
                observation.append(LidarStateObservation(config))
                assert observation[0].observation_space.shape[0] == 275, "not the expert's observation"
            x = numpy_expert.obs_correction(observation[0].observe(vehicle)).reshape(1, -1)
            for i, (kernel, bias) in enumerate(layers):
                x = np.matmul(x, kernel) + bias
                if i < len(layers) - 1:
                    x = np.tanh(x)
            mean = np.split(x.reshape(-1), 2)[0]
            steering, throttle = (float(v) for v in mean)
            if vehicle.speed_km_h > speed_limit_kmh:
                throttle = min(throttle, 0.0)
            action = [steering, throttle]
            self.action_info["action"] = action
            return action

    return WoganExpertPolicy


def make_expert_navigation() -> type:
    """A TrajectoryNavigation that gives the 10 navigation values of MetaDrive's PG maps, on which
    the PPO expert was trained (NodeNetworkNavigation `_get_info_for_checkpoint`), for the route
    cut into pieces that each turn one way, as a PG map's blocks (straights and arcs)."""
    from metadrive.component.navigation_module.trajectory_navigation import TrajectoryNavigation
    from metadrive.component.pg_space import BlockParameterSpace, Parameter
    from metadrive.utils.math import clip, norm

    radius_scale = BlockParameterSpace.CURVE[Parameter.radius].max + LANE_WIDTH_M  # one lane
    angle_scale = BlockParameterSpace.CURVE[Parameter.angle].max  # degrees

    class ExpertNavigation(TrajectoryNavigation):
        CHECK_POINT_INFO_DIM = 5
        NUM_WAY_POINT = 2
        NAVI_POINT_DIST = 50  # BaseNavigation's, the expert's
        STRAIGHT_CURVATURE = 1.0 / 500.0  # 1/m: flatter than this counts as straight
        MAX_PIECE_M = 80.0  # PG blocks are at most about this long

        @classmethod
        def get_navigation_info_dim(cls) -> int:
            return cls.NUM_WAY_POINT * cls.CHECK_POINT_INFO_DIM

        def set_route(self) -> None:
            super().set_route()
            self._pieces = self._cut_route()

        def _cut_route(self) -> list[tuple[float, float, float, float]]:
            """Pieces of the route: (start, end) in metres along it, signed turn (rad, left
            positive) and radius (m)."""
            lane = self.reference_trajectory
            total = lane.length
            step = 1.0
            marks = np.arange(0.0, total, step)
            if len(marks) < 2:
                return [(0.0, total, 0.0, 0.0)]
            headings = np.unwrap([lane.heading_theta_at(s) for s in marks])
            curvature = np.diff(headings) / step
            kind = np.where(np.abs(curvature) < self.STRAIGHT_CURVATURE, 0, np.sign(curvature))
            pieces, begin = [], 0
            for i in range(1, len(kind) + 1):
                if (i == len(kind) or kind[i] != kind[begin]
                        or (i - begin) * step >= self.MAX_PIECE_M):
                    s0, s1 = marks[begin], (marks[i] if i < len(marks) else total)
                    turn = float(headings[min(i, len(headings) - 1)] - headings[begin])
                    radius = (s1 - s0) / abs(turn) if kind[begin] != 0 and turn != 0 else 0.0
                    pieces.append((float(s0), float(s1), turn if kind[begin] != 0 else 0.0, radius))
                    begin = i
            pieces[-1] = (pieces[-1][0], total, pieces[-1][2], pieces[-1][3])
            return pieces

        def update_localization(self, ego_vehicle: Any) -> None:
            lane = self.reference_trajectory
            if lane is None:
                return
            long, lat = lane.local_coordinates(ego_vehicle.position)
            self.last_current_heading_theta_at_long.append(lane.heading_theta_at(long))
            self.last_current_long.append(long)
            self.last_current_lat.append(lat)
            index = next((i for i, p in enumerate(self._pieces) if long < p[1]), len(self._pieces) - 1)
            following = min(index + 1, len(self._pieces) - 1)
            self._navi_info[:5] = self._piece_info(self._pieces[index], ego_vehicle)
            self._navi_info[5:] = self._piece_info(self._pieces[following], ego_vehicle)
            self._route_completion = long / lane.length

        def _piece_info(self, piece: tuple[float, float, float, float], ego_vehicle: Any) -> list:
            """NodeNetworkNavigation's five values for a block ending at the piece's end."""
            _, end, turn, radius = piece
            checkpoint = self.reference_trajectory.position(end, 0)
            direction = checkpoint - ego_vehicle.position
            distance = norm(direction[0], direction[1])
            if distance > self.NAVI_POINT_DIST:
                direction = direction / distance * self.NAVI_POINT_DIST
            ahead, rhs = ego_vehicle.convert_to_local_coordinates(direction, 0.0)
            # CircularLane: direction -1 clockwise (turning right), the value is -direction.
            bend = 0.0 if turn == 0 else (1.0 if turn < 0 else -1.0)
            return [
                clip((ahead / self.NAVI_POINT_DIST + 1) / 2, 0.0, 1.0),
                clip((rhs / self.NAVI_POINT_DIST + 1) / 2, 0.0, 1.0),
                clip(radius / radius_scale, 0.0, 1.0),
                clip((bend + 1) / 2, 0.0, 1.0),
                clip((np.rad2deg(abs(turn)) / angle_scale + 1) / 2, 0.0, 1.0),
            ]

        def get_current_lateral_range(self, current_position: Any, engine: Any) -> float:
            return LANE_WIDTH_M  # from the centre line to the road's outer edge

        def get_current_lane_width(self) -> float:
            return LANE_WIDTH_M

    return ExpertNavigation


@dataclass
class DriveResult:
    outcome: str
    reason: Optional[str]
    max_bolp: float
    sim_time_s: float
    side: Optional[str]
    point: Optional[tuple] = None
    min_lane_distance_m: float = LANE_WIDTH_M / 2.0
    execution_data: Optional[list] = None  # with --execution-data


# The competition pipeline's `SimulationDataRecord` fields, in its order (`--execution-data`).
RECORD_FIELDS = ("timer", "pos", "dir", "vel", "steering", "steering_input", "brake",
                 "brake_input", "throttle", "throttle_input", "wheelspeed", "vel_kmh", "is_oob",
                 "oob_counter", "max_oob_percentage", "oob_distance", "oob_percentage")
ROAD_HEIGHT_M = -28.0  # the competition level's road surface (wogan's sbst/format.rs)


@dataclass
class ExecutionData:
    """The drive as the competition pipeline records it, one 17-field array per sample, mapped as
    `wogan simulate --execution-data` maps its own samples (crates/cli/src/sbst/format.rs):
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
               monitor: "LaneMonitor") -> None:
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
        oob_distance = LANE_WIDTH_M / 2.0 - abs(monitor.last_lateral_m + LANE_WIDTH_M / 2.0)
        self.records.append([
            round(t, 4), [float(position[0]), float(position[1]), ROAD_HEIGHT_M], [c, s, 0.0],
            [speed_mps * c, speed_mps * s, 0.0], steering_input * float(car.max_steering),
            steering_input, brake, brake, throttle, throttle, speed_mps, round(speed_mps * 3.6),
            is_oob, self._oob_counter, self._max_oob, oob_distance, bolp])


class MetaDriveDriver:
    """One MetaDrive (`ScenarioOnlineEnv`) for many roads, rebuilt after a fault."""

    def __init__(self, policy: str, speed_limit_kmh: float, tolerance: float,
                 wheel_friction: Optional[float] = None) -> None:
        self.policy = policy
        self.speed_limit_kmh = speed_limit_kmh
        self.tolerance = tolerance
        self.wheel_friction = wheel_friction
        self.env: Any = None
        self._on_sample: Optional[Callable[[], None]] = None
        self._roads = 0

    def _config(self, data_directory: str) -> dict:
        vehicle_config: dict = {"show_navi_mark": False, "show_dest_mark": False,
                                "show_line_to_dest": False}
        if self.policy == "idm":
            policy = make_idm_policy(self.speed_limit_kmh)
            # IDM reads no observation; the env's own is kept small.
            vehicle_config.update(lidar=dict(num_lasers=0, distance=50, num_others=0),
                                  side_detector=dict(num_lasers=0, distance=50),
                                  lane_line_detector=dict(num_lasers=0, distance=20))
        else:
            policy = make_expert_policy(self.speed_limit_kmh)
            # The expert's observation (numpy_expert.py expert_obs_cfg) with its navigation part.
            vehicle_config.update(navigation_module=make_expert_navigation(), **EXPERT_SENSORS)
        return dict(
            data_directory=data_directory, num_scenarios=1, start_scenario_index=0,
            agent_policy=policy, use_render=False, image_observation=False,
            no_traffic=True, no_light=True, no_static_vehicles=True,
            store_map=False, horizon=None, log_level=logging.WARNING,
            vehicle_config=vehicle_config,
        )

    def _set_car(self, car: Any) -> None:
        """The car's tyres and top speed, set on the car itself: they are parameters of MetaDrive's
        vehicle (its PARAMETER_SPACE), which `vehicle_config` refuses, and the tyres' friction is
        read only when the wheels are made, so the wheels are given it here, at every road."""
        if self.wheel_friction is not None:  # MetaDrive's car: 0.9
            car.config["wheel_friction"] = self.wheel_friction
            for wheel in car.wheels:
                wheel.setFrictionSlip(self.wheel_friction)
        # MetaDrive's car stops accelerating at 80 km/h (its `max_speed_km_h`); above that the speed
        # limit is its top speed. The expert's observation gives its speed as a share of the top
        # speed, so above 80 km/h it reads a lower share than it was trained on.
        if self.speed_limit_kmh > 80.0:
            car.config["max_speed_km_h"] = self.speed_limit_kmh

    def start(self) -> None:
        """Starts MetaDrive. `ScenarioOnlineEnv` reads a data directory holding one scenario when it
        is built (roads come later through `set_scenario`): a straight road's, written and removed."""
        from metadrive.envs.scenario_env import ScenarioOnlineEnv
        from metadrive.manager.base_manager import BaseManager

        started = time.monotonic()
        directory = tempfile.mkdtemp(prefix="wogan-metadrive-")
        try:
            scenario, _ = scenario_of(build_road([[0.0, 0.0], [0.0, 50.0]]), "placeholder")
            name = "sd_wogan_placeholder.pkl"
            with open(os.path.join(directory, name), "wb") as f:
                pickle.dump(scenario, f)
            with open(os.path.join(directory, "dataset_summary.pkl"), "wb") as f:
                pickle.dump({name: {}}, f)
            with open(os.path.join(directory, "dataset_mapping.pkl"), "wb") as f:
                pickle.dump({name: ""}, f)
            self.env = ScenarioOnlineEnv(self._config(directory))
        finally:
            shutil.rmtree(directory, ignore_errors=True)

        driver = self

        class Sampler(BaseManager):
            """Called before each physics step: samples the car as the last step left it."""
            PRIORITY = 100

            def step(self, *args: Any, **kwargs: Any) -> dict:
                if driver._on_sample is not None:
                    driver._on_sample()
                return {}

        self.env.engine.register_manager("wogan_sampler", Sampler())
        log.info("MetaDrive started (%s policy) in %.2f s", self.policy, time.monotonic() - started)

    def close(self) -> None:
        if self.env is not None:
            env, self.env = self.env, None
            env.close()

    def drive(self, road: Road, broken: bool = False, record: bool = False) -> DriveResult:
        """Drives `road` (`broken`: without its lane's centre line, to test the fault path;
        `record`: with the pipeline's execution records)."""
        if self.env is None:
            self.start()
        env = self.env
        self._roads += 1
        scenario, origin = scenario_of(road, f"wogan-{self._roads}")
        if broken:
            del scenario["map_features"]["right_lane"]["polyline"]
        from metadrive.scenario.scenario_description import ScenarioDescription

        env.set_scenario(ScenarioDescription(scenario))
        env.reset()
        car = env.agent
        self._set_car(car)
        monitor = LaneMonitor(road, float(car.LENGTH), float(car.WIDTH), self.tolerance)
        dt = float(env.config["physics_world_step_size"])
        steps = [0]
        recorder = ExecutionData(self.tolerance) if record else None

        def on_sample() -> None:
            k = steps[0]
            steps[0] += 1
            if k == 0:  # the start pose, before any step: wogan samples after each step
                return
            position = np.asarray(car.position, dtype=float) + origin
            heading = float(car.heading_theta)
            monitor.sample(k * dt, position, heading)
            if recorder is not None and monitor.samples > len(recorder.records):
                recorder.sample(k * dt, position, heading, car, monitor)

        self._on_sample = on_sample
        try:
            while monitor.verdict is None:
                env.step([0.0, 0.0])  # the policy drives; the action given is not used
                if not np.all(np.isfinite(car.position)):
                    monitor.verdict = Verdict("ERROR", "non_finite_physics_state", steps[0] * dt)
        finally:
            self._on_sample = None
        v = monitor.verdict
        return DriveResult(v.outcome, v.reason, monitor.max_bolp, v.t_s, v.side, v.point,
                           monitor.min_lane_distance_m,
                           recorder.records if recorder is not None else None)


# ----------------------------------------------------------------------------------------------
# The protocol: wogan.Executor serves it, this class drives
# ----------------------------------------------------------------------------------------------

class MetaDriveExecutor(wogan.Executor):
    """Drives each road wogan sends in one MetaDrive, started again after a fault. MetaDrive starts
    at the first road (and again after a fault): that road's drive, and wogan's timeout for it,
    include the start."""

    name = "wogan-metadrive-executor"

    def __init__(self, policy: str, wall_timeout_s: float, execution_data: bool = False,
                 wheel_friction: Optional[float] = None) -> None:
        super().__init__()
        self.policy = policy
        self.wheel_friction = wheel_friction
        self.execution_data = execution_data
        self.wall_timeout_s = wall_timeout_s
        self.speed_limit_kmh = DEFAULT_SPEED_LIMIT_KMH
        self.tolerance = DEFAULT_OOB_TOLERANCE
        self.driver: Optional[MetaDriveDriver] = None
        self.broken = False  # MetaDrive failed: close it before the next road

    def hello(self, settings: dict) -> None:
        self.speed_limit_kmh = float(settings.get("speed_limit_kmh", self.speed_limit_kmh))
        self.tolerance = float(settings.get("oob_tolerance", self.tolerance))
        if self.driver is not None:  # a second hello: new settings, new MetaDrive
            self.driver.close()
            self.driver = None
        log.info("hello: speed limit %.1f km/h, tolerance %.3f, policy %s",
                 self.speed_limit_kmh, self.tolerance, self.policy)

    def reported_settings(self) -> dict:
        """What the reply to `hello` says of this executor's settings."""
        return {"simulator": f"metadrive-simulator {_metadrive_version()}", "policy": self.policy,
                "speed_limit_kmh": self.speed_limit_kmh, "oob_tolerance": self.tolerance,
                "road_wall_timeout_s": self.wall_timeout_s, "execution_data": self.execution_data,
                "wheel_friction": self.wheel_friction, "lane_width_m": LANE_WIDTH_M}

    def drive(self, road: wogan.Road) -> wogan.Answer:
        if self.broken:
            self.restart_driver()
        started = time.monotonic()
        try:
            built = build_road(road.points)
        except RoadError as error:
            return wogan.Answer(max_bolp=0.0, outcome="ERROR", sim_time_s=0.0,
                                error=f"road cannot be built: {error}", extra={"policy": self.policy})
        if self.driver is None:
            self.driver = MetaDriveDriver(self.policy, self.speed_limit_kmh, self.tolerance, self.wheel_friction)
        previous = signal.signal(signal.SIGALRM, _on_alarm)
        signal.setitimer(signal.ITIMER_REAL, self.wall_timeout_s)
        try:
            result = self.driver.drive(built, broken=fault_injection(road.id), record=self.execution_data)
        except Exception as error:  # MetaDrive's exceptions are of every kind
            signal.setitimer(signal.ITIMER_REAL, 0)
            what = ("MetaDrive took more than %g s of wall time" % self.wall_timeout_s
                    if isinstance(error, WallTimeout) else f"MetaDrive: {type(error).__name__}: {error}")
            log.exception("road %d: %s; restarting MetaDrive", road.id, what)
            self.broken = True
            return wogan.Answer(max_bolp=0.0, outcome="ERROR", sim_time_s=0.0, error=what,
                                extra={"policy": self.policy, "wall_s": round(time.monotonic() - started, 3)})
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, previous)
        extra: dict = {}
        if result.reason is not None:
            extra["reason"] = result.reason
        extra["policy"] = self.policy
        if result.execution_data is not None:
            extra["execution_data"] = result.execution_data
        extra["wall_s"] = round(time.monotonic() - started, 3)
        return wogan.Answer(max_bolp=result.max_bolp, outcome=result.outcome,
                            sim_time_s=round(result.sim_time_s, 4), oob_side=result.side, oob_point=result.point,
                            min_lane_distance_m=round(result.min_lane_distance_m, 4), extra=extra)

    def restart_driver(self) -> None:
        """Closes the MetaDrive that failed; the next road starts a new one. If it cannot be
        closed, the process cannot go on safely: exit, and wogan starts a new executor."""
        driver, self.driver, self.broken = self.driver, None, False
        if driver is None:
            return
        try:
            driver.close()
        except BaseException as error:  # noqa: BLE001 - anything here means a broken MetaDrive
            log.error("MetaDrive cannot be closed (%s: %s); exiting", type(error).__name__, error)
            os._exit(1)

    def close(self) -> None:
        """`bye`, the end of input or a signal: MetaDrive is closed."""
        if self.broken:
            self.restart_driver()
        elif self.driver is not None:
            self.driver.close()
            self.driver = None


def _metadrive_version() -> str:
    """The installed metadrive-simulator's version ("unknown" when it is not installed)."""
    try:
        from importlib.metadata import version
        return version("metadrive-simulator")
    except Exception:  # noqa: BLE001 - not installed, or no metadata
        return "unknown"


def _on_alarm(signum: int, frame: Any) -> None:
    raise WallTimeout()


def fault_injection(road_id: int) -> bool:
    """For testing the fault paths (examples/metadrive/check.sh): WOGAN_METADRIVE_FAULT=KIND:ID
    makes road ID fail. KIND `exception`: MetaDrive is given the road without its lane's centre
    line, which it refuses (True is returned: break the scenario); `hang`: a wait without end;
    `crash`: the process aborts."""
    spec = os.environ.get("WOGAN_METADRIVE_FAULT", "")
    kind, _, target = spec.partition(":")
    if not spec or target != str(road_id):
        return False
    if kind == "hang":
        while True:
            time.sleep(1)
    if kind == "crash":
        os.abort()
    return kind == "exception"


def set_lane_width(metres: float) -> None:
    """Each lane `metres` wide (`--lane-width`): the road, the start, the lane monitor and the
    expert's navigation all read these two."""
    global LANE_WIDTH_M, ROAD_WIDTH_M
    LANE_WIDTH_M, ROAD_WIDTH_M = float(metres), 2.0 * float(metres)


def _on_terminate(signum: int, frame: Any) -> None:
    raise SystemExit(128 + signum)


def main(argv: Optional[list] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--policy", choices=("idm", "expert"), default="idm",
                        help="who drives: MetaDrive's IDMPolicy or its PPO expert (default idm)")
    parser.add_argument("--road-wall-timeout", type=float, default=300.0, metavar="SECONDS",
                        help="wall time one road may take before it is answered ERROR (default 300)")
    parser.add_argument("--execution-data", action="store_true",
                        help="answers also carry the drive as the SBST pipeline records it "
                             "(`execution_data`, as `wogan simulate --execution-data`), for "
                             "scripts/peers; wogan ignores it")
    parser.add_argument("--wheel-friction", type=float, default=None, metavar="F",
                        help="the tyres' friction, Bullet's friction slip of the wheels (MetaDrive's car: "
                             "0.9; lower is more slippery); MetaDrive's own when absent")
    parser.add_argument("--lane-width", type=float, default=LANE_WIDTH_M, metavar="M",
                        help="the width of each of the road's two lanes, metres (default 4, the "
                             "competition's and wogan's); BOLP is measured against it")
    parser.add_argument("--log-level", default="INFO", help="of the log on standard error")
    args = parser.parse_args(argv)

    logging.basicConfig(level=args.log_level.upper(), stream=sys.stderr,
                        format="[metadrive-executor %(process)d] %(levelname)s %(message)s")
    signal.signal(signal.SIGTERM, _on_terminate)
    signal.signal(signal.SIGINT, _on_terminate)
    if args.wheel_friction is not None and not 0.0 < args.wheel_friction <= 10.0:
        parser.error(f"--wheel-friction: {args.wheel_friction} is not above 0 and at most 10")
    if not 2.5 <= args.lane_width <= 6.0:  # MetaDrive's car is 1.85 m wide
        parser.error(f"--lane-width: {args.lane_width} is not within 2.5 and 6 m")
    set_lane_width(args.lane_width)
    executor = MetaDriveExecutor(args.policy, args.road_wall_timeout, args.execution_data, args.wheel_friction)
    try:
        # Standard output carries the protocol only: serve() keeps it for that, and sends whatever
        # else writes there (MetaDrive, Panda3D, print) to standard error. When wogan closes the
        # answers' pipe, serving ends.
        executor.serve()
    except SystemExit as stop:
        log.info("stopped by a signal; MetaDrive closed")
        return int(stop.code or 0)
    return 0


if __name__ == "__main__":
    sys.exit(main())
