#!/usr/bin/env python3
"""An executor for `wogan run --executor` that misbehaves on purpose, for the end-to-end tests.

    faulty_executor.py MODE ROAD_ID

It answers `hello` (protocol version 3), then every road, naming it by its `id`, as passed (max
BOLP 0.01, 2 simulated seconds) except the road whose `id` is ROAD_ID, where MODE happens: `crash` (exit 3 after a line on stderr), `hang` (never
answer), `garbage` (a line that is not JSON), `range` (max_bolp 7), `flood` (two lines), `late-second` (a second answer to it written only once the next road has been
read), `wrong-id` (the answer names another road), `error` (an honest ERROR with the reason in
`error`, as an executor whose simulator refused the road answers), or
`fail` (an honest failure: max BOLP 0.9, over the left edge), `fail-placed` (the same, and where:
its third road point), `status` (exit 7), `segv` (killed by SIGSEGV), `orphan` (starts a
process that holds its output, then exits), `ansi` (terminal escape sequences on stderr, then exit
3). MODE `always-crash` exits at every road. Modes that misbehave from the start, whatever ROAD_ID:
`early` (an answer to road 1 written before reading anything), `no-hello` (a version 2 executor:
it never answers `hello`), `bad-stderr` (a line of stderr that is not UTF-8 first, then a log line
per road), `stderr-flood` (4 MB of stderr without a newline per road). Standard library only.
"""
import json
import os
import signal
import subprocess
import sys
import time

mode, bad_id = sys.argv[1], int(sys.argv[2])
if mode == "early":
    print(json.dumps({"id": 1, "max_bolp": 0.99}), flush=True)
if mode == "bad-stderr":
    sys.stderr.buffer.write(b"\xff\xfe not text\n")
    sys.stderr.flush()
hello = json.loads(sys.stdin.readline())
assert hello["type"] == "hello" and hello["protocol"] == "wogan-executor", hello
assert hello["version"] == 3, hello
if mode != "no-hello":
    print(json.dumps({"type": "hello", "protocol": "wogan-executor", "version": 3,
                      "executor": {"name": "faulty", "version": "1", "settings": {"mode": mode}}}), flush=True)
late = None
for line in sys.stdin:
    message = json.loads(line)
    if message["type"] == "bye":
        break
    assert message["type"] == "road", message
    if late is not None:
        print(json.dumps(late), flush=True)
        late = None
    answer = {"id": message["id"], "max_bolp": 0.01, "outcome": "PASS", "sim_time_s": 2.0}
    if mode == "bad-stderr":
        print(f"driving road {message['id']}", file=sys.stderr, flush=True)
    if mode == "stderr-flood":
        sys.stderr.write("s" * 4_000_000)
        sys.stderr.flush()
    if mode == "always-crash" or message["id"] == bad_id:
        if mode in ("crash", "always-crash"):
            print(f"faulty executor: crashing at road {message['id']}", file=sys.stderr, flush=True)
            sys.exit(3)
        if mode == "hang":
            time.sleep(3600)
        if mode == "status":
            sys.exit(7)
        if mode == "segv":
            os.kill(os.getpid(), signal.SIGSEGV)
        if mode == "orphan":
            subprocess.Popen(["sleep", "30"], stdout=sys.stdout, stderr=subprocess.DEVNULL)
            sys.exit(0)
        if mode == "ansi":
            print("\x1b]0;TITLE\x07\x1b[2Jcleared", file=sys.stderr, flush=True)
            sys.exit(3)
        if mode == "garbage":
            print("this is not JSON", flush=True)
            continue
        if mode == "range":
            answer["max_bolp"] = 7
        if mode == "wrong-id":
            answer["id"] = message["id"] + 100
        if mode == "flood":
            print(json.dumps(answer), flush=True)
        if mode == "late-second":
            late = answer
        if mode == "error":
            answer = {"id": message["id"], "max_bolp": 0, "outcome": "ERROR",
                      "error": f"the simulator refused road {message['id']}"}
        if mode == "fail":
            answer = {"id": message["id"], "max_bolp": 0.9, "oob_side": "left", "sim_time_s": 1.5}
        if mode == "fail-placed":
            answer = {"id": message["id"], "max_bolp": 0.9, "oob_side": "left", "sim_time_s": 1.5,
                      "oob_point": message["road_points"][2]}
    print(json.dumps(answer), flush=True)
