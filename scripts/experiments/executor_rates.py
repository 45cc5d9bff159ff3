#!/usr/bin/env python3
"""How often an executor's driver fails a road family: the roads of a file driven through an
executor (wogan's executor protocol, version 3, docs/reference.md) at each speed limit asked,
`--jobs` executors at once, the failures counted per `generator` (the dev set's FreneticV, AmbieGen
and the pipeline's random generator) and in all. This is how MetaDrive's subjects are calibrated
as wogan's own drivers were (scripts/runs/driver_rates.sh): a subject must fail a BeamNG.AI-like
share (8-20%) of the SBST 2022 entries' roads before it can judge a search.

    python3 scripts/experiments/executor_rates.py --speeds 45 47 50 \\
        --out target/results/metadrive_rates.idm.jsonl \\
        -- target/metadrive-venv/bin/python examples/metadrive/executor.py --policy idm

Writes one JSON line per road and speed to `--out` (`speed_limit_kmh`, `line` of `--roads`,
`generator`, the answer's `outcome`, `reason`, `max_bolp`, `sim_time_s`, `error`) and prints the
executor's settings (its reply to `hello`), a table of rates and the failures by reason.
`--generator` keeps the roads of one generator only, `--limit N` the first N of them.
Deterministic as the executor is (MetaDrive's IDM and expert are). Standard library only.
"""

import argparse
import json
import subprocess
import sys
import threading
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DEV_ROADS = ROOT / "tests" / "reference" / "peer_roads_dev.jsonl"


class Executor:
    """One executor process: hello answered, then one road, one answer naming its `id`."""

    def __init__(self, command, speed_limit_kmh, tolerance, map_size_m):
        self.process = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        self.send({"type": "hello", "protocol": "wogan-executor", "version": 3, "units": "metres, seconds",
                   "map_size_m": map_size_m, "oob_tolerance": tolerance, "speed_limit_kmh": speed_limit_kmh})
        reply = json.loads(self.process.stdout.readline() or "null")
        if not isinstance(reply, dict) or reply.get("type") != "hello" or reply.get("version") != 3:
            raise SystemExit(f"executor_rates: the executor answered hello with {reply!r}")
        self.description = reply.get("executor") or {}

    def send(self, message):
        self.process.stdin.write(json.dumps(message) + "\n")
        self.process.stdin.flush()

    def drive(self, road_id, road_points):
        self.send({"type": "road", "id": road_id, "road_points": road_points})
        line = self.process.stdout.readline()
        if not line:
            raise SystemExit(f"executor_rates: the executor ended at road {road_id}")
        answer = json.loads(line)
        if answer.get("id") != road_id:
            raise SystemExit(f"executor_rates: answer {answer!r} to road {road_id}")
        return answer

    def close(self):
        self.send({"type": "bye"})
        self.process.stdin.close()
        self.process.wait()


def drive_all(command, roads, speed, tolerance, map_size, jobs):
    """The answers to `roads` (a list of dicts), in order, `jobs` executors sharing them."""
    answers = [None] * len(roads)

    def worker(offset):
        executor = Executor(command, speed, tolerance, map_size)
        if offset == 0:
            print(f"# {speed:g} km/h, the executor's settings: {json.dumps(executor.description)}", flush=True)
        try:
            for index in range(offset, len(roads), jobs):
                answers[index] = executor.drive(index + 1, roads[index]["road_points"])
        finally:
            executor.close()

    threads = [threading.Thread(target=worker, args=(offset,)) for offset in range(jobs)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    if any(answer is None for answer in answers):
        raise SystemExit("executor_rates: a worker failed; see its message above")
    return answers


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--roads", type=Path, default=DEV_ROADS, help="JSON lines with road_points (and generator)")
    parser.add_argument("--generator", help="only the roads whose `generator` is this")
    parser.add_argument("--limit", type=int, help="only the first N roads (of --generator's)")
    parser.add_argument("--speeds", type=float, nargs="+", required=True, help="speed limits, km/h")
    parser.add_argument("--tolerance", type=float, default=0.85, help="BOLP above which a drive fails")
    parser.add_argument("--map-size", type=float, default=200.0)
    parser.add_argument("--jobs", type=int, default=2, help="executors at once")
    parser.add_argument("--out", type=Path, required=True, help="JSON lines: one per road and speed")
    parser.add_argument("command", nargs="+", help="the executor's command, after --")
    args = parser.parse_args()
    roads = [dict(json.loads(text), _line=number)
             for number, text in enumerate(args.roads.read_text().splitlines(), 1) if text.strip()]
    if args.generator:
        roads = [road for road in roads if road.get("generator") == args.generator]
        if not roads:
            raise SystemExit(f"executor_rates: no road of {args.roads} has generator {args.generator!r}")
    if args.limit:
        roads = roads[:args.limit]
    args.out.parent.mkdir(parents=True, exist_ok=True)
    with args.out.open("w") as out:
        print(f"{'speed km/h':>10}  {'family':<28} {'failed':>6} / {'roads':<5} {'rate':>6}  errors")
        for speed in args.speeds:
            answers = drive_all(args.command, roads, speed, args.tolerance, args.map_size, args.jobs)
            failed, total, errors, reasons = Counter(), Counter(), Counter(), Counter()
            for road, answer in zip(roads, answers):
                family = road.get("generator", "all")
                total[family] += 1
                failed[family] += answer.get("outcome") == "FAIL" or (
                    answer.get("outcome") is None and answer["max_bolp"] > args.tolerance)
                errors[family] += answer.get("outcome") == "ERROR"
                if answer.get("outcome") == "FAIL":
                    reasons[answer.get("reason") or "unknown"] += 1
                out.write(json.dumps({"speed_limit_kmh": speed, "line": road["_line"], "generator": family,
                                      "outcome": answer.get("outcome"), "reason": answer.get("reason"),
                                      "max_bolp": answer.get("max_bolp"), "sim_time_s": answer.get("sim_time_s"),
                                      "error": answer.get("error")}) + "\n")
            out.flush()
            for family in sorted(total) + ["all"]:
                f = sum(failed.values()) if family == "all" else failed[family]
                n = sum(total.values()) if family == "all" else total[family]
                e = sum(errors.values()) if family == "all" else errors[family]
                print(f"{speed:>10g}  {family:<28} {f:>6} / {n:<5} {100 * f / n:>5.1f}%  {e}", flush=True)
            print(f"{speed:>10g}  failures by reason: "
                  + (", ".join(f"{r} {c}" for r, c in sorted(reasons.items())) or "none"), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
