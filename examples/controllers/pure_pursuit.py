#!/usr/bin/env python3
"""A pure-pursuit lane keeper for `wogan --oracle cmd:"python3 pure_pursuit.py"`, standard library
only: it steers towards the lane-centre point about LOOKAHEAD_M ahead and holds a set speed.

Each `step` line gives the lane centre ahead in the car's frame (`ahead`: x forward, y left,
metres); the reply is `{"step": n, "steering": s, "throttle": t, "brake": b}`: the step's number,
and steering a share of the car's largest angle, positive left. Lines of other types (`hello`, `road`, `end`, `bye`) get no
reply. The protocol is in wogan's docs/reference.md ("Your own lane keeper").
"""
import json
import math
import sys

LOOKAHEAD_M = 8.0   # how far ahead the point steered at lies
WHEELBASE_M = 2.6   # the car's wheelbase (a typical sedan; wogan's car is close to it)
SPEED_MPS = 12.0    # held below the speed limit
GAIN = 0.5          # throttle per m/s below the set speed

max_steering = 0.6
speed_limit = SPEED_MPS
for line in sys.stdin:
    message = json.loads(line)
    kind = message["type"]
    if kind == "road":
        max_steering = message["max_steering_rad"]
        speed_limit = min(SPEED_MPS, message["speed_limit_mps"])
        continue
    if kind == "bye":
        break
    if kind != "step":
        continue
    ahead = message["ahead"]
    # The first point at least LOOKAHEAD_M away (or the farthest given).
    target = next((p for p in ahead if math.hypot(p[0], p[1]) >= LOOKAHEAD_M), ahead[-1] if ahead else [1.0, 0.0])
    distance = max(math.hypot(target[0], target[1]), 1e-6)
    curvature = 2.0 * target[1] / (distance * distance)
    angle = math.atan(WHEELBASE_M * curvature)
    steering = max(-1.0, min(1.0, angle / max_steering))
    error = speed_limit - message["speed_mps"]
    throttle = max(0.0, min(1.0, GAIN * error))
    brake = max(0.0, min(1.0, -GAIN * error)) if error < -1.0 else 0.0
    reply = {"step": message["step"], "steering": steering, "throttle": throttle, "brake": brake}
    print(json.dumps(reply), flush=True)
