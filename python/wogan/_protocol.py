"""What both protocols share: JSON objects in, one per line; protocol lines out, each flushed at
once; nothing else on the protocol's output.

When a class serves on the process's own standard output, that output is set aside for protocol
lines, and everything else written there goes to standard error from then on: `print`
(sys.stdout), and a library's native code writing to file descriptor 1 (pointed at standard
error).
"""

import contextlib
import json
import logging
import math
import numbers
import os
import signal
import sys
import threading
from typing import IO, Any, Callable, Dict, Iterator, Optional, Set, Tuple

log = logging.getLogger("wogan")

Point = Tuple[float, float]
Message = Dict[str, Any]


class Output:
    """Where protocol lines go: one JSON object per line, flushed; NaN and infinities are refused
    (they are not JSON). `closed` once the reader went away (a broken pipe)."""

    def __init__(self, stream: IO[str]) -> None:
        self.stream = stream
        self.closed = False

    def write(self, message: Message) -> bool:
        """Writes one line; False when the reader has gone away (nothing more can be said). A
        message that is not JSON (a NaN, an object of another kind) is a ValueError, and nothing
        is written."""
        text = line(message)
        if self.closed:
            return False
        try:
            self.stream.write(text)
            self.stream.flush()
        except BrokenPipeError:
            self.closed = True
            log.info("wogan closed the protocol's output; serving ends")
            return False
        return True


def line(message: Message) -> str:
    """`message` as one protocol line, its newline included; a ValueError when it is not JSON (a
    NaN, an object of another kind)."""
    try:
        return json.dumps(message, allow_nan=False) + "\n"
    except (TypeError, ValueError, RecursionError) as error:
        raise ValueError(f"the line cannot be written as JSON: {error}") from None


def sendable(message: Message) -> Message:
    """`message`, once it is known to make a protocol line (a ValueError says why not): an answer
    made in one process and written by another is checked where it is made."""
    line(message)
    return message


def messages(source: IO[Any], protocol: str) -> Iterator[Message]:
    """The JSON objects of `source` (text or bytes, UTF-8), one per line, until it ends. A line
    that is not a JSON object is named on stderr and passed over: wogan writes only objects."""
    for number, raw in enumerate(source, 1):
        try:
            line = raw.decode("utf-8") if isinstance(raw, bytes) else raw
            if not line.strip():
                continue
            message = json.loads(line)
        except (ValueError, RecursionError) as error:  # UnicodeDecodeError, JSONDecodeError: ValueErrors
            log.warning("%s: input line %d is not JSON, passed over: %s", protocol, number, error)
            continue
        if not isinstance(message, dict):
            log.warning("%s: input line %d is not a JSON object, passed over", protocol, number)
            continue
        yield message


class UnknownTypes:
    """Lines of a type this client does not know are passed over (a newer wogan may send more);
    each such type is named once on stderr."""

    def __init__(self, protocol: str) -> None:
        self.protocol = protocol
        self.seen: Set[str] = set()

    def note(self, message: Message) -> None:
        kind = str(message.get("type"))
        if kind not in self.seen:
            self.seen.add(kind)
            log.warning("%s: lines of type %r are not known to this client; passed over", self.protocol, kind)


def exchange(source: IO[Any], protocol: str, version: int,
             handlers: Dict[str, Callable[[Message], Optional[bool]]],
             on_hello: Callable[[Dict[str, Any]], Optional[bool]], oldest: Optional[int] = None) -> None:
    """Hands the JSON objects of `source` on by type until `bye` or the end of input: `hello` is
    checked against `protocol` and the versions this client serves (`oldest` to `version`; by
    default `version` alone) and its settings go to `on_hello`; a type in `handlers` goes to its
    handler. `on_hello` or a handler returns False to end the exchange (its reader gone); other
    types are passed over, each named once on stderr."""
    unknown = UnknownTypes(protocol)
    for message in messages(source, protocol):
        kind = message.get("type")
        if kind == "hello":
            check_hello(message, protocol, version, version if oldest is None else oldest)
            if on_hello(settings_of(message)) is False:
                return
        elif kind == "bye":
            return
        elif isinstance(kind, str) and kind in handlers:
            if handlers[kind](message) is False:
                return
        else:
            unknown.note(message)


def check_hello(message: Message, protocol: str, version: int, oldest: int) -> None:
    """Warns when `hello` names another protocol, or a version outside `oldest` to `version`."""
    said = message.get("version", version)
    served = isinstance(said, int) and not isinstance(said, bool) and oldest <= said <= version
    if message.get("protocol", protocol) != protocol or not served:
        versions = f"{version}" if oldest == version else f"{oldest} to {version}"
        log.warning("hello of protocol %r version %r; this client speaks %s version %s",
                    message.get("protocol"), message.get("version"), protocol, versions)


def settings_of(message: Message) -> Dict[str, Any]:
    """`hello`'s fields but its type."""
    return {key: value for key, value in message.items() if key != "type"}


def shown(value: Any, limit: int = 60) -> str:
    """`repr(value)` for a message, cut to about `limit` characters: a huge number or a long text
    stays readable (and an int past Python's digit limit for text does not fail)."""
    try:
        text = repr(value)
    except Exception:  # noqa: BLE001 - ValueError for an int past sys.get_int_max_str_digits()
        return f"<{type(value).__name__} too large to show>"
    if len(text) <= limit:
        return text
    return f"{text[:limit - 20]}...{text[-10:]} ({len(text)} characters)"


def _real(value: Any, name: str) -> None:
    """A ValueError naming `name` unless `value` is a real number (bool is not)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ValueError(f"{name}: {shown(value)} is not a finite number")


def number(value: Any, name: str) -> float:
    """`value` as a finite float; a ValueError names `name` otherwise: NaN, infinities, and real
    numbers beyond a float's range (an int of 400 digits, a huge Fraction), which JSON lines
    cannot carry either."""
    _real(value, name)
    try:
        result = float(value)
    except (OverflowError, ValueError):
        raise ValueError(f"{name}: {shown(value)} is not a finite number: beyond a float's range") from None
    if not math.isfinite(result):
        raise ValueError(f"{name}: {shown(value)} is not a finite number")
    return result


def clamped(value: Any, name: str, low: float, high: float) -> float:
    """`value` clamped into `[low, high]`, as a float: any finite real number, those beyond a
    float's range too (an int of 400 digits is clamped to `high`); a ValueError names `name` for
    NaN, infinities and what is not a number."""
    _real(value, name)
    try:
        result = float(value)
    except OverflowError:  # a finite number too large for a float: beyond either bound
        return high if value > 0 else low
    except ValueError:
        raise ValueError(f"{name}: {shown(value)} is not a finite number") from None
    if not math.isfinite(result):
        raise ValueError(f"{name}: {shown(value)} is not a finite number")
    return max(low, min(high, result))


def json_object(value: Any, name: str) -> None:
    """A ValueError naming `name` unless `value` is a dict that JSON lines carry as it is: text
    keys, no NaN or infinity, nothing JSON has no form for, no cycle."""
    if not isinstance(value, dict):
        raise ValueError(f"{name}: {type(value).__name__} is not a dict")
    try:
        json.dumps(value, allow_nan=False)
    except (TypeError, ValueError, RecursionError) as error:
        raise ValueError(f"{name}: not JSON: {error}") from None


def point(value: Any, name: str) -> Point:
    """`[x, y]` (any pair of finite numbers, an iterator too) as a tuple of floats; a ValueError
    names `name`."""
    try:
        x, y = value
    except (TypeError, ValueError):
        raise ValueError(f"{name}: {shown(value)} is not a point [x, y]") from None
    return number(x, f"{name}: x"), number(y, f"{name}: y")


@contextlib.contextmanager
def session(source: Optional[IO[Any]], sink: Optional[IO[str]]) -> Iterator[Tuple[IO[Any], Output]]:
    """The input and the protocol's output of one `serve()`. Streams given are used as they are.
    By default: standard input, and standard output kept for protocol lines alone, sys.stdout and
    file descriptor 1 pointing at standard error from then on; while serving, a SIGTERM ends it as
    `SystemExit(143)` (so that `finally` clauses and `close()` run) unless the program has its own
    handler."""
    lines: IO[Any] = getattr(sys.stdin, "buffer", sys.stdin) if source is None else source
    with contextlib.ExitStack() as stack:
        if sink is None:
            sink = stack.enter_context(_stdout_for_protocol())
            stack.enter_context(_sigterm_as_exit())
        yield lines, Output(sink)


@contextlib.contextmanager
def _stdout_for_protocol() -> Iterator[IO[str]]:
    """The process's standard output for protocol lines alone. sys.stdout becomes sys.stderr, and
    (when both are files) descriptor 1 is pointed at standard error too, the protocol keeping a
    private copy of it: native code writing to stdout (a simulator's C++) cannot reach wogan
    either. This lasts after serving: the protocol's output is then closed (the exchange is over),
    and what is written to stdout later (say, a library printing at exit) still goes to stderr."""
    real = sys.stdout
    try:
        fd, err_fd = real.fileno(), sys.stderr.fileno()
    except (AttributeError, OSError, ValueError):  # not files (a test's capture): Python level only
        fd = err_fd = -1
    real.flush()
    sys.stdout = sys.stderr
    if fd < 0:
        yield real
        return
    protocol = os.fdopen(os.dup(fd), "w", encoding="utf-8", newline="\n", closefd=True)
    os.dup2(err_fd, fd)
    try:
        yield protocol
    finally:
        with contextlib.suppress(OSError):
            protocol.close()


def _on_sigterm(signum: int, frame: Any) -> None:
    raise SystemExit(128 + signum)


@contextlib.contextmanager
def _sigterm_as_exit() -> Iterator[None]:
    if threading.current_thread() is not threading.main_thread() \
            or signal.getsignal(signal.SIGTERM) is not signal.SIG_DFL:
        yield
        return
    signal.signal(signal.SIGTERM, _on_sigterm)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
