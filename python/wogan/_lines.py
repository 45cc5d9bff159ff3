"""The line loop both protocols share: JSON objects in on stdin, one per line; protocol lines out
on the real stdout, flushed; everything else a program prints goes to stderr."""

import contextlib
import json
import sys
from typing import Any, Dict, Iterator, TextIO


def write(out: TextIO, message: Dict[str, Any]) -> None:
    """Writes one protocol line and flushes it (NaN and infinities are refused: not JSON)."""
    out.write(json.dumps(message, allow_nan=False) + "\n")
    out.flush()


def messages(source: TextIO) -> Iterator[Dict[str, Any]]:
    """The JSON objects of `source`, one per line, until it ends; a line that is not an object is
    named on stderr and skipped (wogan writes only objects)."""
    for number, line in enumerate(source, 1):
        line = line.strip()
        if not line:
            continue
        try:
            message = json.loads(line)
        except json.JSONDecodeError as error:
            print(f"wogan client: input line {number} is not JSON: {error}", file=sys.stderr)
            continue
        if isinstance(message, dict):
            yield message


@contextlib.contextmanager
def protocol_stdout() -> Iterator[TextIO]:
    """The real stdout, kept for protocol lines, while `print` goes to stderr."""
    real = sys.stdout
    sys.stdout = sys.stderr
    try:
        yield real
    finally:
        sys.stdout = real
