#!/usr/bin/env python3
"""A peer of wogan that records every line it is sent, for the schema tests: standard library only,
so that what it writes is the protocol as written here, not as the client would shape it.

    recording_peer.py executor FILE     replies to hello, answers every road (max BOLP 0.1)
    recording_peer.py controller FILE   replies to every step (straight on, a little throttle)

Each line read is appended to FILE, each line written to FILE.replies.
"""
import json
import sys

role, record = sys.argv[1], sys.argv[2]
with open(record, "a", encoding="utf-8") as seen, open(record + ".replies", "a", encoding="utf-8") as said:
    for line in sys.stdin:
        seen.write(line)
        message = json.loads(line)
        kind = message.get("type")
        if role == "executor" and kind == "hello":
            reply = {"type": "hello", "protocol": "wogan-executor", "version": 3,
                     "executor": {"name": "recording", "version": "1", "settings": {"role": role}}}
        elif role == "executor" and kind == "road":
            reply = {"id": message["id"], "max_bolp": 0.1, "sim_time_s": 1.0}
        elif role == "controller" and kind == "step":
            reply = {"step": message["step"], "steering": 0.0, "throttle": 0.2, "brake": 0.0}
        else:
            continue
        text = json.dumps(reply)
        said.write(text + "\n")
        print(text, flush=True)
