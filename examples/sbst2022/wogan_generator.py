"""WOGAN as a test generator of the SBST 2022 tool competition's pipeline (se2p/tool-competition-av):

    python competition.py --module-name wogan_generator --class-name WoganGenerator \
        --module-path /path/to/wogan/examples/sbst2022 --executor beamng ...

`WoganGenerator.start()` runs `wogan run --executor cmd:...` with this process as wogan's
executor: each valid road wogan's search proposes is handed to the pipeline's own executor
(BeamNG.AI, DAVE-2, or any other), and the drive's largest `oob_percentage`, outcome and
simulated time go back to wogan, which learns from them. The pipeline keeps its budgets, files
and analysis as for any generator. wogan talks to this process through two named pipes and a
small relay (relay.py) that wogan starts as its executor; this process serves the executor
protocol on them with the `wogan` Python package's `wogan.Executor` (python/README.md).

Settings through the environment (the pipeline passes only executor and map size):
  WOGAN              the wogan binary (default: `wogan` on PATH)
  WOGAN_ORACLE       the oob tolerance and speed of the search's judge: beamng-ai-proxy (0.85,
                     70 km/h, the default) or dave2-proxy (0.10, 25 km/h); match the pipeline's
  WOGAN_SEED         the search's seed (default 0)
  WOGAN_OUT          where wogan writes its run file (default: wogan-run.jsonl in the current folder)
  WOGAN_ARGS         more `wogan run` options, e.g. "--mutation-share 0.25"
"""
import logging as log
import os
import shlex
import subprocess
import sys
import tempfile
import threading

from code_pipeline.tests_generation import RoadTestFactory

HERE = os.path.dirname(os.path.abspath(__file__))
# Without the package installed (`pip install .` in wogan's checkout), it is found in the checkout.
sys.path.append(os.path.join(HERE, "..", "..", "python"))
import wogan  # noqa: E402


def largest_bolp(execution_data):
    """The drive's largest share of the car outside its lane, as the pipeline records it."""
    values = [getattr(record, "oob_percentage", 0.0) or 0.0 for record in execution_data or []]
    return min(1.0, max(0.0, max(values, default=0.0)))


class WoganGenerator:
    def __init__(self, executor=None, map_size=None):
        self.executor = executor
        self.map_size = map_size
        self.wogan = None

    def command(self, roads_fifo, answers_fifo):
        relay = f"{shlex.quote(sys.executable)} {shlex.quote(os.path.join(HERE, 'relay.py'))} " \
                f"{shlex.quote(roads_fifo)} {shlex.quote(answers_fifo)}"
        return [os.environ.get("WOGAN", "wogan"), "run",
                "--oracle", os.environ.get("WOGAN_ORACLE", "beamng-ai-proxy"),
                "--map-size", str(self.map_size),
                "--seed", os.environ.get("WOGAN_SEED", "0"),
                "--quiet"] + self.budget_options() + [
                "--out", os.environ.get("WOGAN_OUT", "wogan-run.jsonl"),
                "--executor", f"cmd:{relay}",
                # The pipeline's own simulator may take long per road.
                "--executor-timeout", "30m"] + shlex.split(os.environ.get("WOGAN_ARGS", ""))

    def budget_options(self):
        """The pipeline's budgets, so that wogan's schedule (its random share, the bias of its
        batches) follows them; the pipeline's own accounting ends the run."""
        budget = getattr(self.executor, "time_budget", None)
        generation = getattr(budget, "generation_budget", None)
        execution = getattr(budget, "execution_budget", None)
        total = getattr(budget, "time_budget", None)
        if generation and execution:
            return ["--generation-budget", str(generation), "--execution-budget", str(execution)]
        if total:
            return ["--budget", f"{total}s"]
        return ["--budget", "48h"]

    def start(self):
        folder = tempfile.mkdtemp(prefix="wogan-pipeline-")
        roads_fifo = os.path.join(folder, "roads")
        answers_fifo = os.path.join(folder, "answers")
        os.mkfifo(roads_fifo)
        os.mkfifo(answers_fifo)
        self.wogan = subprocess.Popen(self.command(roads_fifo, answers_fifo))
        threading.Thread(target=self.unblock_when_wogan_ends, args=(roads_fifo, answers_fifo),
                         daemon=True).start()
        try:
            # The relay opens the roads pipe first, then the answers pipe: the same order here.
            with open(roads_fifo) as roads, open(answers_fifo, "w") as answers:
                try:
                    PipelineDrives(self.executor).serve(roads, answers)
                finally:
                    # Before the pipes close: a road cut short by the pipeline's budget is then
                    # not reported by wogan, as the pipeline does not keep it either.
                    self.stop()
        finally:
            self.stop()
        if self.wogan.returncode not in (0, 130, -15):
            raise RuntimeError(f"wogan ended with exit status {self.wogan.returncode}; its stderr says why")

    def unblock_when_wogan_ends(self, roads_fifo, answers_fifo):
        """When wogan ends before its relay opened the pipes (bad options, say), opens their other
        ends so that start() is not left waiting for it."""
        self.wogan.wait()
        for path, mode in ((roads_fifo, os.O_WRONLY), (answers_fifo, os.O_RDONLY)):
            try:
                os.close(os.open(path, mode | os.O_NONBLOCK))
            except OSError:
                pass

    def stop(self):
        if self.wogan is not None and self.wogan.poll() is None:
            self.wogan.terminate()
            try:
                self.wogan.wait(timeout=30)
            except subprocess.TimeoutExpired:
                self.wogan.kill()
                self.wogan.wait()


class PipelineDrives(wogan.Executor):
    """wogan's executor, on the pipes: each road through the pipeline's executor."""

    def __init__(self, executor):
        super().__init__()
        self.executor = executor

    def drive(self, road):
        the_test = RoadTestFactory.create_road_test(list(road.points))
        # The pipeline ends the run from inside execute_test (sys.exit) when a budget is spent.
        outcome, description, execution_data = self.executor.execute_test(the_test)
        log.info("wogan road %s as pipeline test %s: %s", road.id, the_test.id, outcome)
        timer = execution_data[-1].timer if execution_data else 0.0
        return wogan.Answer(max_bolp=largest_bolp(execution_data),
                            outcome=outcome if outcome in ("PASS", "FAIL") else "ERROR",
                            sim_time_s=max(0.0, float(timer)))

    def drive_failed(self, road, error):
        # The pipeline's own faults end the generation (as its sys.exit does), not just one road.
        raise error
