"""A test controller: steers at the lane-centre point about 8 m ahead, holds about 12 m/s."""

import math

import wogan


class Pursuit(wogan.Controller):
    def begin(self, road):
        self.limit = min(12.0, road.speed_limit_mps)
        self.max_steering = road.max_steering_rad

    def step(self, seen):
        x, y = next(((px, py) for px, py in seen.ahead if px >= 8.0), seen.ahead[-1])
        angle = math.atan2(2.0 * 2.7 * y, x * x + y * y)
        steering = max(-1.0, min(1.0, angle / self.max_steering))
        throttle = 0.6 if seen.speed_mps < self.limit else 0.0
        return wogan.Control(steering=steering, throttle=throttle, brake=0.0)


Pursuit().serve()
