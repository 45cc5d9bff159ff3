"""The executor: wogan's executor protocol served by `wogan.Executor`, each road driven by a
MetaDriveDriver, and the command line (`main`).

A fault of one road (a road that cannot be built, a MetaDrive exception, more wall time than
--road-wall-timeout) answers that road ERROR; MetaDrive is then closed and started again for the
next road. A crash or a hang in native code is left to wogan (its --executor-timeout, then a new
executor). `bye`, the end of input, SIGTERM and SIGINT close MetaDrive.
"""
from __future__ import annotations

import argparse
import logging
import os
import signal
import sys
import time
from typing import Any, Optional

# Without `pip install .` (wogan's wheel), the package is found in this checkout's python/ folder.
sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "python"))
import wogan  # noqa: E402

from .constants import DEFAULT_OOB_TOLERANCE, DEFAULT_SPEED_LIMIT_KMH  # noqa: E402
from .driving import MetaDriveDriver  # noqa: E402
from .road import RoadError, build_road, lanes, set_lane_width  # noqa: E402

log = logging.getLogger("metadrive-executor")


class WallTimeout(Exception):
    """A road took more wall time than --road-wall-timeout."""


class MetaDriveExecutor(wogan.Executor):
    """Drives each road wogan sends in one MetaDrive, started again after a fault. MetaDrive starts
    at the first road (and again after a fault): that road's drive, and wogan's timeout for it,
    include the start."""

    name = "wogan-metadrive-executor"

    def __init__(self, policy: str, wall_timeout_s: float, execution_data: bool = False,
                 wheel_friction: Optional[float] = None) -> None:
        super().__init__()
        self.policy = policy
        self.wheel_friction = wheel_friction
        self.execution_data = execution_data
        self.wall_timeout_s = wall_timeout_s
        self.speed_limit_kmh = DEFAULT_SPEED_LIMIT_KMH
        self.tolerance = DEFAULT_OOB_TOLERANCE
        self.driver: Optional[MetaDriveDriver] = None
        self.broken = False  # MetaDrive failed: close it before the next road

    def hello(self, settings: dict) -> None:
        self.speed_limit_kmh = float(settings.get("speed_limit_kmh", self.speed_limit_kmh))
        self.tolerance = float(settings.get("oob_tolerance", self.tolerance))
        if self.driver is not None:  # a second hello: new settings, new MetaDrive
            self.driver.close()
            self.driver = None
        log.info("hello: speed limit %.1f km/h, tolerance %.3f, policy %s",
                 self.speed_limit_kmh, self.tolerance, self.policy)

    def reported_settings(self) -> dict:
        """What the reply to `hello` says of this executor's settings."""
        return {"simulator": f"metadrive-simulator {_metadrive_version()}", "policy": self.policy,
                "speed_limit_kmh": self.speed_limit_kmh, "oob_tolerance": self.tolerance,
                "road_wall_timeout_s": self.wall_timeout_s, "execution_data": self.execution_data,
                "wheel_friction": self.wheel_friction, "lane_width_m": lanes.lane_width_m}

    def drive(self, road: wogan.Road) -> wogan.Answer:
        if self.broken:
            self.restart_driver()
        started = time.monotonic()
        try:
            built = build_road(road.points)
        except RoadError as error:
            return wogan.Answer(max_bolp=0.0, outcome="ERROR", sim_time_s=0.0,
                                error=f"road cannot be built: {error}", extra={"policy": self.policy})
        if self.driver is None:
            self.driver = MetaDriveDriver(self.policy, self.speed_limit_kmh, self.tolerance, self.wheel_friction)
        previous = signal.signal(signal.SIGALRM, _on_alarm)
        signal.setitimer(signal.ITIMER_REAL, self.wall_timeout_s)
        try:
            result = self.driver.drive(built, broken=fault_injection(road.id), record=self.execution_data)
        except Exception as error:  # MetaDrive's exceptions are of every kind
            signal.setitimer(signal.ITIMER_REAL, 0)
            what = ("MetaDrive took more than %g s of wall time" % self.wall_timeout_s
                    if isinstance(error, WallTimeout) else f"MetaDrive: {type(error).__name__}: {error}")
            log.exception("road %d: %s; restarting MetaDrive", road.id, what)
            self.broken = True
            return wogan.Answer(max_bolp=0.0, outcome="ERROR", sim_time_s=0.0, error=what,
                                extra={"policy": self.policy, "wall_s": round(time.monotonic() - started, 3)})
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, previous)
        extra: dict = {}
        if result.reason is not None:
            extra["reason"] = result.reason
        extra["policy"] = self.policy
        if result.execution_data is not None:
            extra["execution_data"] = result.execution_data
        extra["wall_s"] = round(time.monotonic() - started, 3)
        return wogan.Answer(max_bolp=result.max_bolp, outcome=result.outcome,
                            sim_time_s=round(result.sim_time_s, 4), oob_side=result.side, oob_point=result.point,
                            min_lane_distance_m=round(result.min_lane_distance_m, 4), extra=extra)

    def restart_driver(self) -> None:
        """Closes the MetaDrive that failed; the next road starts a new one. If it cannot be
        closed, the process cannot go on safely: exit, and wogan starts a new executor."""
        driver, self.driver, self.broken = self.driver, None, False
        if driver is None:
            return
        try:
            driver.close()
        except BaseException as error:  # noqa: BLE001 - anything here means a broken MetaDrive
            log.error("MetaDrive cannot be closed (%s: %s); exiting", type(error).__name__, error)
            os._exit(1)

    def close(self) -> None:
        """`bye`, the end of input or a signal: MetaDrive is closed."""
        if self.broken:
            self.restart_driver()
        elif self.driver is not None:
            self.driver.close()
            self.driver = None


def _metadrive_version() -> str:
    """The installed metadrive-simulator's version ("unknown" when it is not installed)."""
    try:
        from importlib.metadata import version
        return version("metadrive-simulator")
    except Exception:  # noqa: BLE001 - not installed, or no metadata
        return "unknown"


def _on_alarm(signum: int, frame: Any) -> None:
    """SIGALRM at --road-wall-timeout: the drive, in Python code, is interrupted where it is."""
    raise WallTimeout()


def fault_injection(road_id: int) -> bool:
    """For testing the fault paths (examples/metadrive/check.sh): WOGAN_METADRIVE_FAULT=KIND:ID
    makes road ID fail. KIND `exception`: MetaDrive is given the road without its lane's centre
    line, which it refuses (True is returned: break the scenario); `hang`: a wait without end;
    `crash`: the process aborts."""
    spec = os.environ.get("WOGAN_METADRIVE_FAULT", "")
    kind, _, target = spec.partition(":")
    if not spec or target != str(road_id):
        return False
    if kind == "hang":
        while True:
            time.sleep(1)
    if kind == "crash":
        os.abort()
    return kind == "exception"


def _on_terminate(signum: int, frame: Any) -> None:
    raise SystemExit(128 + signum)


def main(argv: Optional[list] = None, description: Optional[str] = None) -> int:
    """The executor's command line (`description`: of its --help); serves the protocol until `bye`,
    the end of input or a signal. Returns the exit status."""
    parser = argparse.ArgumentParser(description=description,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--policy", choices=("idm", "expert"), default="idm",
                        help="who drives: MetaDrive's IDMPolicy or its PPO expert (default idm)")
    parser.add_argument("--road-wall-timeout", type=float, default=300.0, metavar="SECONDS",
                        help="wall time one road may take before it is answered ERROR (default 300)")
    parser.add_argument("--execution-data", action="store_true",
                        help="answers also carry the drive as the SBST pipeline records it "
                             "(`execution_data`, as `wogan simulate --execution-data`), for "
                             "scripts/peers; wogan ignores it")
    parser.add_argument("--wheel-friction", type=float, default=None, metavar="F",
                        help="the tyres' friction, Bullet's friction slip of the wheels (MetaDrive's car: "
                             "0.9; lower is more slippery); MetaDrive's own when absent")
    parser.add_argument("--lane-width", type=float, default=lanes.lane_width_m, metavar="M",
                        help="the width of each of the road's two lanes, metres (default 4, the "
                             "competition's and wogan's); BOLP is measured against it")
    parser.add_argument("--log-level", default="INFO", help="of the log on standard error")
    args = parser.parse_args(argv)

    logging.basicConfig(level=args.log_level.upper(), stream=sys.stderr,
                        format="[metadrive-executor %(process)d] %(levelname)s %(message)s")
    signal.signal(signal.SIGTERM, _on_terminate)
    signal.signal(signal.SIGINT, _on_terminate)
    if args.wheel_friction is not None and not 0.0 < args.wheel_friction <= 10.0:
        parser.error(f"--wheel-friction: {args.wheel_friction} is not above 0 and at most 10")
    if not 2.5 <= args.lane_width <= 6.0:  # MetaDrive's car is 1.85 m wide
        parser.error(f"--lane-width: {args.lane_width} is not within 2.5 and 6 m")
    set_lane_width(args.lane_width)
    executor = MetaDriveExecutor(args.policy, args.road_wall_timeout, args.execution_data, args.wheel_friction)
    try:
        # Standard output carries the protocol only: serve() keeps it for that, and sends whatever
        # else writes there (MetaDrive, Panda3D, print) to standard error. When wogan closes the
        # answers' pipe, serving ends.
        executor.serve()
    except SystemExit as stop:
        log.info("stopped by a signal; MetaDrive closed")
        return int(stop.code or 0)
    return 0
