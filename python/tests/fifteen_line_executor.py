import math

import wogan


class Bends(wogan.Executor):
    def drive(self, road):
        xs, ys = zip(*road.points)
        heading = [math.atan2(y1 - y0, x1 - x0) for x0, y0, x1, y1 in zip(xs, ys, xs[1:], ys[1:])]
        turn = max(abs(b - a) for a, b in zip(heading, heading[1:]))
        return wogan.Answer(max_bolp=min(1.0, turn), sim_time_s=5.0)


Bends().serve()
