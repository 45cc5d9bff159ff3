"""A test executor: "drives" a road by its sharpest bend (BOLP grows with the largest turn
between two segments), so that some roads fail. With RAISE_AT=N its drive raises at road N."""

import math
import os

import wogan


class Geometric(wogan.Executor):
    def drive(self, road):
        if road.id == int(os.environ.get("RAISE_AT", "0")):
            raise ValueError(f"road {road.id} refused on purpose")
        headings = [math.atan2(b[1] - a[1], b[0] - a[0]) for a, b in zip(road.points, road.points[1:])]
        turns = [abs((b - a + math.pi) % (2 * math.pi) - math.pi) for a, b in zip(headings, headings[1:])]
        bolp = min(1.0, max(turns, default=0.0) / 0.8)
        print(f"road {road.id}: bolp {bolp:.3f}")  # to stderr: serve() keeps stdout for protocol lines
        return wogan.Answer(max_bolp=bolp, sim_time_s=10.0,
                            oob_side="left" if bolp > self.settings["oob_tolerance"] else None)


Geometric().serve()
