"""Who drives the car: MetaDrive's policies, made to hold the speed limit `hello` gives.

- `idm`: MetaDrive's `IDMPolicy` (a PID steering onto the route, IDM throttle), lane changes off.
- `expert`: MetaDrive's PPO expert (`metadrive.examples.ppo_expert`, numpy inference), its mean
  action, no throttle above the speed limit. It reads the LiDAR-state observation of MetaDrive's
  procedural maps, which needs the expert's sensors (EXPERT_SENSORS) and navigation
  (expert_navigation.py) on the car.

The classes are made by functions, at MetaDrive's start: MetaDrive is imported only then, and the
speed limit is a class attribute of IDMPolicy.
"""
from __future__ import annotations

from typing import Any

import numpy as np


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
