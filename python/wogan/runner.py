"""Running the `wogan` binary from Python: `run` (a search, read back) and `find_binary`.

    run = wogan.run(["--max-tests", "50", "--seed", "1"])
    print(run.summary["failed"], "of", len(run.tests), "failed")
"""

import collections
import os
import shutil
import signal
import subprocess
import sys
import sysconfig
import tempfile
import threading
from typing import IO, Deque, Iterable, List, Optional, Sequence, Tuple

from .run_file import PathLike, Run, read_run

# The stderr lines a WoganError keeps.
STDERR_TAIL_LINES = 40
# How long a run told to stop (SIGTERM) has to write its summary before it is killed.
STOP_GRACE_S = 10.0


class WoganError(RuntimeError):
    """The binary failed: it ended with an exit status the caller did not accept, it ended before
    answering (`wogan simulate`), or it answered something that is not an answer. `status` (None
    when it was still running) and `stderr` (its last lines, or "") say more."""

    def __init__(self, message: str, status: Optional[int] = None, stderr: str = "") -> None:
        super().__init__(message)
        self.status = status
        self.stderr = stderr


def find_binary() -> str:
    """The `wogan` binary: `$WOGAN_BIN` when set; else the one installed beside this Python (its
    scripts folder, where `pip install` of the wheel puts it); else the first `wogan` on PATH.
    FileNotFoundError when there is none."""
    given = os.environ.get("WOGAN_BIN")
    if given:
        if not (os.path.isfile(given) and os.access(given, os.X_OK)):
            raise FileNotFoundError(f"WOGAN_BIN={given}: not an executable file")
        return given
    beside = os.path.join(sysconfig.get_path("scripts"), "wogan")
    if os.path.isfile(beside) and os.access(beside, os.X_OK):
        return beside
    found = shutil.which("wogan")
    if found:
        return found
    raise FileNotFoundError("no wogan binary: `pip install .` in wogan's checkout installs one "
                            "(or set WOGAN_BIN to its path)")


def _out_of(args: List[str]) -> Optional[str]:
    """The `--out` that `args` gives, if any (`--out FILE` or `--out=FILE`)."""
    for i, arg in enumerate(args):
        if arg == "--out" and i + 1 < len(args):
            return args[i + 1]
        if arg.startswith("--out="):
            return arg[len("--out="):]
    return None


def run(args: Sequence[str], *, out: Optional[PathLike] = None, binary: Optional[PathLike] = None,
        check: bool = True, ok_statuses: Iterable[int] = (0,), timeout: Optional[float] = None) -> Run:
    """Runs `wogan run ARGS` and returns its run file read by `read_run` (with `.status`, the
    exit status).

    - `args`: the options of `wogan run` (a leading "run" is allowed).
    - `out`: where the run file goes. Without it (and without `--out` in `args`) the run goes to a
      temporary file, removed once read.
    - `binary`: the binary to run; by default `find_binary()` (`$WOGAN_BIN`, the one installed
      beside this Python, PATH).
    - `check`, `ok_statuses`: an exit status outside `ok_statuses` raises WoganError with the
      status and the binary's last stderr lines (`check=False`: any status is accepted when the
      run file can be read). `wogan run --fail-on failure` exits 1 on a failing road: a verdict,
      not an error; give `ok_statuses=(0, 1)` to read that run. 130 is a run stopped by Ctrl-C
      or SIGTERM (its summary says `interrupted`).
    - `timeout`: seconds; past it the run is stopped (SIGTERM, then SIGKILL) and
      subprocess.TimeoutExpired is raised. A budget is better given to wogan (`--budget 10m`).

    The binary's stderr is passed on to this process's stderr as it comes (`--quiet` in `args`
    quiets its progress).
    """
    args = [os.fspath(a) for a in args]
    if args[:1] == ["run"]:
        args = args[1:]
    given = _out_of(args)
    if given is not None and out is not None:
        raise ValueError(f"out={os.fspath(out)!r} and --out {given} in args: give one")
    scratch: Optional[tempfile.TemporaryDirectory] = None  # type: ignore[type-arg]
    if given is not None:
        path = given
    elif out is not None:
        path = os.fspath(out)
        args += ["--out", path]
    else:
        scratch = tempfile.TemporaryDirectory(prefix="wogan-run-")
        path = os.path.join(scratch.name, "run.jsonl")
        args += ["--out", path]
    command = [os.fspath(binary) if binary is not None else find_binary(), "run", *args]
    try:
        status, tail = _run(command, timeout)
        accepted = not check or status in tuple(ok_statuses)
        if not accepted:
            raise WoganError(f"wogan run exited with status {status}:\n{tail}".rstrip(), status, tail)
        try:
            result = read_run(path)
        except FileNotFoundError:
            raise WoganError(f"wogan run exited with status {status} and wrote no run file:\n{tail}".rstrip(),
                             status, tail) from None
        result.status = status
        return result
    finally:
        if scratch is not None:
            scratch.cleanup()


def _run(command: List[str], timeout: Optional[float]) -> Tuple[int, str]:
    """Runs `command`, its stderr passed on and its last lines kept; (exit status, those lines)."""
    tail: Deque[str] = collections.deque(maxlen=STDERR_TAIL_LINES)
    process = subprocess.Popen(command, stdin=subprocess.DEVNULL, stderr=subprocess.PIPE)
    assert process.stderr is not None
    reader = threading.Thread(target=_pass_on, args=(process.stderr, tail), daemon=True)
    reader.start()
    try:
        status = process.wait(timeout=timeout)
    except BaseException:  # a timeout, Ctrl-C: the run is stopped, not left behind
        _stop(process)
        raise
    finally:
        reader.join(timeout=5.0)
    return status, "".join(tail)


def _pass_on(stream: IO[bytes], tail: Deque[str]) -> None:
    for raw in stream:
        line = raw.decode("utf-8", errors="replace")
        tail.append(line)
        try:
            sys.stderr.write(line)
            sys.stderr.flush()
        except (OSError, ValueError):  # this process's stderr is gone: keep the tail only
            pass


def _stop(process: "subprocess.Popen[bytes]") -> None:
    if process.poll() is not None:
        return
    process.send_signal(signal.SIGTERM)
    try:
        process.wait(timeout=STOP_GRACE_S)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()
