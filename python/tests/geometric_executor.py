"""A test executor written with wogan.Executor: it "drives" a road by its sharpest bend (BOLP =
the largest turn between two segments / 0.8 rad, at most 1), so that some roads fail, and prints
to stdout (which serve() sends to stderr). With RAISE_AT=N its drive raises at road N; with
HELLO_TO=FILE its hello hook appends hello's fields to FILE, a JSON line; with HELLO_RAISES=1 it
raises (a simulator that does not start)."""

import json
import math
import os

import wogan


def bolp_of(points):
    headings = [math.atan2(b[1] - a[1], b[0] - a[0]) for a, b in zip(points, points[1:])]
    turns = [abs(math.remainder(b - a, math.tau)) for a, b in zip(headings, headings[1:])]
    return min(1.0, max(turns, default=0.0) / 0.8)


class Geometric(wogan.Executor):
    version = "1.0"

    def hello(self, settings):
        if os.environ.get("HELLO_RAISES") == "1":
            raise RuntimeError("the simulator did not start")
        if os.environ.get("HELLO_TO"):
            with open(os.environ["HELLO_TO"], "a") as f:
                f.write(json.dumps(settings) + "\n")

    def reported_settings(self):
        return {"bolp": "sharpest turn / 0.8 rad"}

    def drive(self, road):
        if road.id == int(os.environ.get("RAISE_AT", "0")):
            raise ValueError(f"road {road.id} refused on purpose")
        bolp = bolp_of(road.points)
        print(f"road {road.id}: bolp {bolp:.3f}")  # not a protocol line: it must not reach wogan
        failed = bolp > self.settings["oob_tolerance"]
        return wogan.Answer(max_bolp=bolp, sim_time_s=10.0, oob_side="left" if failed else None,
                            oob_point=road.points[2] if failed else None)


if __name__ == "__main__":
    Geometric().serve()
