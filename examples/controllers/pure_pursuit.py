#!/usr/bin/env python3
"""A pure-pursuit lane keeper for `wogan --oracle cmd:"python3 pure_pursuit.py"`, written on the
`wogan` Python package (python/; `pip install .` installs it, and this file finds it in a
checkout): it steers towards the lane-centre point about LOOKAHEAD_M ahead and holds a set speed.

Each step's observation gives the lane centre ahead in the car's frame (`ahead`: x forward, y
left, metres); the control's steering is a share of the car's largest angle, positive left. The
protocol is in wogan's docs/reference.md ("Your own lane keeper").
"""
import math
import os
import sys

try:
    import wogan
except ImportError:  # run from a checkout without `pip install .`: the package is in python/
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
    import wogan

LOOKAHEAD_M = 8.0   # how far ahead the point steered at lies
WHEELBASE_M = 2.6   # the car's wheelbase (a typical sedan; wogan's car is close to it)
SPEED_MPS = 12.0    # held below the speed limit
GAIN = 0.5          # throttle per m/s below the set speed


class PurePursuit(wogan.Controller):
    def begin(self, road):
        self.max_steering = road.max_steering_rad
        self.speed_limit = min(SPEED_MPS, road.speed_limit_mps)

    def step(self, seen):
        # The first point at least LOOKAHEAD_M away (or the farthest given).
        ahead = seen.ahead
        target = next((p for p in ahead if math.hypot(p[0], p[1]) >= LOOKAHEAD_M), ahead[-1] if ahead else (1.0, 0.0))
        distance = max(math.hypot(target[0], target[1]), 1e-6)
        curvature = 2.0 * target[1] / (distance * distance)
        steering = max(-1.0, min(1.0, math.atan(WHEELBASE_M * curvature) / self.max_steering))
        error = self.speed_limit - seen.speed_mps
        throttle = max(0.0, min(1.0, GAIN * error))
        brake = max(0.0, min(1.0, -GAIN * error)) if error < -1.0 else 0.0
        return wogan.Control(steering, throttle, brake)


PurePursuit().serve()
