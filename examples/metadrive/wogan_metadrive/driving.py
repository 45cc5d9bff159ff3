"""Driving a road in MetaDrive: one `ScenarioOnlineEnv` kept for many roads, the car sampled
before every physics step (50 Hz) by the lane monitor, and the drive's result.

MetaDrive's own ends of a drive (arrival, out of road) are ignored: the lane monitor's verdict,
wogan's rules, ends it. The policy drives; the action given to `env.step` is not used.
"""
from __future__ import annotations

import logging
import os
import pickle
import shutil
import tempfile
import time
from dataclasses import dataclass
from typing import Any, Callable, Optional

import numpy as np

from .execution_data import ExecutionData
from .expert_navigation import make_expert_navigation
from .lane_monitor import LaneMonitor, Verdict
from .policies import EXPERT_SENSORS, make_expert_policy, make_idm_policy
from .road import Road, build_road
from .scenario import scenario_of

log = logging.getLogger("metadrive-executor")


@dataclass
class DriveResult:
    """How a drive ended (the lane monitor's verdict), with its measures."""

    outcome: str  # PASS, FAIL or ERROR
    reason: Optional[str]
    max_bolp: float
    sim_time_s: float
    side: Optional[str]  # out of lane only
    point: Optional[tuple]  # out of lane only
    min_lane_distance_m: float
    execution_data: Optional[list]  # with --execution-data


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
        return DriveResult(outcome=v.outcome, reason=v.reason, max_bolp=monitor.max_bolp, sim_time_s=v.t_s,
                           side=v.side, point=v.point, min_lane_distance_m=monitor.min_lane_distance_m,
                           execution_data=recorder.records if recorder is not None else None)
