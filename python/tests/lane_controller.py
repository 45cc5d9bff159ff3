"""A test controller written with wogan.Controller: steers at the lane-centre point about 8 m
ahead, holds about 12 m/s, and prints to stdout (which serve() sends to stderr). With
RAISE_AT=D:S its step raises at step S of its D-th drive (counted by this process)."""

import math
import os

import wogan


class Pursuit(wogan.Controller):
    drives = 0

    def begin(self, road):
        self.drives += 1
        self.limit = min(12.0, road.speed_limit_mps)
        self.max_steering = road.max_steering_rad
        print(f"drive {self.drives}: {len(road.lane_centre)} lane points")

    def step(self, seen):
        if os.environ.get("RAISE_AT") == f"{self.drives}:{seen.step}":
            raise RuntimeError(f"step {seen.step} of drive {self.drives} refused on purpose")
        x, y = next(((px, py) for px, py in seen.ahead if math.hypot(px, py) >= 8.0), seen.ahead[-1])
        angle = math.atan(2.0 * 2.6 * y / (x * x + y * y))
        steering = angle / self.max_steering
        throttle = 0.5 * (self.limit - seen.speed_mps)
        return wogan.Control.clamped(steering, throttle, 0.0)


if __name__ == "__main__":
    Pursuit().serve()
