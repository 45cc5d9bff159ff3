#!/usr/bin/env python3
"""An executor for `wogan run --executor` that drives several roads at once, for the end-to-end
tests of roads in flight.

    concurrent_executor.py MODE ROADS_AT_ONCE [ROAD_ID]

It announces ROADS_AT_ONCE in its reply to `hello` and answers each road on a thread of its own
after a delay that depends on the road's `id`, so that answers come out of order. An answer is a
function of the road alone (max BOLP from its points), so any order, and any number of roads at
once, gives the same test records. MODE `ok` behaves; at the road whose `id` is ROAD_ID, `twice`
answers it twice, `unsent` answers a road it was never sent instead, and `die` ends the process
(exit 3) with the roads it holds unanswered. Standard library only.
"""
import json
import os
import sys
import threading
import time

mode, at_once = sys.argv[1], int(sys.argv[2])
bad_id = int(sys.argv[3]) if len(sys.argv) > 3 else 0
hello = json.loads(sys.stdin.readline())
assert hello["type"] == "hello" and hello["version"] == 3, hello
out = threading.Lock()


def say(message):
    with out:
        print(json.dumps(message), flush=True)


say({"type": "hello", "protocol": "wogan-executor", "version": 3, "roads_at_once": at_once,
     "executor": {"name": "concurrent", "settings": {"mode": mode}}})


def answer(road):
    road_id = road["id"]
    time.sleep(0.005 * (road_id % 4))
    bolp = sum(abs(x) + abs(y) for x, y in road["road_points"]) * 997 % 1.0
    reply = {"id": road_id, "max_bolp": bolp, "sim_time_s": 2.0}
    if road_id == bad_id and mode == "unsent":
        reply["id"] = road_id + 1000
    say(reply)
    if road_id == bad_id and mode == "twice":
        say(reply)


for line in sys.stdin:
    message = json.loads(line)
    if message["type"] == "bye":
        break
    if message["type"] != "road":
        continue
    if message["id"] == bad_id and mode == "die":
        print(f"concurrent executor: dying at road {bad_id}", file=sys.stderr, flush=True)
        os._exit(3)
    threading.Thread(target=answer, args=(message,)).start()
