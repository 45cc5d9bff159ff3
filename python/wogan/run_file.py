"""Run files (`wogan run --out`) and suites (`wogan suite add`) read back: JSON lines, one record
each, read line by line and strictly, every error naming `path:line` (docs/reference.md,
"Records" and "wogan suite").

    run = wogan.read_run("run.jsonl")
    run.header["seed"], len(run.tests), run.summary["failed"]
"""

import json
import os
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Union

Record = Dict[str, Any]
PathLike = Union[str, "os.PathLike[str]"]

# The record types that open a file, and the ones read into `tests`, per kind of file.
_HEADERS = {"header": "run", "suite": "suite"}
_TESTS = {"run": "test", "suite": "road"}


class RunFileError(ValueError):
    """A run or suite file that cannot be read: the message names `path:line` and the fault."""


@dataclass
class Run:
    """A run or a suite, read.

    - `kind`: "run" (a `wogan run` file) or "suite" (a `wogan suite` file).
    - `header`: the first record (a run's `header`: `version`, `seed`, `oracle`, `config`, ...; a
      suite's `{"type": "suite", "format": "wogan-suite", "version": 1}`).
    - `tests`: a run's `test` records, in order (those marked `beyond_budget` included, as
      written); a suite's `road` records (`name`, `road_points`, `recorded`, `origin`).
    - `summary`: a run's `summary` record; None for a suite, and for a run cut short (killed, or
      still being written).
    - `records`: every record, in order (a run's `train` records too, and any of a kind this
      reader does not know).
    - `truncated`: the file's last line was cut short (a run killed while writing it) and was
      dropped.
    - `path`: where it was read from; `status`: the exit status of the binary, for a run that
      `wogan.run` made, else None.
    """

    kind: str
    header: Record
    tests: List[Record] = field(default_factory=list)
    summary: Optional[Record] = None
    records: List[Record] = field(default_factory=list)
    truncated: bool = False
    path: Optional[str] = None
    status: Optional[int] = None

    @property
    def failures(self) -> List[Record]:
        """The failing tests: a run's tests whose outcome is FAIL (those beyond an SBST budget
        left out, as the summary's `failed` leaves them), a suite's roads recorded as FAIL."""
        if self.kind == "suite":
            return [r for r in self.tests if (r.get("recorded") or {}).get("outcome") == "FAIL"]
        return [t for t in self.tests if t.get("outcome") == "FAIL" and not t.get("beyond_budget")]


def read_run(path: PathLike, allow_truncated: bool = True) -> Run:
    """Reads the run or suite file at `path`, line by line.

    The first record must be a header (`"type": "header"` for a run, `"suite"` for a suite).
    A line that is not UTF-8 JSON, a record that is not an object with a `"type"`, a second
    header, a run's `road` or a suite's `test` each raise RunFileError naming `path:line`; blank
    lines are passed over. A run without a summary is read (`summary` None).

    The last line of a run killed while writing it (or read while wogan still writes) is cut
    short: no newline, not JSON. With `allow_truncated` (the default: a killed run is common and
    its whole records are sound) it is dropped and `truncated` is set; with
    `allow_truncated=False` it is a RunFileError naming its line. Any other bad line is an error
    either way.
    """
    name = os.fspath(path)
    run: Optional[Run] = None
    truncated = False
    with open(name, "rb") as source:
        for number, raw in enumerate(source, 1):
            at = f"{name}:{number}"
            cut = not raw.endswith(b"\n")  # only the last line can lack its newline
            try:
                text = raw.decode("utf-8")
            except UnicodeDecodeError as error:
                if cut and allow_truncated:  # cut inside a character
                    truncated = True
                    break
                raise RunFileError(f"{at}: not UTF-8 text: {error}") from None
            if not text.strip():
                continue
            try:
                record = json.loads(text)
            except ValueError as error:
                if cut and allow_truncated:
                    truncated = True
                    break
                why = " (the file ends inside it: a run cut short?)" if cut else ""
                raise RunFileError(f"{at}: not JSON{why}: {error}") from None
            if not isinstance(record, dict) or not isinstance(record.get("type"), str):
                raise RunFileError(f"{at}: not a record (a JSON object with a \"type\")")
            kind = record["type"]
            if run is None:
                if kind not in _HEADERS:
                    raise RunFileError(f"{at}: not a run or suite file: its first record is a {kind!r}, "
                                       "not a header")
                run = Run(kind=_HEADERS[kind], header=record, path=name)
            elif kind in _HEADERS:
                raise RunFileError(f"{at}: a second header (a {kind!r} record)")
            elif kind == _TESTS[run.kind]:
                run.tests.append(record)
            elif kind in _TESTS.values():
                raise RunFileError(f"{at}: a {kind!r} record in a {run.kind} file")
            elif kind == "summary" and run.kind == "run":
                run.summary = record
            run.records.append(record)
    if run is None:
        what = "its only line is cut short" if truncated else "empty"
        raise RunFileError(f"{name}: {what}: not a run or suite file")
    run.truncated = truncated
    return run
