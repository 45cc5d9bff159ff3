#!/usr/bin/env python3
"""A pure-pursuit lane keeper for `wogan --oracle cmd:"python3 pure_pursuit.py"`: it steers towards
the lane-centre point about LOOKAHEAD_M ahead and holds a set speed. Written on the `wogan` Python
package (python/README.md), which speaks the controller protocol (docs/reference.md, "Your own
lane keeper"): each step's observation gives the lane centre ahead in the car's frame (`ahead`: x
forward, y left, metres); steering is a share of the car's largest angle, positive left.
"""
import math
import os
import sys

# Without `pip install .`, the package is found in this checkout's python/ folder.
sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import wogan  # noqa: E402

LOOKAHEAD_M = 8.0   # how far ahead the point steered at lies
WHEELBASE_M = 2.6   # the car's wheelbase (a typical sedan; wogan's car is close to it)
SPEED_MPS = 12.0    # held below the speed limit
GAIN = 0.5          # throttle per m/s below the set speed


class PurePursuit(wogan.Controller):
    def begin(self, road):
        self.max_steering = road.max_steering_rad
        self.speed = min(SPEED_MPS, road.speed_limit_mps)

    def step(self, seen):
        # The first point at least LOOKAHEAD_M away (or the farthest given).
        ahead = seen.ahead
        target = next((p for p in ahead if math.hypot(*p) >= LOOKAHEAD_M), ahead[-1] if ahead else (1.0, 0.0))
        distance = max(math.hypot(*target), 1e-6)
        curvature = 2.0 * target[1] / (distance * distance)
        angle = math.atan(WHEELBASE_M * curvature)
        error = self.speed - seen.speed_mps
        brake = -GAIN * error if error < -1.0 else 0.0
        return wogan.Control.clamped(steering=angle / self.max_steering, throttle=GAIN * error, brake=brake)


PurePursuit().serve()
