"""wogan's own simulator as a child process, one road at a time: a `wogan simulate` kept running,
written one road and read its answer before the next (docs/reference.md, "wogan simulate").

    with wogan.Simulator(["--oracle", "dave2-proxy"]) as simulator:
        result = simulator.drive([(100, 10), (100, 60), (100, 110)])
        print(result["outcome"], result["max_bolp"])
"""

import json
import logging
import os
import subprocess
from typing import Any, Dict, Iterable, List, Optional, Sequence, Union

from .runner import WoganError, find_binary

log = logging.getLogger("wogan")

Command = Union[str, "os.PathLike[str]", Sequence[str]]


class Simulator:
    """A `wogan simulate OPTIONS` child (`--oracle`, `--speed-limit`, `--oob-tolerance`,
    `--map-size`, `--config FILE`, `--execution-data`, ...). `binary`: the binary's path, or a
    command as a list (["python3", "fake.py"]); by default `find_binary()`. Its stderr is this
    process's. `process` is the child (a subprocess.Popen).

    `drive(points)` writes one road and returns its answer line: a `result` (`outcome` PASS, FAIL,
    ERROR or INVALID for a road the validator refuses, `max_bolp`, `sim_time_s`, `oob`, ...) or an
    `error` (a line that holds no road). A child that ended, or a line that is not the answer to
    the road written, raises WoganError. `close()` ends the child (closing its input is its sign
    to finish) and returns its exit status; a `with` block closes it too.
    """

    def __init__(self, options: Iterable[str] = (), *, binary: Optional[Command] = None) -> None:
        if binary is None:
            command = [find_binary()]
        elif isinstance(binary, (str, os.PathLike)):
            command = [os.fspath(binary)]
        else:
            command = list(binary)
        command += ["simulate", *options]
        self.command = command
        self.process = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                        text=True, encoding="utf-8", bufsize=1)
        self.lines_sent = 0

    def drive(self, points: Iterable[Sequence[float]], *, label: Optional[str] = None,
              **fields: Any) -> Dict[str, Any]:
        """Drives the road through `points` ([x, y], metres) and returns wogan's answer line.
        `fields` go into the input line too (an `id`, which the answer echoes). `label` names the
        road in a WoganError's message (by default "road N", N counting from 1)."""
        line_number = self.lines_sent + 1
        label = label or f"road {line_number}"
        road: List[List[float]] = [[float(x), float(y)] for x, y in points]
        text = json.dumps({**fields, "road_points": road}, allow_nan=False) + "\n"
        stdin, stdout = self.process.stdin, self.process.stdout
        assert stdin is not None and stdout is not None
        try:
            stdin.write(text)
            stdin.flush()
            answer_line = stdout.readline()
        except (BrokenPipeError, ValueError):  # ValueError: the pipe was closed already
            answer_line = ""
        self.lines_sent += 1
        if not answer_line:
            status = self.process.poll()
            raise WoganError(f"wogan simulate (pid {self.process.pid}) ended before answering {label} "
                             f"(exit status {status})", status)
        try:
            answer = json.loads(answer_line)
        except ValueError:
            answer = None
        if (not isinstance(answer, dict) or answer.get("type") not in ("result", "error")
                or answer.get("line") != line_number):
            raise WoganError(f"wogan simulate answered {label} with garbage: {answer_line[:200]!r}")
        return answer

    def close(self, timeout: float = 10.0) -> Optional[int]:
        """Closes the child's input (it answers what it has read and exits), waits `timeout`
        seconds for it, then kills it; returns its exit status (negative: the signal that ended
        it)."""
        stdin, stdout = self.process.stdin, self.process.stdout
        if stdin is not None and not stdin.closed:
            try:
                stdin.close()
            except BrokenPipeError:
                pass
        try:
            self.process.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            log.warning("wogan simulate (pid %d) did not exit; killing it", self.process.pid)
            self.kill()
        if stdout is not None and not stdout.closed:
            stdout.close()
        return self.process.returncode

    def kill(self) -> None:
        """Kills the child at once and reaps it."""
        self.process.kill()
        self.process.wait()

    def __enter__(self) -> "Simulator":
        return self

    def __exit__(self, *exc_info: Any) -> None:
        self.close()
