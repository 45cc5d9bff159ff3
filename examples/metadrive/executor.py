#!/usr/bin/env python3
"""A wogan executor that drives each road in MetaDrive (metadrive-simulator 0.4.3, Bullet physics,
headless, no GPU, no assets): `wogan run --executor cmd:"PYTHON executor.py --policy idm"`.

It is a `wogan.Executor` (the `wogan` Python package, python/README.md), which speaks the executor
protocol, version 3 (wogan's docs/reference.md, "Plug points: your own simulator"): JSON lines on
standard input (`hello`, one `road` per test, `bye`), on standard output one reply to `hello` (the
executor's name and its settings: policy, speed limit, tolerance, MetaDrive's version...) and one
answer line per road, nothing else there (MetaDrive's own output goes to standard error with the
logs). Set up by `examples/metadrive/setup.sh`, which makes `target/metadrive-venv`.

The road, as wogan's simulator has it (crates/road-sim/src):
- The centre line is the competition's spline through `road_points` (FITPACK's `splprep(s=0)`, a
  line through 2 points, a parabola through 3, the not-a-knot cubic through more), sampled about
  every metre and rounded to 3 decimals (road/spline.rs). The road is two 4 m lanes either side of
  it (road/geometry.rs; `--lane-width` makes them narrower or wider); the car drives in the right
  one.
- The car starts at rest on the right lane's centre 2.5 m along the centre line from the first
  point, heading along the road (sim/config.rs `start_offset_m`, sim/episode.rs `start_pose`).

In MetaDrive that road is a scenario description given to `ScenarioOnlineEnv.set_scenario`: two
lanes (the right lane's centre line forward, the left lane's backward, each with its 4 m polygon), a
solid yellow centre line, the two road edges, and the ego track (the car's route, which MetaDrive's
policies follow): the start pose, then the right lane's centre to the road's end. The scenario is
laid in a frame whose origin is the start (MetaDrive moves its origin there anyway), so a MetaDrive
position plus the start is a point of wogan's map. No traffic, no lights, a new map per road.

The driver (`--policy`):
- `idm`: MetaDrive's `IDMPolicy` (a PID steering onto the route, IDM throttle) with its target speed
  set to the speed limit of `hello` and lane changes off. Control at 10 Hz (MetaDrive's
  `decision_repeat` 5 of 0.02 s physics steps).
- `expert`: MetaDrive's PPO expert (`metadrive.examples.ppo_expert`, weights shipped in the
  package, numpy inference), its mean action (deterministic), the throttle cut above the speed
  limit. The expert wants the 275-value LiDAR-state observation of MetaDrive's procedural (PG)
  maps: 9 ego values, 10 navigation values (two checkpoints of 5), 240 LiDAR rays and 16 values of
  the 4 nearest cars. `ScenarioOnlineEnv`'s navigation (`TrajectoryNavigation`) gives 22
  navigation values, so this executor gives the car `ExpertNavigation`: the route cut into pieces
  that turn one way (as a PG map's blocks are straights and arcs), each described as a PG block
  (checkpoint at its end, bend radius, direction, angle), the road one 4 m lane wide.

The measures, sampled at every physics step (50 Hz):
- BOLP: the share of the car's footprint (MetaDrive's car: its box, `LENGTH` x `WIDTH`, at its
  position and heading) outside the right lane's polygon, as wogan's lane monitor measures it
  (sim/lane_monitor.rs): the lane's window from 6 centre-line points behind the car's projection to
  7 ahead (centre line forward, right edge back), extended 10 m straight back behind the first
  point, intersected with the box by shapely. `max_bolp` is its largest value.
- The drive ends as wogan's (sim/episode.rs): FAIL `out_of_lane` when BOLP exceeds the tolerance of
  `hello` (`oob_side` "left" when the car's centre is nearer the centre line than the road's
  outer edge, i.e. left of the right lane's centre, else "right"); PASS when the car centre is
  within 8 m of the road's last point having got within 25 centre-line points of it along the road;
  FAIL `not_moving` when the car has moved less than 1 m in 10 s; FAIL `timeout` after
  20 s + length / (2 m/s). MetaDrive's own ends (arrival, out of road) are ignored.
- `sim_time_s`: simulated seconds until the end.

Answers carry `id`, `max_bolp`, `outcome`, `sim_time_s`, `min_lane_distance_m` (the smallest
signed distance of the car centre to the right lane's edges over the samples, as wogan's lane
monitor measures it, so that `--fitness distance` searches MetaDrive), `oob_side` and `oob_point`
(FAIL out of lane only: the side, and the car centre in wogan's frame at the first sample past the tolerance),
`error` (ERROR only: kept in the test record) and, for people reading them (wogan ignores them),
`reason`, `policy` and `wall_s`. With `--execution-data` (for the SBST pipeline's generators in
scripts/peers, which read the drive) an answer also carries `execution_data`: one array per sample
of the pipeline's 17 `SimulationDataRecord` fields, as `wogan simulate --execution-data` gives.

Faults: a road whose geometry cannot be built, or a MetaDrive exception while building or driving
it, answers that road `ERROR` with the message in `error`; MetaDrive is then closed, and started
again for the next road. A road taking longer than `--road-wall-timeout` seconds of wall time (a
hang in Python code) is answered the same way. A crash of the process, or a hang inside native
code, is left to wogan: `--executor-timeout`, then a new executor. `bye`, end of input, SIGTERM and
SIGINT close MetaDrive and exit; MetaDrive starts no other process.

This file is the entry point; the code is the package beside it, `wogan_metadrive/` (its modules:
README.md, "Layout"). wogan's numbers above (lane width, start offset, end distance, time limit...)
are read from docs/protocols/wogan-simulator-constants.json, which wogan writes.
"""
import os
import sys

# The package beside this file: found when the file is run (its folder is then first on sys.path)
# and when it is loaded by path (wogan.ray's `FILE.py:CLASS`), from any working directory.
_HERE = os.path.dirname(os.path.abspath(__file__))
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)

# MetaDriveExecutor is named here for `python -m wogan.ray ... examples/metadrive/executor.py:MetaDriveExecutor`.
from wogan_metadrive.executor import MetaDriveExecutor, main  # noqa: E402

__all__ = ["MetaDriveExecutor", "main"]

if __name__ == "__main__":
    sys.exit(main(description=__doc__.split("\n\n")[0]))
