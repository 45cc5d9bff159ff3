#!/usr/bin/env python3
"""A lane keeper that steers from the camera frame alone, for
`wogan --oracle cmd:"python3 camera_keeper.py" --config camera.json` with camera.json
`{"driver": {"camera": true}}`, written on the `wogan` Python package (python/; `pip install .`
installs it, and this file finds it in a checkout).

Each `step` then carries `camera`: the 66 x 200 gray frame of wogan's front camera (DAVE-2's),
row by row from the top. The lane markings are the brightest pixels: in a row two thirds down the
frame, the rightmost bright run is the road's edge and the one left of it the centre line; this
keeper steers to put their midpoint, the lane's centre, in the middle of the image, and holds a
set speed.
"""
import os
import sys

try:
    import wogan
except ImportError:  # run from a checkout without `pip install .`: the package is in python/
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
    import wogan

SPEED_MPS = 8.0
STEER_GAIN = 1.6     # steering share per image half-width of offset
GAIN = 0.5


class CameraKeeper(wogan.Controller):
    def begin(self, road):
        self.speed_limit = min(SPEED_MPS, road.speed_limit_mps)

    def step(self, seen):
        frame = seen.camera
        steering = 0.0
        if frame:
            width, height, gray = frame["width"], frame["height"], frame["gray"]
            y = 2 * height // 3
            row = gray[y * width:(y + 1) * width]
            threshold = (max(row) + sorted(row)[width // 2]) / 2
            runs, start = [], None
            for i, v in enumerate(row + [0]):
                if v > threshold and start is None:
                    start = i
                elif v <= threshold and start is not None:
                    runs.append((start + i - 1) / 2)
                    start = None
            if len(runs) >= 2:
                target = (runs[-1] + runs[-2]) / 2
            elif runs:
                # One marking: the edge if it is right of the middle, else the centre line.
                target = runs[0] - width / 4 if runs[0] > width / 2 else runs[0] + width / 4
            else:
                target = width / 2
            offset = (target - width / 2) / (width / 2)
            steering = max(-1.0, min(1.0, -STEER_GAIN * offset))
        error = self.speed_limit - seen.speed_mps
        throttle = max(0.0, min(1.0, GAIN * error))
        return wogan.Control(steering, throttle, 0.0)


CameraKeeper().serve()
