"""Runs one SBST 2022 test generator, unchanged, in the competition's pipeline against wogan's simulator.

Dev-time only (docs: scripts/peers/README.md). It does what the pipeline's competition.py
`generate` does (its logging, a result folder, the executor, `the_class(executor=...,
map_size=...).start()`), with simulate_executor.WoganExecutor in place of BeamNG's, driving roads with `wogan simulate` or
with an executor (MetaDrive's):

  venv/bin/python scripts/peers/run_peer.py --pipeline PIPELINE --module-name M --class-name C \
      --wogan target/release/wogan --oracle beamng-ai-proxy --seed 1 --out OUT
  venv/bin/python scripts/peers/run_peer.py ... --oracle metadrive-idm --seed 1 --out OUT \
      --executor "target/metadrive-venv/bin/python examples/metadrive/executor.py --policy idm --execution-data"

Budgets are the competition's (1 h of generation, 2 h of simulated execution), on a virtual clock:
the pipeline's `time.monotonic` advances by each drive's simulated time (which the pipeline does
not count as generation) and `time.sleep` advances it instead of sleeping, so a generator whose
phases are set in seconds sees its time pass as beside a real-time simulator.
"""
import argparse
import importlib
import json
import logging as log
import os
import random
import shlex
import signal
import sys
import time
import traceback
import types

HERE = os.path.dirname(os.path.abspath(__file__))


class VirtualClock:
    """time.monotonic plus the simulated seconds so far; time.sleep only advances it."""

    def __init__(self):
        self.offset_s = 0.0
        self.real_monotonic = time.monotonic

    def monotonic(self):
        return self.real_monotonic() + self.offset_s

    def advance(self, seconds):
        self.offset_s += float(seconds)

    def install(self):
        time.monotonic = self.monotonic
        time.sleep = self.advance


def stub_beamng_executor():
    """Some generators import code_pipeline.beamng_executor (and so beamngpy) without using it."""
    try:
        import beamngpy  # noqa: F401
        return
    except ImportError:
        pass
    module = types.ModuleType("code_pipeline.beamng_executor")

    class BeamngExecutor:
        def __init__(self, *args, **kwargs):
            raise RuntimeError("BeamNG is not available here: roads are driven by wogan")

    module.BeamngExecutor = BeamngExecutor
    sys.modules["code_pipeline.beamng_executor"] = module


def arguments():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--pipeline", required=True, help="checkout holding code_pipeline/ and the generator")
    p.add_argument("--module-name", required=True)
    p.add_argument("--class-name", required=True)
    p.add_argument("--module-path", help="another folder to import the generator from")
    p.add_argument("--api", choices=["2022", "2021"], default="2022",
                   help="2021: a generator written for the 2021 pipeline (time_budget argument, "
                        "get_remaining_time() in seconds)")
    p.add_argument("--wogan", help="the wogan binary (drives the roads with `wogan simulate`)")
    p.add_argument("--executor", metavar="COMMAND",
                   help="instead of --wogan: an executor speaking wogan's executor protocol that "
                        "answers with execution data, e.g. \"PYTHON examples/metadrive/executor.py "
                        "--policy idm --execution-data\" (split as a shell would)")
    p.add_argument("--oracle", default="beamng-ai-proxy",
                   help="the driver: wogan's (with --wogan), or the executor's name in the summary")
    p.add_argument("--oob-tolerance", type=float, default=None,
                   help="default: the competition's 0.85 for beamng-ai-proxy, 0.10 for dave2-proxy")
    p.add_argument("--speed-limit", type=int, default=None,
                   help="km/h; default: 70 for beamng-ai-proxy, 25 for dave2-proxy")
    p.add_argument("--map-size", type=int, default=200)
    p.add_argument("--generation-budget", type=int, default=3600, help="seconds of generation")
    p.add_argument("--execution-budget", type=int, default=7200, help="simulated seconds")
    p.add_argument("--max-valid-tests", type=int, help="also stop after this many executed valid tests")
    p.add_argument("--clock", choices=["virtual", "real"], default="virtual")
    p.add_argument("--exact-validator", action="store_true",
                   help="the pipeline's validity check as it is (default: fast_validity's, same verdicts)")
    p.add_argument("--seed", type=int, help="seeds Python's random and numpy's global generator")
    p.add_argument("--out", required=True, help="result folder, created (an existing one is refused)")
    args = p.parse_args()
    if (args.wogan is None) == (args.executor is None):
        p.error("give one of --wogan and --executor")
    dave2 = args.oracle == "dave2-proxy"
    if args.oob_tolerance is None:
        args.oob_tolerance = 0.10 if dave2 else 0.85
    if args.speed_limit is None:
        args.speed_limit = 25 if dave2 else 70
    return args


def main():
    args = arguments()
    out = os.path.abspath(args.out)
    os.makedirs(out)  # refuses an existing folder: a run never writes over another
    # Paths made absolute before the generator's folder becomes the working directory.
    wogan = os.path.abspath(args.wogan) if args.wogan else None
    executor_command = None
    if args.executor is not None:
        executor_command = [os.path.abspath(w) if os.path.exists(w) else w
                            for w in shlex.split(args.executor)]
    sys.path[:0] = [HERE, os.path.abspath(args.pipeline)]
    if args.module_path:  # after the pipeline: its code_pipeline is the one that runs
        sys.path.insert(2, os.path.abspath(args.module_path))
    clock = VirtualClock() if args.clock == "virtual" else None
    if clock:
        clock.install()
    if args.seed is not None:
        random.seed(args.seed)
        import numpy
        numpy.random.seed(args.seed)
    stub_beamng_executor()
    if not args.exact_validator:
        import fast_validity
        fast_validity.install()
    os.chdir(out)  # generators write relative paths (simulations/, experiments/)

    import competition
    from code_pipeline.test_generation_utils import register_exit_fun
    from simulate_executor import Api2021Executor, ExecutorChild, SimulateChild, WoganExecutor

    competition.setup_logging(os.path.join(out, "run.log"), False)
    generator_class = getattr(importlib.import_module(args.module_name), args.class_name)
    if args.executor is not None:
        child = ExecutorChild(executor_command, args.oob_tolerance, args.speed_limit,
                              args.map_size)
    else:
        child = SimulateChild(wogan, args.oracle, args.oob_tolerance, args.speed_limit,
                              args.map_size)
    executor_class = Api2021Executor if args.api == "2021" else WoganExecutor
    executor = executor_class(out, args.map_size, child, generation_budget=args.generation_budget,
                              execution_budget=args.execution_budget,
                              max_valid_tests=args.max_valid_tests, clock=clock)
    started = time.perf_counter()
    register_exit_fun(lambda: write_summary(args, out, executor, started))
    note_interrupting_signals(executor)
    try:
        if args.api == "2021":
            generator = generator_class(time_budget=args.execution_budget, executor=executor,
                                        map_size=args.map_size)
        else:
            generator = generator_class(executor=executor, map_size=args.map_size)
        generator.start()
    except Exception:
        log.fatal("The generator failed")
        traceback.print_exc()
        executor.crashed = traceback.format_exc().strip().splitlines()[-1]
        sys.exit(2)
    finally:
        executor.close()


def note_interrupting_signals(executor):
    """Notes on the executor a SIGTERM or SIGINT before the handler already installed runs (the
    pipeline's writes the summary on SIGTERM), so that the summary of a run cut short says so
    and a campaign runs it again instead of counting a part of a run as a whole one."""
    for number in (signal.SIGTERM, signal.SIGINT):
        earlier = signal.getsignal(number)

        def note(signum, frame, earlier=earlier):
            executor.interrupted = signal.Signals(signum).name
            if callable(earlier):
                earlier(signum, frame)
            else:
                sys.exit(128 + signum)

        signal.signal(number, note)


def write_summary(args, out, executor, started):
    """summary.json: what `wogan report` reads as the run's configuration, and the run's counts."""
    stats = executor.stats
    summary = {"type": "summary", "generator": f"{args.module_name}.{args.class_name}",
               "oracle": args.oracle, "executor": args.executor,
               "oob_tolerance": args.oob_tolerance,
               "speed_limit": args.speed_limit, "seed": args.seed, "clock": args.clock,
               "generation_budget_s": args.generation_budget,
               "execution_budget_s": args.execution_budget,
               "proposals": stats.test_generated, "valid": stats.test_valid,
               "invalid": stats.test_invalid, "passed": stats.test_passed,
               "failed": stats.test_failed, "obes": stats.obes, "errors": stats.test_in_error,
               "simulated_s": round(sum(stats.test_execution_simulation_times), 1),
               "ended_by_budget": executor.is_force_timeout(),
               "crashed": getattr(executor, "crashed", None),
               "interrupted": getattr(executor, "interrupted", None),
               "wall_s": round(time.perf_counter() - started, 1)}
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(summary, f)
    print(json.dumps(summary), flush=True)


if __name__ == "__main__":
    main()
