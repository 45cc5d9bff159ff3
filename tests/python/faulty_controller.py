#!/usr/bin/env python3
"""A controller for `wogan --oracle cmd:...` that misbehaves on purpose, for the end-to-end tests.

    faulty_controller.py MODE ROAD STEP

It drives straight ahead at a steady throttle, except at step STEP of its ROAD-th drive (both from
1, counted by this process), where MODE happens: `crash` (exit 3 after a line on stderr), `hang`
(never answer), `garbage` (a line that is not JSON), `range` (steering 5). MODE `always-crash`
exits at the first step of every drive. Standard library only.
"""
import json
import sys
import time

mode, bad_road, bad_step = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
hello = json.loads(sys.stdin.readline())
assert hello["type"] == "hello" and hello["protocol"] == "wogan-controller", hello
road = step = 0
for line in sys.stdin:
    message = json.loads(line)
    if message["type"] == "road":
        road, step = road + 1, 0
        continue
    if message["type"] == "bye":
        break
    if message["type"] != "step":
        continue
    step += 1
    reply = {"steering": 0.0, "throttle": 0.3, "brake": 0.0}
    if mode == "always-crash" or (road == bad_road and step == bad_step):
        if mode in ("crash", "always-crash"):
            print(f"faulty controller: crashing at step {step} of drive {road}", file=sys.stderr, flush=True)
            sys.exit(3)
        if mode == "hang":
            time.sleep(3600)
        if mode == "garbage":
            print("steer left please", flush=True)
            continue
        if mode == "range":
            reply["steering"] = 5
    print(json.dumps(reply), flush=True)
