"""`python -m wogan.ray`: a search's roads driven by Ray actors on a real Ray cluster of two nodes on
this machine (`ray start --head` and a second node joining it), started here and torn down at the
end, every address on loopback.

Ray binds and announces the host's network address by default: these tests run only where the
network is loopback alone, a network namespace of its own (CI: `unshare -n sh -c 'ip link set lo
up && exec python -m pytest test_ray.py'`, as root). Without Ray, or outside such a namespace, they
fail, saying why: a skipped test would prove nothing, and CI installs Ray."""

import json
import os
import shlex
import signal
import socket
import subprocess
import sys
import tempfile
import time

import pytest
from helpers import HERE, command

import wogan


def _unmet(reason):
    pytest.fail(f"the Ray tests cannot run: {reason}", pytrace=False)


try:
    import ray
except ImportError:
    _unmet(f"Ray is not installed for {sys.executable} (pip install 'wogan[ray]')")

if [name for _, name in socket.if_nameindex()] != ["lo"]:
    _unmet("the network is not loopback alone: run in a namespace of its own, "
           "unshare -n sh -c 'ip link set lo up && exec python -m pytest test_ray.py' (as root)")

LOOPBACK = "127.0.0.1"
# Ray's token authentication off for the cluster, the pools and this process alike (on loopback in
# a namespace of our own there is no one to keep out), and no token written to ~/.ray by a private
# `--address local` Ray (newer Rays make one there by default, which later clusters then demand).
os.environ["RAY_AUTH_MODE"] = "disabled"
# A node declared dead after about 3 s of missed health checks (Ray's default: about 15 s).
QUICK_HEALTH_CHECKS = {"RAY_health_check_period_ms": "1000", "RAY_health_check_timeout_ms": "1000",
                       "RAY_health_check_failure_threshold": "3"}
NODE_CPUS = 2
ACTOR_CPUS = "0.1"
GEOMETRIC = os.path.join(HERE, "geometric_executor.py")
TRACED = os.path.join(HERE, "ray_executor.py")
HELLO = {"type": "hello", "protocol": "wogan-executor", "version": 3, "units": "metres, seconds",
         "map_size_m": 200.0, "oob_tolerance": 0.85, "speed_limit_kmh": 70.0}
ROAD = {"type": "road", "id": 1, "road_points": [[100.0, 10.0], [100.0, 25.0], [99.9, 40.0], [95.5, 54.3]]}


def free_port():
    with socket.socket() as s:
        s.bind((LOOPBACK, 0))
        return s.getsockname()[1]


def ray_cli():
    beside = os.path.join(os.path.dirname(sys.executable), "ray")
    return beside if os.path.exists(beside) else "ray"


def until(condition, timeout, what):
    """Waits for `condition()` to be true, at most `timeout` seconds; fails naming `what`."""
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            pytest.fail(f"after {timeout} s: {what}")
        time.sleep(0.2)


def processes():
    """Every process of this machine: pid -> its command line."""
    found = {}
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as f:
                found[int(pid)] = f.read().replace(b"\0", b" ").decode(errors="replace")
        except OSError:
            pass
    return found


def children(pid):
    """The processes whose parent is `pid`: pid -> the program's name."""
    found = {}
    for child in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open(f"/proc/{child}/stat") as f:
                stat = f.read()
        except OSError:
            continue
        name, rest = stat[stat.index("(") + 1:stat.rindex(")")], stat[stat.rindex(")") + 2:].split()
        if int(rest[1]) == pid:
            found[int(child)] = name
    return found


class Cluster:
    """Two Ray nodes on this machine, each a `ray start --block` of its own (its own process group
    and temporary folder), the head's GCS on a free port of 127.0.0.1."""

    def __init__(self):
        self.port = free_port()
        self.address = f"{LOOPBACK}:{self.port}"
        self.folder = tempfile.mkdtemp(prefix="wogan-ray-")  # short: Ray's socket paths are bounded
        self.head = self._start("head", ["--head", "--port", str(self.port), "--include-dashboard", "false"])
        self.worker = None

    def _start(self, name, args):
        temp = os.path.join(self.folder, name)
        log = open(os.path.join(self.folder, f"{name}.log"), "w")
        process = subprocess.Popen(
            [ray_cli(), "start", "--block", "--node-ip-address", LOOPBACK, "--num-cpus", str(NODE_CPUS),
             "--object-store-memory", str(100 * 2**20), "--temp-dir", temp, "--disable-usage-stats", *args],
            stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT, start_new_session=True,
            env={**os.environ, **QUICK_HEALTH_CHECKS})
        log.close()
        until(lambda: process.poll() is not None or "Ray runtime started" in self.log(name), 90,
              f"ray start ({name}) did not start: {self.log(name)[-2000:]}")
        assert process.poll() is None, f"ray start ({name}) ended: {self.log(name)[-2000:]}"
        return process

    def log(self, name):
        with open(os.path.join(self.folder, f"{name}.log"), errors="replace") as f:
            return f.read()

    def start_worker(self):
        self.worker = self._start("worker", ["--address", self.address])
        until(lambda: len(self.alive_nodes()) == 2, 60, "the second node did not join")

    def alive_nodes(self):
        return [node for node in ray.nodes() if node["Alive"]]

    def raylet(self, process):
        """The pid of the raylet a `ray start` started: the node itself."""
        found = [pid for pid, name in children(process.pid).items() if name == "raylet"]
        assert len(found) == 1, children(process.pid)
        return found[0]

    def stop(self):
        for process in (self.worker, self.head):
            if process is None:
                continue
            if process.poll() is None:
                process.terminate()  # `ray start --block` stops its node's processes and ends
                try:
                    process.wait(timeout=30)
                except subprocess.TimeoutExpired:
                    pass
            try:  # anything of its process group still there (its own group: start_new_session)
                os.killpg(process.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            process.wait()
        # The node's processes name their temporary folder; none may be left.
        left = {pid: line for pid, line in processes().items() if self.folder in line}
        for pid in left:
            os.kill(pid, signal.SIGKILL)
        assert not left, f"left by the cluster: {left}"


@pytest.fixture(scope="module")
def cluster():
    started = Cluster()
    try:
        ray.init(address=started.address, log_to_driver=False)
        started.start_worker()
        yield started
    finally:
        ray.shutdown()
        started.stop()
        subprocess.run(["rm", "-rf", started.folder], check=False)


def pool(cluster, spec, actors, *more, address=None):
    """`cmd:...` of a pool of `actors` actors serving `spec` (FILE.py:CLASS) on the cluster."""
    return "cmd:" + shlex.join(pool_args(cluster, spec, actors, *more, address=address))


def pool_args(cluster, spec, actors, *more, address=None):
    return [sys.executable, "-m", "wogan.ray", "--address", address or cluster.address, "--actors", str(actors),
            "--actor-cpus", ACTOR_CPUS, *more, spec]


def deterministic(test):
    """A test record but for its wall times."""
    return {k: v for k, v in test.items() if k not in ("generation_ms", "sbst_generation_ms", "execution_ms")}


def pool_actors():
    """The pool's actors Ray still has (each is named `wogan-...`, in the namespace `wogan`)."""
    return [a for a in ray.util.list_named_actors(all_namespaces=True) if a["name"].startswith("wogan-")]


def actor_processes():
    return {pid: line for pid, line in processes().items() if "PoolActor" in line}


def running_jobs():
    """The Ray jobs (drivers) of the cluster still running but this test's own connection."""
    own = ray.get_runtime_context().get_job_id()
    return [job for job in ray._private.state.jobs() if not job["IsDead"] and job["JobID"] != own]


def assert_no_job_running(timeout=30):
    until(lambda: not running_jobs(), timeout, f"Ray jobs left running: {running_jobs()}")


def assert_nothing_left(timeout=30):
    """No actor of a pool, no actor's process, no pool's Ray job (driver) left running."""
    until(lambda: not pool_actors() and not actor_processes(), timeout,
          f"actors left: {pool_actors()}, processes {actor_processes()}")
    assert_no_job_running(timeout)


def test_the_cluster_is_two_nodes_on_loopback(cluster):
    nodes = cluster.alive_nodes()
    assert len(nodes) == 2
    assert {node["NodeManagerAddress"] for node in nodes} == {LOOPBACK}
    assert ray.get_runtime_context().gcs_address == cluster.address


def test_a_search_over_4_actors_gives_the_records_of_4_local_processes(cluster):
    args = ["--max-tests", "40", "--seed", "7", "--jobs", "4"]
    local = wogan.run([*args, "--executor", command("geometric_executor.py")])
    pooled = wogan.run([*args, "--executor", pool(cluster, f"{GEOMETRIC}:Geometric", 4)])
    assert len(pooled.tests) == 40 and pooled.status == 0
    assert [deterministic(t) for t in pooled.tests] == [deterministic(t) for t in local.tests]
    assert {t["outcome"] for t in pooled.tests} == {"PASS", "FAIL"}
    # The executor described is the class served, and the pool: its actors on both nodes.
    described = pooled.summary["executor"]
    assert (described["name"], described["version"]) == ("Geometric", "1.0")
    assert described["settings"]["bolp"] == "sharpest turn / 0.8 rad"
    assert described["settings"]["ray"] == {"address": cluster.address, "actors": 4, "actor_cpus": 0.1, "nodes": 2}
    assert_nothing_left()


def test_an_exception_in_drive_answers_that_road_error_with_its_message(cluster):
    run = wogan.run(["--max-tests", "8", "--seed", "3", "--jobs", "2", "--executor",
                     pool(cluster, f"{GEOMETRIC}:Geometric", 2, "--env", "RAISE_AT=3")])
    assert [t["id"] for t in run.tests] == list(range(1, 9))
    # RAISE_AT names the third road sent (the protocol's id), which with --jobs 2 is test 3's or
    # test 4's: the two are sent at once, in either order.
    errors = [t for t in run.tests if t["outcome"] == "ERROR"]
    assert len(errors) == 1 and errors[0]["id"] in (3, 4), [(t["id"], t["outcome"]) for t in run.tests]
    assert errors[0]["error"] == "road 3: the executor: ValueError: road 3 refused on purpose"
    assert all(t["outcome"] in ("PASS", "FAIL") for t in run.tests if t is not errors[0])


def test_an_actor_that_dies_has_its_road_driven_again_once_and_is_replaced(cluster, tmp_path):
    where = tmp_path / "where.jsonl"
    run = wogan.run(["--max-tests", "10", "--seed", "3", "--jobs", "2", "--executor",
                     pool(cluster, f"{TRACED}:Traced", 2, "--env", f"WHERE_TO={where}", "--env", "DIE_ONCE_AT=4",
                          "--env", "DIE_AT=7")])
    assert [t["id"] for t in run.tests] == list(range(1, 11))
    errors = [t["error"] for t in run.tests if t["outcome"] == "ERROR"]
    # Road 4's actor died once: another drove it. Road 7 killed both its actors: ERROR, saying so.
    # (Roads are numbered as sent: with --jobs 2, road 7 is test 7's or test 8's.)
    assert len(errors) == 1, errors
    assert errors[0].startswith("road 7: the executor: lost its Ray actor 2 times: its Ray actor wogan-")
    assert "was lost" in errors[0] and "The actor died" in errors[0]
    drives = [json.loads(line) for line in where.read_text().splitlines()]
    by_road = {road: [d["pid"] for d in drives if d["id"] == road] for road in (4, 7)}
    assert len(set(by_road[4])) == 2 and len(set(by_road[7])) == 2, by_road
    # Three actors died (road 4's first, both of road 7's); the pool replaced them and went on:
    # the next round's roads (9, 10: rounds of --jobs 2) were driven by actors alive.
    died = {by_road[4][0], *by_road[7]}
    assert len(died) == 3, by_road
    last_round = {d["pid"] for d in drives if d["id"] in (9, 10)}
    assert last_round and not last_round & died, drives
    assert_nothing_left()


def test_a_worker_node_killed_mid_run_loses_no_test(cluster, tmp_path):
    """Also: the roads of one search are driven by actors on more than one Ray node."""
    where, out = tmp_path / "where.jsonl", tmp_path / "run.jsonl"
    executor = pool(cluster, f"{TRACED}:Traced", 4, "--env", f"WHERE_TO={where}", "--env", "SLEEP_S=0.5")
    run = subprocess.Popen([wogan.find_binary(), "run", "--max-tests", "40", "--seed", "5", "--jobs", "4",
                            "--executor", executor, "--out", str(out)], stdout=subprocess.DEVNULL,
                           stderr=subprocess.PIPE, text=True)
    worker_node = cluster.worker
    try:
        def drives():
            return [json.loads(line) for line in where.read_text().splitlines()] if where.exists() else []

        worker_id = next(n["NodeID"] for n in cluster.alive_nodes() if not n["Resources"].get("node:__internal_head__"))
        until(lambda: len(drives()) >= 8 and worker_id in {d["node"] for d in drives()}, 120,
              f"no roads driven on the worker node: {drives()}")
        assert len({d["node"] for d in drives()}) == 2  # both nodes drove roads of this one search
        os.kill(cluster.raylet(worker_node), signal.SIGKILL)  # the node, at once
        driven_before = len(drives())
        _, stderr = run.communicate(timeout=240)
    finally:
        if run.poll() is None:
            run.kill()
            run.wait()
        worker_node.wait(timeout=60)  # its `ray start` saw its raylet die: it stopped the rest and ended
        cluster.start_worker()  # for the tests after this one
    assert run.returncode == 0, stderr
    assert driven_before < 40, "the node was killed mid-run, with roads still to drive"
    tests = [json.loads(line) for line in out.read_text().splitlines() if '"type":"test"' in line]
    assert sorted(t["id"] for t in tests) == list(range(1, 41))  # each exactly once
    assert all(t["outcome"] in ("PASS", "FAIL") for t in tests), [t.get("error") for t in tests]
    # (The lost actors' replacement is asserted where it is not a matter of timing: the test of an
    # actor that dies, whose last roads only replacements can drive.)
    assert_nothing_left()


def default_signals():
    """In the pool's process before it starts: Ctrl-C and quit as a terminal delivers them. A
    shell without job control starts its background commands with both ignored, and a test run
    from such a command would otherwise hand that on."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.signal(signal.SIGQUIT, signal.SIG_DFL)


def serve(args, *lines, env=None):
    """The pool started by hand: `args`, its hello (and `lines`) written, the process."""
    process = subprocess.Popen(args, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True, env=env, preexec_fn=default_signals)
    for message in (HELLO, *lines):
        process.stdin.write(json.dumps(message) + "\n")
    process.stdin.flush()
    return process


@pytest.mark.parametrize("spec, more, says", [
    ("no_such_file.py:Geometric", [], "no_such_file.py: no such file"),
    (f"{GEOMETRIC}:Missing", [], f"{GEOMETRIC}: no Missing in it"),
    (f"{GEOMETRIC}:bolp_of", [], f"{GEOMETRIC}:bolp_of: not a wogan.Executor subclass (function bolp_of)"),
    (f"{TRACED}:NeedsArguments", [], "NeedsArguments(**{}) cannot be made (on node 127.0.0.1): "),
    (f"{GEOMETRIC}:Geometric", ["--env", "HELLO_RAISES=1"], "RuntimeError: the simulator did not start"),
])
def test_an_executor_that_cannot_start_is_named_before_any_road_and_no_hello_is_replied(cluster, spec, more, says):
    process = serve(pool_args(cluster, spec, 2, *more), ROAD)
    stdout, stderr = process.communicate(timeout=120)
    assert stdout == "", "no reply to hello, no answer"
    assert process.returncode == (2 if "no such file" in says else 1), stderr
    assert says in stderr.splitlines()[-1], stderr
    assert_nothing_left()


def test_init_gives_the_class_its_arguments(cluster):
    process = serve(pool_args(cluster, f"{TRACED}:NeedsArguments", 1, "--init", '{"policy": "idm"}'), ROAD,
                    {"type": "bye"})
    stdout, stderr = process.communicate(timeout=120)
    reply, answer = [json.loads(line) for line in stdout.splitlines()]
    assert reply["roads_at_once"] == 1 and reply["executor"]["settings"]["policy"] == "idm", reply
    assert answer["id"] == 1 and process.returncode == 0, stderr


@pytest.mark.parametrize("end, status", [("bye", 0), ("eof", 0), (signal.SIGTERM, 143), (signal.SIGINT, 130),
                                         (signal.SIGKILL, -9)])
def test_the_end_leaves_no_actor_and_no_process(cluster, tmp_path, end, status):
    """bye (the road in flight answered first, as serve() answers each road before it reads bye),
    the end of input, SIGTERM, Ctrl-C, and being killed outright (Ray ends the actors of a driver
    that is gone); a road in flight at each of them."""
    where = tmp_path / "where.jsonl"
    process = serve(pool_args(cluster, f"{TRACED}:Traced", 2, "--env", f"WHERE_TO={where}", "--env", "SLEEP_S=15"),
                    ROAD)
    assert json.loads(process.stdout.readline())["roads_at_once"] == 2
    until(lambda: where.exists(), 60, "road 1 was not driven")
    assert len(pool_actors()) == 2 and len(actor_processes()) == 2
    if end == "bye":
        process.stdin.write('{"type": "bye"}\n')
    if end in ("bye", "eof"):
        process.stdin.close()
    else:
        process.send_signal(end)
    # Bounded: a pool that does not end fails the test instead of holding it (its output is a line
    # or two, which the pipes hold while it is waited for).
    try:
        process.wait(timeout=120)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()
        raise AssertionError(f"the pool did not end within 120 s of {end}")
    answers = [json.loads(line) for line in process.stdout.read().splitlines()]
    assert process.returncode == status, process.stderr.read()
    assert [a["id"] for a in answers] == ([1] if end == "bye" else []), answers
    assert_nothing_left()


def test_address_local_starts_a_private_ray_and_stops_it():
    """`--address local`: a Ray of this machine alone, started at hello and stopped at the end; its
    processes die with the pool even when the pool is killed outright."""
    before = set(processes())

    def ray_processes():
        return {pid: line for pid, line in processes().items()
                if pid not in before and ("raylet" in line or "gcs_server" in line or "ray::" in line)}

    for end in ("bye", signal.SIGKILL):
        process = serve([sys.executable, "-m", "wogan.ray", "--address", "local", "--actors", "2", "--actor-cpus",
                         ACTOR_CPUS, f"{GEOMETRIC}:Geometric"], ROAD)
        reply, answer = json.loads(process.stdout.readline()), json.loads(process.stdout.readline())
        assert reply["executor"]["settings"]["ray"]["address"] == "local" and answer["id"] == 1
        assert ray_processes()
        if end == "bye":
            process.stdin.write('{"type": "bye"}\n')
            process.stdin.close()
        else:
            process.send_signal(end)
        process.wait(timeout=60)
        until(lambda: not ray_processes(), 30, f"left by --address local ({end}): {ray_processes()}")
