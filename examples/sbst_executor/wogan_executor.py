"""An executor for the SBST 2022 tool competition's pipeline (se2p/tool-competition-av) that drives
every test in one long-lived `wogan simulate` child instead of BeamNG.

Protocol: one JSON line per test in ({"road_points": ...}), one JSON line out (`wogan simulate`
in wogan's docs/reference.md).
The pipeline validates each road and keeps the budgets; this class only drives valid roads.
"""
import json
import logging as log
import subprocess

from code_pipeline.executors import AbstractTestExecutor
from self_driving.simulation_data import SimulationDataRecord

# How a failed drive is described. The pipeline counts a failure as an OBE only when its description
# starts with exactly this prefix (trailing space included), as BeamNG's executor writes it.
OUT_OF_LANE = "Car drove out of the lane "
OTHER_FAILURES = {
    "not_moving": "Car is not moving fast enough",
    "timeout": "Car did not reach the end of the road in time",
}


class WoganError(RuntimeError):
    """The child died or answered something that is not an answer to the road we sent."""


class WoganExecutor(AbstractTestExecutor):

    def __init__(self, result_folder, map_size,
                 generation_budget=None, execution_budget=None, time_budget=None,
                 oob_tolerance=None, max_speed_in_kmh=None,
                 road_visualizer=None, debug=False,
                 wogan="wogan", oracle="beamng-ai-proxy"):
        # `wogan` is the binary's path or a command as a list (e.g. ["python3", "fake.py"]).
        # None for oob_tolerance / max_speed_in_kmh keeps the oracle's own defaults; note that
        # competition.py always passes its CLI values (--oob-tolerance defaults to 0.95 there).
        command = [wogan] if isinstance(wogan, str) else list(wogan)
        command += ["simulate", "--oracle", oracle, "--map-size", str(map_size), "--execution-data"]
        if oob_tolerance is not None:
            command += ["--oob-tolerance", str(oob_tolerance)]
        if max_speed_in_kmh is not None:
            command += ["--speed-limit", str(int(max_speed_in_kmh))]
        # The child is started BEFORE super().__init__(), which starts the budget clock. Its start-up
        # is thus charged to no budget, as with BeamngExecutor, which starts BeamNG inside its first
        # _execute(), time that the pipeline does not count as generation time. (It takes milliseconds.)
        self.child = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                      text=True, bufsize=1)  # stderr is inherited: wogan's errors show
        self.lines_sent = 0
        self.last_answer = None  # the full answer to the last test (max_bolp, oob, features...)
        try:
            super().__init__(result_folder, map_size, generation_budget=generation_budget,
                             execution_budget=execution_budget, time_budget=time_budget,
                             road_visualizer=road_visualizer, debug=debug)
        except BaseException:
            self.child.kill()
            self.child.wait()
            raise

    def _execute(self, the_test):
        # The pipeline's own check: sys.exit(123) when no budget is left (competition.py then
        # post-processes the results from an exit hook).
        super()._execute(the_test)
        answer = self._ask(the_test)
        self.last_answer = answer
        outcome, reason = answer.get("outcome"), answer.get("reason")

        if answer["type"] == "error" or outcome == "INVALID":
            # The pipeline validated this road already; a road wogan cannot drive is an ERROR.
            return "ERROR", answer.get("message") or answer.get("error") or str(reason), []
        if outcome not in ("PASS", "FAIL", "ERROR"):
            raise WoganError(f"wogan answered test {the_test.id} with unknown outcome {outcome!r}")

        # The pipeline charges the simulated time of a test as the `timer` of its last record,
        # which here is wogan's simulated seconds (equal to sim_time_s).
        try:
            execution_data = [SimulationDataRecord(*entry) for entry in answer["execution_data"]]
        except (KeyError, TypeError) as error:
            raise WoganError(f"wogan's answer to test {the_test.id} has no usable execution_data "
                             f"({error}); is the binary new enough for --execution-data?") from None
        if not execution_data:
            raise WoganError(f"wogan's answer to test {the_test.id} has empty execution_data")

        if outcome == "PASS":
            return "PASS", "Successful test", execution_data
        if outcome == "ERROR":
            return "ERROR", answer.get("message") or f"Simulation error: {reason}", execution_data
        if reason == "out_of_lane":
            oob = answer.get("oob") or {}
            where = (f"at t={oob['t_s']:.2f} s, ({oob['x']:.1f}, {oob['y']:.1f}), {oob['side']} side "
                     if {"t_s", "x", "y", "side"} <= oob.keys() else "")
            # OOBAnalyzer (oob_stats.csv) only looks at tests whose outcome is exactly "FAIL".
            return "FAIL", f"{OUT_OF_LANE}{where}(wogan test {the_test.id})", execution_data
        return "FAIL", OTHER_FAILURES.get(reason, f"Test failed: {reason}"), execution_data

    def _ask(self, the_test):
        """Send one road, read one answer; anything else is a WoganError naming the test."""
        points = [[float(x), float(y)] for x, y in the_test.road_points]
        try:
            self.child.stdin.write(json.dumps({"road_points": points}) + "\n")
            self.child.stdin.flush()
            line = self.child.stdout.readline()
        except (BrokenPipeError, ValueError):  # ValueError: the pipe was closed already
            line = ""
        self.lines_sent += 1
        if not line:
            self.child.poll()
            raise WoganError(f"wogan simulate (pid {self.child.pid}) ended before answering test "
                             f"{the_test.id} (exit status {self.child.returncode})")
        try:
            answer = json.loads(line)
        except ValueError:
            answer = None
        if (not isinstance(answer, dict) or answer.get("type") not in ("result", "error")
                or answer.get("line") != self.lines_sent):
            raise WoganError(f"wogan simulate answered test {the_test.id} with garbage: {line[:200]!r}")
        return answer

    def _close(self):
        # Closing stdin is wogan's signal to finish: it answers what it has read and exits 0.
        if not self.child.stdin.closed:
            try:
                self.child.stdin.close()
            except BrokenPipeError:
                pass
        try:
            self.child.wait(timeout=10)
        except subprocess.TimeoutExpired:
            log.warning("wogan simulate (pid %d) did not exit; killing it", self.child.pid)
            self.child.kill()
            self.child.wait()
        self.child.stdout.close()
        if self.child.returncode != 0:
            log.warning("wogan simulate exited with status %s", self.child.returncode)
        super()._close()
