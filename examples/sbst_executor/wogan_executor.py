"""An executor for the SBST 2022 tool competition's pipeline (se2p/tool-competition-av) that drives
every test in one long-lived `wogan simulate` child instead of BeamNG, through the `wogan` Python
package's `wogan.Simulator` (python/README.md): one road in, one answer out.

The pipeline validates each road and keeps the budgets; this class only drives valid roads.
"""
import logging as log
import os
import sys

from code_pipeline.executors import AbstractTestExecutor
from self_driving.simulation_data import SimulationDataRecord

# Without the package installed (`pip install .` in wogan's checkout), it is found in the checkout.
sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from wogan import Simulator, WoganError  # noqa: E402  (WoganError: the child died or answered junk)

# How a failed drive is described. The pipeline counts a failure as an OBE only when its description
# starts with exactly this prefix (trailing space included), as BeamNG's executor writes it.
OUT_OF_LANE = "Car drove out of the lane "
OTHER_FAILURES = {
    "not_moving": "Car is not moving fast enough",
    "timeout": "Car did not reach the end of the road in time",
}


class WoganExecutor(AbstractTestExecutor):

    def __init__(self, result_folder, map_size,
                 generation_budget=None, execution_budget=None, time_budget=None,
                 oob_tolerance=None, max_speed_in_kmh=None,
                 road_visualizer=None, debug=False,
                 wogan="wogan", oracle="beamng-ai-proxy"):
        # `wogan` is the binary's path or a command as a list (e.g. ["python3", "fake.py"]).
        # None for oob_tolerance / max_speed_in_kmh keeps the oracle's own defaults; note that
        # competition.py always passes its CLI values (--oob-tolerance defaults to 0.95 there).
        options = ["--oracle", oracle, "--map-size", str(map_size), "--execution-data"]
        if oob_tolerance is not None:
            options += ["--oob-tolerance", str(oob_tolerance)]
        if max_speed_in_kmh is not None:
            options += ["--speed-limit", str(int(max_speed_in_kmh))]
        # The child is started BEFORE super().__init__(), which starts the budget clock. Its start-up
        # is thus charged to no budget, as with BeamngExecutor, which starts BeamNG inside its first
        # _execute(), time that the pipeline does not count as generation time. (It takes milliseconds.)
        self.simulator = Simulator(options, binary=wogan)  # its stderr is ours: wogan's errors show
        self.child = self.simulator.process
        self.last_answer = None  # the full answer to the last test (max_bolp, oob, features...)
        try:
            super().__init__(result_folder, map_size, generation_budget=generation_budget,
                             execution_budget=execution_budget, time_budget=time_budget,
                             road_visualizer=road_visualizer, debug=debug)
        except BaseException:
            self.simulator.kill()
            raise

    def _execute(self, the_test):
        # The pipeline's own check: sys.exit(123) when no budget is left (competition.py then
        # post-processes the results from an exit hook).
        super()._execute(the_test)
        answer = self.simulator.drive(the_test.road_points, label=f"test {the_test.id}")
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

    def _close(self):
        # Closing its input is wogan's sign to finish: it answers what it has read and exits 0.
        status = self.simulator.close(timeout=10)
        if status != 0:
            log.warning("wogan simulate exited with status %s", status)
        super()._close()
