"""A test executor for the Ray pool (`python -m wogan.ray ... ray_executor.py:Traced`): the answers
of geometric_executor.py's Geometric, and for each road a JSON line appended to the file
$WHERE_TO: the road's id, the Ray node and the process that drove it. With SLEEP_S it sleeps that
long a road, as a simulator keeping to real time would (its CPU idle); with DIE_ONCE_AT=N its
process dies the first time it drives road N (the file $WHERE_TO.died marks it), with DIE_AT=N
every time. The pool forwards these variables to its actors with --env."""

import json
import os
import time

import ray
from geometric_executor import Geometric


class Traced(Geometric):
    def drive(self, road):
        where = os.environ.get("WHERE_TO")
        if where:
            with open(where, "a") as f:
                f.write(json.dumps({"id": road.id, "node": ray.get_runtime_context().get_node_id(),
                                    "pid": os.getpid()}) + "\n")
        time.sleep(float(os.environ.get("SLEEP_S", "0")))
        if road.id == int(os.environ.get("DIE_AT", "0")):
            os._exit(3)
        if road.id == int(os.environ.get("DIE_ONCE_AT", "0")) and not os.path.exists(f"{where}.died"):
            open(f"{where}.died", "w").close()
            os._exit(3)
        return super().drive(road)


class NeedsArguments(Geometric):
    """A class that cannot be made without its arguments (the pool's --init gives them)."""

    def __init__(self, policy):
        super().__init__()
        self.policy = policy

    def reported_settings(self):
        return {"policy": self.policy}


NOT_A_CLASS = 3
