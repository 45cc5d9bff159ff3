"""The Python client of `wogan`, which finds roads on which a self-driving car's lane keeper leaves
its lane. Standard library only; python/README.md in wogan's repository has the whole API.

Your simulator, as the executor of a search (`wogan run --executor cmd:"python3 mine.py"`):

    import wogan

    class Mine(wogan.Executor):
        def drive(self, road):                    # road.id, road.points: [(x, y), ...] metres
            bolp = my_simulator(road.points)      # the largest share of the car outside its lane
            return wogan.Answer(max_bolp=bolp, sim_time_s=12.5)

    Mine().serve()                                # hello, roads, bye on stdin/stdout

An exception in `drive` answers that road ERROR with its message, and serving goes on; `print`
goes to stderr once serving begins; `self.settings` holds `hello`'s fields (`oob_tolerance`, ...).

Your lane keeper, steering wogan's car (`wogan run --oracle cmd:"python3 keeper.py"`):

    class Keeper(wogan.Controller):
        def begin(self, road):                    # road.lane_centre, road.speed_limit_mps, ...
            ...
        def step(self, seen):                     # seen.ahead, seen.speed_mps, seen.camera, ...
            return wogan.Control(steering=0.0, throttle=0.5, brake=0.0)

    Keeper().serve()

Runs and suites read back, and the binary run from Python:

    run = wogan.read_run("run.jsonl")             # .header, .tests (dicts, in order), .summary
    run = wogan.run(["--max-tests", "20", "--seed", "1"])   # the installed binary; its run read
    with wogan.Simulator() as simulator:          # a `wogan simulate` child, one road at a time
        result = simulator.drive([(100, 10), (100, 60), (100, 110)])
"""

from .controller import Control, Controller, DriveRoad, Frame, Observation
from .executor import Answer, Executor, Road
from .run_file import Run, RunFileError, read_run
from .runner import WoganError, find_binary, run
from .simulator import Simulator


def _version() -> str:
    try:
        from importlib.metadata import PackageNotFoundError, version
    except ImportError:  # Python 3.7
        return "0+unknown"
    try:
        return version("wogan")
    except PackageNotFoundError:  # used from a checkout, not installed
        return "0+unknown"


__version__ = _version()

__all__ = [
    "Answer", "Control", "Controller", "DriveRoad", "Executor", "Frame", "Observation", "Road", "Run",
    "RunFileError", "Simulator", "WoganError", "find_binary", "read_run", "run", "__version__",
]
