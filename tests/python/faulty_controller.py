#!/usr/bin/env python3
"""A controller for `wogan --oracle cmd:...` that misbehaves on purpose, for the end-to-end tests.

    faulty_controller.py MODE ROAD STEP

It drives straight ahead at a steady throttle, except at step STEP of its ROAD-th drive (both from
1, counted by this process), where MODE happens: `crash` (exit 3 after a line on stderr), `hang`
(never answer), `garbage` (a line that is not JSON), `range` (steering 5), `wrong-step` (the reply
names another step), `flood` (two replies), `late-second` (a second reply to it written only once
the next step has been read), `end-second` (its drive's last step replied to again when the drive
ends; STEP is not used). Every reply names its step. MODE `always-crash` exits at the first step
of every drive; MODE `slow-start` starts slower than a step's deadline (it waits 1.5 s before
reading `hello`) and then drives well; MODE `bad-stderr` writes a stderr line that is not UTF-8
first and a log line to stderr at every step, and drives well. Standard library only.
"""
import json
import sys
import time

mode, bad_road, bad_step = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
if mode == "slow-start":
    time.sleep(1.5)
if mode == "bad-stderr":
    sys.stderr.buffer.write(b"\xff\xfe not text\n")
    sys.stderr.flush()
hello = json.loads(sys.stdin.readline())
assert hello["type"] == "hello" and hello["protocol"] == "wogan-controller", hello
assert hello["version"] == 2, hello
road = step = 0
late = last = None
for line in sys.stdin:
    message = json.loads(line)
    if message["type"] == "road":
        road, step = road + 1, 0
        continue
    if message["type"] == "bye":
        break
    if message["type"] == "end" and mode == "end-second" and road == bad_road:
        print(json.dumps(last), flush=True)
    if message["type"] != "step":
        continue
    step += 1
    assert message["step"] == step, message
    if mode == "bad-stderr":
        print(f"step {step}", file=sys.stderr, flush=True)
    if late is not None:
        print(json.dumps(late), flush=True)
        late = None
    reply = {"step": step, "steering": 0.0, "throttle": 0.3, "brake": 0.0}
    last = reply
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
        if mode == "wrong-step":
            reply["step"] = step + 100
        if mode == "flood":
            print(json.dumps(reply), flush=True)
        if mode == "late-second":
            late = reply
    print(json.dumps(reply), flush=True)
