"""Run files (`wogan run --out`) and suites (`wogan suite add`) read back: JSON lines, one record
each, read line by line and strictly, every error naming `path:line` (docs/reference.md,
"Records" and "wogan suite").

    run = wogan.read_run("run.jsonl")
    run.header["seed"], len(run.tests), run.summary["failed"]
"""

import json
import math
import os
from dataclasses import dataclass, field
from typing import IO, Any, Dict, List, Optional, Union

Record = Dict[str, Any]
PathLike = Union[str, "os.PathLike[str]"]

# The longest line read, in bytes (its newline not counted): the binary's bound on the lines it
# reads. A longer line is a RunFileError, found without holding more than this in memory.
MAX_LINE_BYTES = 16 * 1024 * 1024
# A line is read a piece of this many bytes at a time.
_PIECE_BYTES = 1024 * 1024
# The longest integer read, in characters: longer ones are beyond a float's range, which the
# binary's JSON reader refuses (checked before converting: a long digit string costs time).
_MAX_INT_CHARACTERS = 400

# The record types that open a file, and the ones read into `tests`, per kind of file.
_HEADERS = {"header": "run", "suite": "suite"}
_TESTS = {"run": "test", "suite": "road"}


class RunFileError(ValueError):
    """A run or suite file that cannot be read: the message names `path:line` and the fault."""


class _LineTooLong(Exception):
    """A line longer than MAX_LINE_BYTES."""


def _line(source: IO[bytes]) -> Optional[bytes]:
    """The next line of `source` and its newline, None at the end, read a piece at a time:
    _LineTooLong once a line is found longer than MAX_LINE_BYTES (no more of it is read)."""
    pieces: List[bytes] = []
    held = 0
    while True:
        piece = source.readline(min(_PIECE_BYTES, MAX_LINE_BYTES + 1 - held))
        if not piece:
            break
        pieces.append(piece)
        held += len(piece)
        if piece.endswith(b"\n"):
            break
        if held > MAX_LINE_BYTES:
            raise _LineTooLong()
    if len(pieces) > 1:
        return b"".join(pieces)
    return pieces[0] if pieces else None


def _not_json(token: str) -> Any:
    raise ValueError(f"{token} is not JSON (a number must be finite)")


def _finite_float(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise ValueError(f"the number {_cut(text)} is beyond a float's range")
    return value


def _float_sized_int(text: str) -> int:
    if len(text) <= _MAX_INT_CHARACTERS:
        value = int(text)
        try:
            float(value)
            return value
        except OverflowError:
            pass
    raise ValueError(f"the number {_cut(text)} is beyond a float's range")


def _cut(text: str) -> str:
    return text if len(text) <= 40 else f"{text[:30]}... ({len(text)} characters)"


def _record_of(text: str) -> Any:
    """The JSON value of one line, read as the binary reads it: NaN, Infinity and numbers beyond
    a float's range (1e400) are not JSON (ValueError); nesting too deep is a RecursionError."""
    return json.loads(text, parse_constant=_not_json, parse_float=_finite_float, parse_int=_float_sized_int)


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
    A line that is not UTF-8 JSON (NaN, Infinity and numbers beyond a float's range such as 1e400
    are not: the binary refuses them too), one nested too deeply, one longer than
    `MAX_LINE_BYTES` (16 MiB), a record that is not an object with a `"type"`, a second header, a
    run's `road` or a suite's `test` each raise RunFileError naming `path:line`; blank lines are
    passed over. A run without a summary is read (`summary` None).

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
        number = 0
        while True:
            number += 1
            at = f"{name}:{number}"
            try:
                raw = _line(source)
            except _LineTooLong:
                raise RunFileError(f"{at}: a line longer than {MAX_LINE_BYTES} bytes (16 MiB), the longest "
                                   "a run or suite file may hold") from None
            if raw is None:
                break
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
                record = _record_of(text)
            except RecursionError:
                raise RunFileError(f"{at}: not JSON: nested too deeply to read") from None
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
