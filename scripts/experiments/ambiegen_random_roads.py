"""AmbieGen's road family without AmbieGen's search: a test generator for the competition's
pipeline that drives random roads drawn as AmbieGen draws its first population.

Development-time only (docs/experiments/2026-11-28-winding-roads.md): does AmbieGen's lead in
the paper's diversity on dave2-proxy come from how it builds roads (chains of straights and turns
of 10–85°, run until the map's edge) or from how its search picks them? Each road is a state chain
from AmbieGen's own `RoadGen`, made into points and interpolated by its own `Solution` and car
model, and driven once; nothing is optimised. Imported from a checkout of AmbieGen's competition
entry (scripts/peers/README.md, `pr/108`), run by run_peer.py:

    ~/peers/venv/bin/python scripts/peers/run_peer.py --pipeline ~/peers/pr/108 \
        --module-path scripts/experiments --module-name ambiegen_random_roads \
        --class-name AmbieGenRandomRoads --wogan target/release/wogan --oracle dave2-proxy \
        --seed 1 --out target/probe/dave2-proxy.agrand.1
"""

import ambiegen.config as cf
from ambiegen.Solution import Solution
from ambiegen.road_gen import RoadGen
from code_pipeline.tests_generation import RoadTestFactory


class AmbieGenRandomRoads:
    """Random AmbieGen roads until the pipeline's budget is spent."""

    def __init__(self, time_budget=None, executor=None, map_size=None):
        self.executor = executor

    def start(self):
        model = cf.model
        roads = RoadGen(model["map_size"], model["min_len"], model["max_len"],
                        model["min_angle"], model["max_angle"])
        while not self.executor.is_over():
            road = Solution()
            road.states = roads.test_case_generate()
            road.get_points()
            road.remove_invalid_cases()
            # AmbieGen's own floor: a chain of two points or fewer is no road.
            if len(road.road_points) <= 2:
                continue
            points = road.car.interpolate_road(road.road_points)
            self.executor.execute_test(RoadTestFactory.create_road_test(points))
