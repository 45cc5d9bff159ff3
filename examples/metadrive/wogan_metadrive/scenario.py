"""The road as a MetaDrive scenario: the description `ScenarioOnlineEnv.set_scenario` is given.

Two lanes (the right lane's centre line forward, the left lane's backward, each with its polygon),
a solid yellow centre line, the two road edges, and the ego track, the route MetaDrive's policies
follow: the car's start, then the right lane's centre to the road's end. The scenario is laid in a
frame whose origin is the start (MetaDrive moves its origin there anyway), so a MetaDrive position
plus the start is a point of wogan's map. No traffic, no lights.
"""
from __future__ import annotations

import numpy as np

from .road import Road, lanes, start_pose

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
    right_centre = shifted.offset_line(-lanes.lane_width_m / 2.0)
    left_centre = shifted.offset_line(lanes.lane_width_m / 2.0)
    right_edge = shifted.offset_line(-lanes.road_width_m / 2.0)
    left_edge = shifted.offset_line(lanes.road_width_m / 2.0)

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
