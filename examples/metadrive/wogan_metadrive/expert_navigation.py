"""The expert's navigation: the 10 navigation values of MetaDrive's procedural (PG) maps, on which
MetaDrive's PPO expert was trained, for a road that is no PG map.

The expert's observation has 275 values: 9 of the car, 10 of navigation (two checkpoints of 5), 240
LiDAR rays and 16 of the 4 nearest cars. `ScenarioOnlineEnv`'s navigation (`TrajectoryNavigation`)
gives 22 navigation values of another kind, so the car is given `ExpertNavigation`: the route cut
into pieces that each turn one way (as a PG map's blocks are straights and arcs), each described as
a PG block (its checkpoint at the piece's end, bend radius, direction, angle), the road one lane
wide.
"""
from __future__ import annotations

from typing import Any

import numpy as np

from .road import lanes


def make_expert_navigation() -> type:
    """A TrajectoryNavigation that gives the 10 navigation values of MetaDrive's PG maps, on which
    the PPO expert was trained (NodeNetworkNavigation `_get_info_for_checkpoint`), for the route
    cut into pieces that each turn one way, as a PG map's blocks (straights and arcs)."""
    from metadrive.component.navigation_module.trajectory_navigation import TrajectoryNavigation
    from metadrive.component.pg_space import BlockParameterSpace, Parameter
    from metadrive.utils.math import clip, norm

    radius_scale = BlockParameterSpace.CURVE[Parameter.radius].max + lanes.lane_width_m  # one lane
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
            return lanes.lane_width_m  # from the centre line to the road's outer edge

        def get_current_lane_width(self) -> float:
            return lanes.lane_width_m

    return ExpertNavigation
