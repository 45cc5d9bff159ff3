#!/usr/bin/env python3
"""An executor for `wogan run --executor` that misbehaves on purpose, for the end-to-end tests.

    faulty_executor.py MODE ROAD_ID

Every road is answered, naming it by its `id`, as passed (max BOLP 0.01, 2 simulated seconds) except the road whose
`id` is ROAD_ID, where MODE happens: `crash` (exit 3 after a line on stderr), `hang` (never
answer), `garbage` (a line that is not JSON), `range` (max_bolp 7), `flood` (two lines), `late-second` (a second answer to it written only once the next road has been
read), `wrong-id` (the answer names another road), `error` (an honest ERROR with the reason in
`error`, as an executor whose simulator refused the road answers), or
`fail` (an honest failure: max BOLP 0.9, over the left edge), `fail-placed` (the same, and where:
its third road point). MODE `always-crash` exits at every road. Standard
library only.
"""
import json
import sys
import time

mode, bad_id = sys.argv[1], int(sys.argv[2])
hello = json.loads(sys.stdin.readline())
assert hello["type"] == "hello" and hello["protocol"] == "wogan-executor", hello
assert hello["version"] == 2, hello
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
    if mode == "always-crash" or message["id"] == bad_id:
        if mode in ("crash", "always-crash"):
            print(f"faulty executor: crashing at road {message['id']}", file=sys.stderr, flush=True)
            sys.exit(3)
        if mode == "hang":
            time.sleep(3600)
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
