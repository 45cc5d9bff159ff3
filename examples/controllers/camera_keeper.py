#!/usr/bin/env python3
"""A lane keeper that steers from the camera frame alone, for
`wogan --oracle cmd:"python3 camera_keeper.py" --config camera.json` with camera.json
`{"driver": {"camera": true}}`, written on the `wogan` Python package (python/README.md).

Each step's observation then carries `camera`: the 66 x 200 gray frame of wogan's front camera
(DAVE-2's). The lane markings are the brightest pixels: in a row two thirds down the frame, the
rightmost bright run is the road's edge and the one left of it the centre line; this keeper steers
to put their midpoint, the lane's centre, in the middle of the image, and holds a set speed.
"""
import os
import sys

# Without `pip install .`, the package is found in this checkout's python/ folder.
sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import wogan  # noqa: E402

SPEED_MPS = 8.0
STEER_GAIN = 1.6     # steering share per image half-width of offset
GAIN = 0.5


def lane_centre_column(frame):
    """The column of the lane's centre in the row two thirds down `frame` (its middle if no
    marking is seen)."""
    width = frame.width
    row = frame.row(2 * frame.height // 3)
    threshold = (max(row) + sorted(row)[width // 2]) / 2
    runs, start = [], None  # the middle column of each run of bright pixels
    for i, v in enumerate(row + [0]):
        if v > threshold and start is None:
            start = i
        elif v <= threshold and start is not None:
            runs.append((start + i - 1) / 2)
            start = None
    if len(runs) >= 2:
        return (runs[-1] + runs[-2]) / 2
    if runs:  # one marking: the edge if it is right of the middle, else the centre line
        return runs[0] - width / 4 if runs[0] > width / 2 else runs[0] + width / 4
    return width / 2


class CameraKeeper(wogan.Controller):
    def begin(self, road):
        self.speed = min(SPEED_MPS, road.speed_limit_mps)

    def step(self, seen):
        steering = 0.0
        if seen.camera:
            half = seen.camera.width / 2
            offset = (lane_centre_column(seen.camera) - half) / half
            steering = -STEER_GAIN * offset
        return wogan.Control.clamped(steering, throttle=GAIN * (self.speed - seen.speed_mps))


CameraKeeper().serve()
