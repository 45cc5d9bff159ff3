"""The Python client of `wogan`, which finds roads on which a lane keeper leaves its lane.

Speak wogan's protocols without writing the line loop:

    import wogan

    class MyExecutor(wogan.Executor):
        def drive(self, road):                  # road.id, road.points: [(x, y), ...] metres
            bolp = my_simulator(road.points)    # the largest share of the car outside its lane
            return wogan.Answer(max_bolp=bolp)

    MyExecutor().serve()                        # wogan run --executor cmd:"python3 my_executor.py"

`Controller` steers wogan's own car (`--oracle cmd:...`); `read_run` reads a run or a suite file;
`run` runs the installed binary and reads what it wrote. Standard library only.
"""

from .controller import Control, Controller, Observation
from .executor import Answer, Executor, Road
from .run_file import Run, RunFileError, read_run
from .runner import WoganError, binary, run

try:
    from importlib.metadata import PackageNotFoundError, version

    __version__ = version("wogan")
except PackageNotFoundError:  # used from a checkout, not installed
    __version__ = "0+unknown"

__all__ = [
    "Answer", "Control", "Controller", "Executor", "Observation", "Road", "Run", "RunFileError",
    "WoganError", "binary", "read_run", "run", "__version__",
]
