"""One search, many machines: a `wogan.Executor` served as a pool of Ray actors.

    python -m wogan.ray --address ADDRESS --actors N FILE.py:CLASS

is an executor for `wogan run --executor cmd:"..."` (the executor protocol, version 3, in wogan's
docs/reference.md) that drives each road on one of N Ray actors, each holding one long-lived
instance of CLASS, the `wogan.Executor` subclass defined in FILE.py (its own `serve()` call under
`if __name__ == "__main__"`), so that the simulators of one search run on every machine of a Ray
cluster. For example, 32 MetaDrive simulators on a cluster already started with `ray start`:

    wogan run --jobs 32 --executor "cmd:python -m wogan.ray --address auto --actors 32 \\
        --init '{\\"policy\\": \\"idm\\", \\"wall_timeout_s\\": 300}' examples/metadrive/executor.py:MetaDriveExecutor"

At wogan's `hello` it connects to Ray (`ray.init(address=ADDRESS)`; `local` starts a private
single-node Ray on this machine, stopped at the end), starts the N actors spread over the nodes,
each of which loads FILE.py by its path (the file, and what it imports, must be at that path on
every node, as must Ray, wogan and the simulator), makes `CLASS(**INIT)` and calls its
`hello(settings)` hook; then it replies to `hello` with `roads_at_once` N and the executor's
description (CLASS's name, version and settings, with `ray`: the address, the actors, the nodes
they are on). wogan then keeps up to N roads in flight to this one process; each goes to a free
actor, and each answer is written as soon as it is known, in any order.

Faults: an exception in `drive` answers that road ERROR with its message, in the actor, as
`wogan.Executor.serve()` does (one function answers for both). An actor that dies, or whose node
is lost, has its road driven again by another actor, once; a road lost twice is answered ERROR
with the reason. A lost actor is replaced (a new actor, told `hello`), so the pool stays at N
while the cluster can hold it. A FILE.py:CLASS that cannot be loaded or made, or a `hello` hook
that raises, is named on stderr before any road, and the process exits with status 1 without a
reply to `hello` (wogan shows the message). `bye` (once the roads in flight are answered, as
`serve()` answers each road before it reads `bye`), the end of input, SIGTERM and Ctrl-C kill the
actors (after asking each to `close()` its executor, briefly) and disconnect from Ray; nothing is
left behind, not even when this process is killed outright: Ray ends the actors of a driver that
is gone, and a reaper process kills what is left of a `local` Ray.

Standard output carries protocol lines alone (Ray's own output, and the actors' prints that Ray
forwards, go to stderr).
"""

import argparse
import collections
import importlib.util
import json
import logging
import os
import queue
import re
import signal
import socket
import subprocess
import sys
import threading
import time
import traceback
from dataclasses import dataclass, field
from typing import Any, Deque, Dict, List, Optional, Sequence, Set

from . import _protocol
from .executor import OLDEST_VERSION, PROTOCOL, VERSION, Executor, replies_to, road_number

try:
    import ray
    from ray.exceptions import RayError, RayTaskError
except ImportError:  # the `ray` extra is not installed: main() says so
    ray = None

log = logging.getLogger("wogan.ray")

# The most roads one executor may take at once (the protocol's bound on `roads_at_once`).
MAX_ACTORS = 1024
# How often a road is driven when its actor is lost: once more, by another actor.
DRIVES_PER_ROAD = 2
# How long the actors have to close their executors when the pool ends, seconds.
CLOSE_WAIT_S = 2.0
# How often the wait for the actors to start says how far it got, seconds.
PROGRESS_EVERY_S = 15.0
# The Ray namespace of the pool's actors (each is named `wogan-HOST-PID-K` in it).
NAMESPACE = "wogan"


# The private Ray of `--address local` is this process's children (and theirs). Ray ties them to
# this process, but not all of them, nor at once: this small program, started first in a session
# of its own, notes them every second and kills what is left of them when this process ends,
# however it ends (its input, a pipe from this process, then reaches its end).
_REAPER = r"""
import os, select, signal, sys

def table():
    found = {}
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open(f"/proc/{pid}/stat") as f:
                stat = f.read()
        except OSError:
            continue
        rest = stat[stat.rindex(")") + 2:].split()
        found[int(pid)] = (int(rest[1]), rest[19])  # parent, start time
    return found

def below(roots, processes):
    found, more = {}, list(roots)
    while more:
        pid = more.pop()
        for child, (parent, started) in processes.items():
            if parent == pid and child not in found and child != os.getpid():
                found[child] = started
                more.append(child)
    return found

watched, known = int(sys.argv[1]), {}
while True:
    ready, _, _ = select.select([sys.stdin], [], [], 1.0)
    if ready and not os.read(sys.stdin.fileno(), 4096):
        break
    known.update(below([watched], table()))
for _ in range(3):
    processes = table()
    alive = [pid for pid, started in known.items() if processes.get(pid, (0, None))[1] == started]
    known.update(below(alive, processes))
    for pid in alive:
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:
            pass
"""


class StartError(Exception):
    """The pool could not be started (the message says why); nothing was replied to `hello`."""


@dataclass(frozen=True)
class ExecutorSpec:
    """`FILE.py:CLASS` of the command line: the file's absolute path and the class's name."""

    path: str
    class_name: str

    @classmethod
    def parse(cls, text: str) -> "ExecutorSpec":
        """`FILE.py:CLASS`; a ValueError says what is wrong with it."""
        path, colon, name = text.rpartition(":")
        if not colon or not path or not name:
            raise ValueError(f"{text!r} is not FILE.py:CLASS (the file defining the wogan.Executor subclass, "
                             "and the class's name)")
        if not name.isidentifier():
            raise ValueError(f"{text!r}: {name!r} is not a class name")
        return cls(os.path.abspath(path), name)

    def __str__(self) -> str:
        return f"{self.path}:{self.class_name}"


def load_executor_class(spec: ExecutorSpec) -> type:
    """The `wogan.Executor` subclass `spec` names, its file loaded as a module of its own (not
    `__main__`, so its `serve()` call is not reached), its folder first on `sys.path` as for
    `python FILE.py` (its own modules found beside it). A ValueError names the file and what is
    wrong: no such file, an import that failed, no such class, not a wogan.Executor subclass."""
    if not os.path.isfile(spec.path):
        raise ValueError(f"{spec.path}: no such file (it must be at this path on every Ray node)")
    folder = os.path.dirname(spec.path)
    if folder not in sys.path:
        sys.path.insert(0, folder)
    module_name = "_wogan_ray_" + re.sub(r"\W", "_", os.path.splitext(os.path.basename(spec.path))[0])
    module_spec = importlib.util.spec_from_file_location(module_name, spec.path)
    if module_spec is None or module_spec.loader is None:
        raise ValueError(f"{spec.path}: not a Python file that can be loaded")
    module = importlib.util.module_from_spec(module_spec)
    sys.modules[module_name] = module
    try:
        module_spec.loader.exec_module(module)
    except BaseException as error:  # SystemExit too: a file that ends the program when loaded
        del sys.modules[module_name]
        raise ValueError(f"{spec.path}: loading it failed: {type(error).__name__}: {error}") from error
    found = getattr(module, spec.class_name, None)
    if found is None:
        raise ValueError(f"{spec.path}: no {spec.class_name} in it")
    if not isinstance(found, type) or not issubclass(found, Executor):
        raise ValueError(f"{spec}: not a wogan.Executor subclass ({type(found).__name__} "
                         f"{getattr(found, '__qualname__', spec.class_name)})")
    return found


class PoolActor:
    """One actor of the pool (a Ray actor class once `ray.remote` wraps it): one long-lived
    instance of the executor class, made and told `hello` once, driving one road at a time."""

    def __init__(self) -> None:
        self.executor: Optional[Executor] = None

    def setup(self, spec: ExecutorSpec, init: Dict[str, Any], settings: Dict[str, Any],
              log_level: str) -> Dict[str, Any]:
        """Loads and makes the executor, calls its `hello(settings)` hook; returns its description
        and where the actor runs. A ValueError says what failed (an exception from the class's
        constructor or hook is raised as it is, its traceback in the actor's log)."""
        logging.basicConfig(level=log_level, format="%(name)s: %(message)s", stream=sys.stderr)
        where = f"on node {ray.util.get_node_ip_address()}"
        try:
            executor_class = load_executor_class(spec)
        except ValueError as error:
            raise ValueError(f"{error} ({where})") from None
        try:
            executor = executor_class(**init)
        except TypeError as error:
            raise ValueError(f"{spec.class_name}(**{json.dumps(init)}) cannot be made ({where}): {error}; "
                             "give its arguments with --init '{\"name\": value, ...}'") from None
        executor._ready(settings)
        description = executor._description()
        self.executor = executor
        return {"description": description, "node": ray.get_runtime_context().get_node_id(),
                "ip": ray.util.get_node_ip_address(), "pid": os.getpid()}

    def drive(self, message: Dict[str, Any]) -> Optional[Dict[str, Any]]:
        """The answer line to one `road` line, as `wogan.Executor.serve()` answers it."""
        assert self.executor is not None, "setup() first"
        return self.executor._answer_to(message)

    def close(self) -> None:
        """The executor's `close()` hook: the pool is ending."""
        if self.executor is not None:
            self.executor.close()
            self.executor = None


@dataclass
class _Member:
    """An actor of the pool: its handle and, once started, where it runs."""

    handle: Any
    name: str
    node: str = ""
    ip: str = ""


@dataclass
class _Road:
    """A road wogan sent: its line, its number, and how often it was driven."""

    id: int
    message: Dict[str, Any]
    drives: int = 0
    reasons: List[str] = field(default_factory=list)
    lost_on: Set[str] = field(default_factory=set)  # the nodes where it lost its actor


def one_line(error: BaseException, limit: int = 1500) -> str:
    """An exception's message as one line (Ray's are several), cut to about `limit` characters."""
    text = " ".join(part.strip() for part in str(error).splitlines() if part.strip())
    return text if len(text) <= limit else text[:limit - 3] + "..."


class Pool:
    """The driver's side of `python -m wogan.ray`: the actors, the roads waiting for one, the
    roads in flight. `hello(settings)` starts the actors and returns the reply to `hello`;
    `submit(message)` takes a `road` line; answers are written to the protocol's output by the
    pool's own thread as they come; `close()` ends it all. Every Ray call after `hello` is made
    on that thread, which alone holds the pool's state: the others hand it events."""

    def __init__(self, spec: ExecutorSpec, actors: int, address: str, actor_cpus: float,
                 init: Dict[str, Any], env: Dict[str, str], log_level: str) -> None:
        self.spec, self.wanted, self.address = spec, actors, address
        self.actor_cpus, self.init, self.env, self.log_level = actor_cpus, init, env, log_level
        self.out: Optional[_protocol.Output] = None
        self.settings: Dict[str, Any] = {}
        self.members: Dict[str, _Member] = {}  # by the actor's name
        self.idle: Deque[_Member] = collections.deque()
        self.waiting: Deque[_Road] = collections.deque()
        self.in_flight: Dict[int, _Road] = {}
        self.starting = 0
        self.failed_starts = 0  # replacements that failed since the last that started
        self.started_actors = 0
        self.events: "queue.Queue[tuple]" = queue.Queue()
        self.thread: Optional[threading.Thread] = None
        self.connected = False
        self.gone = False  # wogan stopped reading our output
        self.crashed: Optional[BaseException] = None
        self.actor_class: Any = None
        self.reaper: Optional[subprocess.Popen] = None
        self.drained = threading.Event()
        self.draining = False

    # --- the main thread's side ---------------------------------------------------------------

    def hello(self, settings: Dict[str, Any]) -> Optional[Dict[str, Any]]:
        """Connects to Ray and starts the actors, each told `hello`; returns the reply to
        `hello` (None for a `hello` that gets none). A StartError says why the pool could not
        start."""
        if self.connected:
            log.warning("a second hello: passed over (the actors keep the first one's settings)")
            return None
        self.settings = settings
        # wogan's own package goes with the job (Ray's py_modules): the actors import this very
        # version of it, installed on the nodes or not.
        runtime_env: Dict[str, Any] = {"py_modules": [os.path.dirname(os.path.abspath(__file__))]}
        if self.env:
            runtime_env["env_vars"] = dict(self.env)
        # A private Ray (`local`) is this machine's alone: on loopback, not on the network, and
        # its processes end with this one.
        private = {"_node_ip_address": "127.0.0.1"} if self.address == "local" else {}
        if self.address == "local" and os.path.isdir("/proc"):
            self.reaper = subprocess.Popen([sys.executable, "-c", _REAPER, str(os.getpid())], stdin=subprocess.PIPE,
                                           stdout=subprocess.DEVNULL, start_new_session=True)
        own_sigterm = signal.getsignal(signal.SIGTERM) if threading.current_thread() is threading.main_thread() \
            else None
        try:
            ray.init(address=self.address, namespace=NAMESPACE, runtime_env=runtime_env, log_to_driver=True,
                     **private)
        except Exception as error:  # ConnectionError, ValueError, RuntimeError...: Ray says which
            raise StartError(f"Ray at --address {self.address}: {type(error).__name__}: {one_line(error)}") from None
        finally:
            # ray.init sets a SIGTERM handler of its own (exit status 15, no clean end): ours again.
            if own_sigterm is not None:
                signal.signal(signal.SIGTERM, own_sigterm)
        self.connected = True
        self._check_room()
        self.actor_class = ray.remote(PoolActor)
        pending = {}
        for _ in range(self.wanted):
            member = self._new_member()
            pending[self._setup(member)] = member
        last_said = time.monotonic()
        first: Optional[Dict[str, Any]] = None
        while pending:
            done, _ = ray.wait(list(pending), num_returns=1, timeout=PROGRESS_EVERY_S)
            if not done:
                last_said = time.monotonic()
                log.info("%d of %d actors ready; waiting for Ray to place the others (%s)",
                         self.wanted - len(pending), self.wanted, self._resources())
                continue
            member = pending.pop(done[0])
            try:
                started = ray.get(done[0])
            except RayTaskError as error:
                log.error("%s", error)  # the actor's traceback
                raise StartError(f"{self.spec}: an actor could not start: {self._cause(error)}") from None
            except RayError as error:
                raise StartError(f"{self.spec}: an actor was lost while starting: {one_line(error)}") from None
            self._joined(member, started)
            first = first or started
            if time.monotonic() - last_said > PROGRESS_EVERY_S:
                last_said = time.monotonic()
                log.info("%d of %d actors ready", self.wanted - len(pending), self.wanted)
        assert first is not None
        nodes = sorted({m.ip + " " + m.node[:8] for m in self.members.values()})
        log.info("%d actors of %s ready on %d Ray node(s): %s", self.wanted, self.spec.class_name, len(nodes),
                 ", ".join(nodes))
        self.thread = threading.Thread(target=self._run, name="wogan.ray pool", daemon=True)
        self.thread.start()
        if not replies_to(settings):
            return None
        description = dict(first["description"])
        own = description.get("settings")
        if own is not None and "ray" in own:
            log.warning("the executor's own setting 'ray' is replaced by the pool's in the reply to hello")
        description["settings"] = {**(own or {}), "ray": {
            "address": self.address, "actors": self.wanted, "actor_cpus": self.actor_cpus,
            "nodes": len({m.node for m in self.members.values()})}}
        return {"type": "hello", "protocol": PROTOCOL, "version": VERSION, "roads_at_once": self.wanted,
                "executor": description}

    def submit(self, message: Dict[str, Any]) -> bool:
        """Takes one `road` line (answered later, by the pool's thread); False once wogan stopped
        reading the answers, or the pool failed."""
        if self.gone or self.crashed is not None:
            return False
        road_id = road_number(message)
        if road_id is None:
            log.error("%s: a road without a road number cannot be answered: id %r", PROTOCOL, message.get("id"))
            return True
        if self.thread is None:
            log.error("road %d: sent before hello; not answered", road_id)
            return True
        self.events.put(("road", _Road(road_id, message)))
        return True

    def drain(self) -> None:
        """After `bye`: waits until every road taken is answered (as `serve()` answers each road
        before it reads `bye`); Ctrl-C or SIGTERM cut it short."""
        if self.thread is None or self.crashed is not None:
            return
        self.events.put(("drain",))
        while not self.drained.wait(timeout=0.5):
            if self.crashed is not None or self.thread is None or not self.thread.is_alive():
                return

    def close(self) -> None:
        """Ends the pool: the pool's thread stopped, each actor asked to close its executor
        (briefly), then killed; disconnected from Ray (a `local` Ray stopped)."""
        try:
            self._close()
        finally:
            if self.reaper is not None:  # what is left of a `local` Ray: killed
                self.reaper.stdin.close()
                try:
                    self.reaper.wait(timeout=30)
                except subprocess.TimeoutExpired:
                    self.reaper.kill()
                self.reaper = None

    def _close(self) -> None:
        if self.thread is not None:
            self.events.put(("stop",))
            self.thread.join(timeout=5.0)
            self.thread = None
        if not self.connected:
            return
        members = list(self.members.values())
        try:
            closing = [m.handle.close.remote() for m in members]
            if closing:
                ray.wait(closing, num_returns=len(closing), timeout=CLOSE_WAIT_S)
            for member in members:
                ray.kill(member.handle, no_restart=True)
        finally:
            self.members.clear()
            self.connected = False
            ray.shutdown()
        log.info("the pool's actors are ended and Ray is left (%d roads were in flight)", len(self.in_flight))

    # --- starting actors ----------------------------------------------------------------------

    def _check_room(self) -> None:
        """A `local` Ray that cannot hold the actors is a StartError (they would wait for ever);
        a cluster that cannot hold them now is warned of (an autoscaler may add nodes)."""
        cpus = ray.cluster_resources().get("CPU", 0.0)
        needed = self.wanted * self.actor_cpus
        if needed <= cpus + 1e-9:
            return
        what = (f"{self.wanted} actors of {self.actor_cpus:g} CPU need {needed:g} CPUs; Ray has {cpus:g}: give "
                "--actor-cpus less (a simulator that keeps to real time, sleeping, needs little) or --actors fewer")
        if self.address == "local":
            raise StartError(f"--address local: {what}")
        log.warning("%s; the actors beyond wait until the cluster has room", what)

    def _resources(self) -> str:
        free = ray.available_resources().get("CPU", 0.0)
        return f"CPUs free {free:g} of {ray.cluster_resources().get('CPU', 0.0):g}, {self.actor_cpus:g} an actor"

    def _new_member(self) -> _Member:
        """A new actor (not yet set up), spread over the nodes."""
        self.started_actors += 1
        name = f"wogan-{socket.gethostname()}-{os.getpid()}-{self.started_actors}"
        handle = self.actor_class.options(num_cpus=self.actor_cpus, scheduling_strategy="SPREAD", name=name,
                                          max_restarts=0, max_task_retries=0).remote()
        return _Member(handle, name)

    def _setup(self, member: _Member) -> Any:
        """Asks `member` to load, make and hello its executor: the reference to its answer."""
        return member.handle.setup.remote(self.spec, self.init, self.settings, self.log_level)

    def _joined(self, member: _Member, started: Dict[str, Any]) -> None:
        member.node, member.ip = started["node"], started["ip"]
        self.members[member.name] = member
        self.idle.append(member)
        log.info("actor %s ready on node %s (%s), pid %s", member.name, member.ip, member.node[:8], started["pid"])

    @staticmethod
    def _cause(error: BaseException) -> str:
        """What a task raised in its actor, as `Type: message`."""
        cause = getattr(error, "cause", None)
        if isinstance(cause, BaseException):
            return f"{type(cause).__name__}: {cause}" if not isinstance(cause, ValueError) else str(cause)
        return one_line(error)

    # --- the pool's thread ----------------------------------------------------------------------

    def _run(self) -> None:
        """The pool's thread: roads to free actors, answers out, lost actors replaced."""
        try:
            while True:
                event = self.events.get()
                kind = event[0]
                if kind == "stop":
                    return
                if kind == "drain":
                    self.draining = True
                if kind == "road":
                    self.waiting.append(event[1])
                elif kind == "answer":
                    self._answered(*event[1:])
                elif kind == "ready":
                    self._ready(*event[1:])
                self._dispatch()
                if self.draining and not self.waiting and not self.in_flight:
                    self.drained.set()
        except BaseException as error:  # a fault of the pool itself: end the process, say why
            self.crashed = error
            log.error("the pool failed: %s", "".join(traceback.format_exception(type(error), error,
                                                                                error.__traceback__)))
            import _thread
            _thread.interrupt_main()

    def _dispatch(self) -> None:
        """Each waiting road to a free actor; with no actor left, none starting, none to replace
        them, every waiting road is answered ERROR."""
        held: List[_Road] = []
        while self.waiting and self.idle:
            road = self.waiting.popleft()
            member = self._actor_for(road)
            if member is None:
                held.append(road)
                continue
            road.drives += 1
            self.in_flight[road.id] = road
            reference = member.handle.drive.remote(road.message)
            reference.future().add_done_callback(lambda future, r=road, m=member: self.events.put(("answer", r, m, future)))
        self.waiting.extendleft(reversed(held))
        if self.waiting and not self.members and not self.starting:
            while self.waiting:
                road = self.waiting.popleft()
                self._write(self._error(road, "no Ray actor is left to drive it: " + "; ".join(road.reasons[-1:])))

    def _actor_for(self, road: _Road) -> Optional[_Member]:
        """The idle actor to drive `road`: for a road that lost its actor, one on another node
        (its node may be dying, its actors not yet known lost), waiting for one there is busy;
        None to wait."""
        if road.lost_on:
            for member in self.idle:
                if member.node not in road.lost_on:
                    self.idle.remove(member)
                    return member
            if any(m.node not in road.lost_on for m in self.members.values()):
                return None
        return self.idle.popleft()

    def _answered(self, road: _Road, member: _Member, future: Any) -> None:
        """A drive ended: its answer written, or (actor lost) the road driven again."""
        self.in_flight.pop(road.id, None)
        try:
            answer = future.result()
        except RayTaskError as error:
            # drive_failed() raised: that executor stops serving, as serve() would; the road is
            # answered ERROR, and the actor replaced.
            log.error("road %d: %s", road.id, error)
            self._lose(member, f"its executor stopped serving: {self._cause(error)}")
            self._write(self._error(road, f"the executor stopped serving ({member.name} on {member.ip}): "
                                          f"{self._cause(error)}"))
            return
        except Exception as error:  # RayActorError, a node lost (or another RayError): the actor is gone
            reason = f"its Ray actor {member.name} on node {member.ip} was lost: {one_line(error)}"
            self._lose(member, reason)
            self._prune()
            road.reasons.append(reason)
            road.lost_on.add(member.node)
            if road.drives < DRIVES_PER_ROAD:
                log.warning("road %d: %s; driven again by another actor", road.id, reason)
                self.waiting.appendleft(road)
            else:
                self._write(self._error(road, f"lost its Ray actor {road.drives} times: " + " / ".join(road.reasons)))
            return
        self.idle.append(member)
        if answer is not None:
            self._write(answer)

    def _lose(self, member: _Member, reason: str) -> None:
        """`member` is gone (or no longer trusted): killed, and a new actor started in its place."""
        self.members.pop(member.name, None)
        try:
            ray.kill(member.handle, no_restart=True)
        except Exception:  # noqa: BLE001 - already dead: nothing to kill
            pass
        log.warning("actor %s on node %s: %s; starting another", member.name, member.ip, reason)
        self._replace()

    def _prune(self) -> None:
        """Idle actors on nodes Ray no longer has are lost too (a node that died takes all its
        actors): replaced now, rather than each failing a road first."""
        alive = {node["NodeID"] for node in ray.nodes() if node.get("Alive")}
        for member in [m for m in self.idle if m.node not in alive]:
            self.idle.remove(member)
            self._lose(member, "its node is gone")

    def _replace(self) -> None:
        if self.failed_starts >= 2 * self.wanted + 2:
            log.error("%d actors failed to start in a row: no more are started; the pool has %d",
                      self.failed_starts, len(self.members))
            return
        member = self._new_member()
        self.starting += 1
        reference = self._setup(member)
        reference.future().add_done_callback(lambda future, m=member: self.events.put(("ready", m, future)))

    def _ready(self, member: _Member, future: Any) -> None:
        """A replacement actor started, or failed to."""
        self.starting -= 1
        try:
            started = future.result()
        except RayError as error:
            self.failed_starts += 1
            reason = self._cause(error) if isinstance(error, RayTaskError) else one_line(error)
            log.error("a new actor could not start: %s", reason)
            try:
                ray.kill(member.handle, no_restart=True)
            except Exception:  # noqa: BLE001 - already dead
                pass
            for road in self.waiting:
                road.reasons.append(f"a new actor could not start: {reason}")
            self._replace()
            return
        self.failed_starts = 0
        self._joined(member, started)

    def _error(self, road: _Road, reason: str) -> Dict[str, Any]:
        return {"id": road.id, "max_bolp": 0.0, "outcome": "ERROR", "sim_time_s": 0.0, "error": reason}

    def _write(self, answer: Dict[str, Any]) -> None:
        if self.out is not None and not self.gone and not self.out.write(answer):
            self.gone = True


def _env(names: Sequence[str]) -> Dict[str, str]:
    """`--env NAME` (the value here) or `--env NAME=VALUE`, as the actors' environment."""
    env = {}
    for item in names:
        name, equals, value = item.partition("=")
        if not name:
            raise ValueError(f"--env {item!r}: no variable's name")
        if not equals:
            if name not in os.environ:
                raise ValueError(f"--env {name}: not set here (give --env {name}=VALUE)")
            value = os.environ[name]
        env[name] = value
    return env


def parser() -> argparse.ArgumentParser:
    parse = argparse.ArgumentParser(
        prog="python -m wogan.ray",
        description="An executor for `wogan run --executor cmd:...` that serves the wogan.Executor subclass "
                    "CLASS of FILE.py as a pool of Ray actors, one simulator each, driving up to N roads at once.")
    parse.add_argument("executor", metavar="FILE.py:CLASS", help="the file defining the wogan.Executor subclass, "
                       "and its name (the file at this path on every Ray node)")
    parse.add_argument("--address", required=True,
                       help="the Ray cluster (ray.init's address: `auto`, HOST:PORT, ray://...); `local` starts a "
                            "private single-node Ray on this machine, stopped at the end")
    parse.add_argument("--actors", type=int, required=True, metavar="N",
                       help=f"how many actors (simulators), 1 to {MAX_ACTORS}: the roads driven at once")
    parse.add_argument("--actor-cpus", type=float, default=1.0, metavar="CPUS",
                       help="the CPUs Ray reserves for each actor (default 1; a simulator that keeps to real "
                            "time, sleeping, needs less: 0.1 say)")
    parse.add_argument("--init", default="{}", metavar="JSON",
                       help="keyword arguments of CLASS(...), a JSON object (default: none)")
    parse.add_argument("--env", action="append", default=[], metavar="NAME[=VALUE]",
                       help="an environment variable for the actors (its value here unless given); repeatable")
    parse.add_argument("--log-level", default="INFO", choices=("DEBUG", "INFO", "WARNING", "ERROR"),
                       help="of the notes on stderr, the pool's and the actors' (default INFO)")
    return parse


def main(argv: Optional[Sequence[str]] = None) -> int:
    """`python -m wogan.ray ...`: serves wogan on stdin and stdout until `bye` or the end of
    input; 0 then, 1 when the pool could not start (the reason on stderr), 2 for bad usage, 130
    after Ctrl-C, 143 after SIGTERM."""
    options = parser().parse_args(argv)
    logging.basicConfig(level=options.log_level, format="wogan.ray: %(message)s", stream=sys.stderr)
    try:
        spec = ExecutorSpec.parse(options.executor)
        if not 1 <= options.actors <= MAX_ACTORS:
            raise ValueError(f"--actors {options.actors}: not from 1 to {MAX_ACTORS}")
        if not options.actor_cpus >= 0:
            raise ValueError(f"--actor-cpus {options.actor_cpus}: not a number of CPUs (0 or more)")
        try:
            init = json.loads(options.init)
        except ValueError as error:
            raise ValueError(f"--init: not JSON: {error}") from None
        if not isinstance(init, dict):
            raise ValueError(f"--init: {_protocol.shown(init)} is not a JSON object of keyword arguments")
        env = _env(options.env)
        if not os.path.isfile(spec.path):
            raise ValueError(f"{spec.path}: no such file")
    except ValueError as error:
        log.error("%s", error)
        return 2
    if ray is None:
        log.error("Ray is not installed for %s: pip install 'wogan[ray]' (or pip install ray)", sys.executable)
        return 1
    if not sys.stderr.isatty():  # wogan reads it: the actors' lines that Ray forwards, uncoloured
        os.environ.setdefault("RAY_COLOR_PREFIX", "0")
    pool = Pool(spec, options.actors, options.address, options.actor_cpus, init, env, options.log_level)

    def on_hello(settings: Dict[str, Any]) -> bool:
        reply = pool.hello(settings)
        return True if reply is None else out.write(reply)

    ended = []

    def lines(source: Any) -> Any:
        yield from source
        ended.append(True)  # the end of input (else `bye`, or wogan gone)

    try:
        with _protocol.session(None, None) as (source, out):
            pool.out = out
            try:
                _protocol.exchange(lines(source), PROTOCOL, VERSION, {"road": pool.submit}, on_hello,
                                   oldest=OLDEST_VERSION)
                if not ended and not pool.gone:
                    pool.drain()  # `bye`: every road taken is answered first
            finally:
                pool.close()
    except StartError as error:
        log.error("%s", error)
        return 1
    except KeyboardInterrupt:
        if pool.crashed is not None:
            return 1
        log.info("interrupted")
        return 130
    return 1 if pool.crashed is not None else 0


if __name__ == "__main__":
    # Run as `python -m wogan.ray`, this file is `__main__`: the pool is used from the module
    # `wogan.ray`, which Ray's workers import by that name to make its actors.
    from wogan.ray import main as _main

    sys.exit(_main())
