"""Running the installed `wogan` binary from Python."""

import os
import shutil
import subprocess
import sys
import sysconfig
import tempfile
from typing import Iterable, Optional, Sequence

from .run_file import Run, read_run


class WoganError(RuntimeError):
    """The binary ended with an exit status the caller did not accept; the message carries its
    stderr's last lines."""

    def __init__(self, status: int, stderr: str) -> None:
        tail = "\n".join(stderr.strip().splitlines()[-20:])
        super().__init__(f"wogan exited with status {status}: {tail}")
        self.status = status
        self.stderr = stderr


def binary() -> str:
    """The `wogan` binary: $WOGAN_BIN, else the one installed beside this Python (where the wheel
    puts it), else the first on PATH."""
    given = os.environ.get("WOGAN_BIN")
    if given:
        return given
    beside = os.path.join(sysconfig.get_path("scripts"), "wogan")
    if os.access(beside, os.X_OK):
        return beside
    found = shutil.which("wogan")
    if found:
        return found
    raise FileNotFoundError("no wogan binary: pip install wogan, or set WOGAN_BIN")


def run(args: Sequence[str], *, out: Optional[str] = None, ok_statuses: Iterable[int] = (0,),
        timeout: Optional[float] = None) -> Run:
    """Runs `wogan run ARGS` and reads the run it wrote. Without `--out` in `args` (nor `out`) the
    run goes to a temporary file. An exit status outside `ok_statuses` raises WoganError (give
    (0, 1) for `--fail-on failure`, whose 1 is a verdict)."""
    args = list(args)
    if args and args[0] == "run":
        args = args[1:]
    scratch = None
    if "--out" not in args:
        if out is None:
            scratch = tempfile.TemporaryDirectory(prefix="wogan-")
            out = os.path.join(scratch.name, "run.jsonl")
        args += ["--out", out]
    else:
        out = args[args.index("--out") + 1]
    try:
        done = subprocess.run([binary(), "run", *args], capture_output=True, text=True, timeout=timeout)
        if done.returncode not in tuple(ok_statuses):
            raise WoganError(done.returncode, done.stderr)
        sys.stderr.write(done.stderr)
        return read_run(out)
    finally:
        if scratch is not None:
            scratch.cleanup()
