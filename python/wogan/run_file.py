"""Run files (`wogan run --out`) and suites (`wogan suite`) read back: JSON lines, one record
each, read strictly, naming the line at fault."""

import json
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional


class RunFileError(ValueError):
    """A line of a run or suite file that cannot be read: the message names `path:line`."""


@dataclass
class Run:
    """A run: its `header`, its `tests` in order and its `summary` (None for a run cut short).
    A suite reads as a Run too: `header` is the suite's header line and `tests` its roads.
    `truncated`: the last line was cut short (a run killed while writing) and was dropped."""

    header: Optional[Dict[str, Any]] = None
    tests: List[Dict[str, Any]] = field(default_factory=list)
    summary: Optional[Dict[str, Any]] = None
    records: List[Dict[str, Any]] = field(default_factory=list)
    truncated: bool = False

    @property
    def failures(self) -> List[Dict[str, Any]]:
        """The failing tests (outcome FAIL)."""
        return [t for t in self.tests if (t.get("outcome") or t.get("recorded", {}).get("outcome")) == "FAIL"]


def read_run(path, allow_truncated: bool = True) -> Run:
    """Reads a run or a suite file line by line. Every record is kept in `records`; `test` (and a
    suite's `road`) records in `tests`. A last line without its newline that is not JSON is a
    write cut short: dropped with `truncated` set when `allow_truncated` (the default, as a run
    killed by a signal may leave one), else an error. Any other bad line is a RunFileError."""
    run = Run()
    with open(path, encoding="utf-8") as source:
        text = source.read()
    lines = text.split("\n")
    last_complete = text.endswith("\n")
    for number, line in enumerate(lines, 1):
        if not line.strip():
            continue
        is_last = number == len(lines)
        try:
            record = json.loads(line)
        except json.JSONDecodeError as error:
            if is_last and not last_complete and allow_truncated:
                run.truncated = True
                break
            cut = " (cut short: the file ends inside it)" if is_last and not last_complete else ""
            raise RunFileError(f"{path}:{number}: not JSON{cut}: {error}") from None
        if not isinstance(record, dict) or not isinstance(record.get("type"), str):
            raise RunFileError(f"{path}:{number}: not a record (an object with a \"type\")")
        kind = record["type"]
        if kind in ("header", "suite"):
            if run.header is not None:
                raise RunFileError(f"{path}:{number}: a second header")
            run.header = record
        elif kind in ("test", "road"):
            run.tests.append(record)
        elif kind == "summary":
            run.summary = record
        run.records.append(record)
    if run.header is None:
        raise RunFileError(f"{path}: no header line (not a run or suite file)")
    return run
