#!/usr/bin/env bash
# What a pool of Ray actors buys (issue 71): `python -m wogan.ray` serving an executor whose drive
# sleeps as a real-time simulator would (its CPU idle), with 1, 8 and 32 actors on this machine.
# Lines for docs/results.md:
# - per pool size: tests per wall second, and the dispatch overhead per road (the wall time of a
#   road per actor, wall * actors / roads, minus the sleep), then the ratio of 32 actors to 1;
# - MetaDrive (when its venv, target/metadrive-venv, exists: examples/metadrive/setup.sh): one
#   `wogan run --algorithm random` over 2 actors against the same run with `--jobs 2` local
#   processes, tests per wall second of each (the pool's figure includes starting its Ray).
#
# The sleeping pools are driven through the executor protocol directly, as wogan drives an
# executor (hello, its reply, up to `roads_at_once` roads in flight matched by id, bye), so that
# the figures are the pool's alone: the clock starts at the reply to hello (the actors started)
# and stops at the last answer. Each pool is a private Ray (`--address local`), on loopback: the
# script runs itself in a network namespace of its own with loopback alone (unshare -n, as root).
#
#   PYTHON=venv/bin/python scripts/bench/ray_bench.sh [WOGAN_BINARY] | tee target/bench-output/ray.txt
#
# Each figure is a line of standard output starting "wogan " (Ray's own notes go to stderr).
#
# PYTHON: a Python with Ray (pip install '.[ray]'); SLEEP_S (default 1): a road's drive; ROUNDS
# (default 8): roads per actor; SIZES (default "1 8 32"); METADRIVE_TESTS (default 60).
set -euo pipefail
cd "$(dirname "$0")/../.."
metadrive=target/metadrive-venv
both=target/ray-metadrive-venv
if [ "${WOGAN_BENCH_NETNS:-}" != 1 ]; then
  # MetaDrive's pool runs a Python of its own: a venv of Ray (made here, from PyPI, before the
  # namespace cuts the network; kept) that also sees MetaDrive's venv's packages (a .pth file:
  # after its own), so that MetaDrive's venv stays as setup.sh made it.
  if [ -x "$metadrive/bin/python" ] && ! "$both/bin/python" -c "import ray, metadrive" 2> /dev/null; then
    python3 -m venv --clear "$both" && "$both/bin/pip" install -q "ray[default]>=2.9"
    "$metadrive/bin/python" -c 'import sysconfig; print(sysconfig.get_path("purelib"))' \
      > "$("$both/bin/python" -c 'import sysconfig; print(sysconfig.get_path("purelib"))')/metadrive-venv.pth"
  fi
  exec env WOGAN_BENCH_NETNS=1 unshare -n sh -c 'ip link set lo up && exec bash "$0" "$@"' "$0" "$@"
fi
wogan=$(realpath "${1:-target/release/wogan}")
python=${PYTHON:-python3}
sleep_s=${SLEEP_S:-1}
rounds=${ROUNDS:-8}
sizes=${SIZES:-1 8 32}
metadrive_tests=${METADRIVE_TESTS:-60}
work=$(realpath -m target/ray-bench)
rm -rf "$work" && mkdir -p "$work"
# The checkout's package; Ray's token authentication off (loopback alone: no one to keep out; and
# no token written to ~/.ray by the private Rays).
export PYTHONPATH="$PWD/python${PYTHONPATH:+:$PYTHONPATH}" WOGAN_BIN="$wogan" RAY_AUTH_MODE=disabled

cat > "$work/sleeper.py" << 'EOF'
"""An executor whose drive sleeps $SLEEP_S seconds, as a simulator keeping to real time would."""
import os
import time

import wogan


class Sleeper(wogan.Executor):
    def drive(self, road):
        time.sleep(float(os.environ["SLEEP_S"]))
        return wogan.Answer(max_bolp=0.0, sim_time_s=float(os.environ["SLEEP_S"]))
EOF

cat > "$work/drive.py" << 'EOF'
"""Drives ROADS roads through `python -m wogan.ray --actors ACTORS` as wogan does, up to
`roads_at_once` in flight; prints one JSON line: actors, roads, wall_s (reply to hello .. last
answer), tests_per_s, overhead_ms (wall * actors / roads - SLEEP_S, milliseconds)."""
import json
import subprocess
import sys
import time

actors, roads, sleep_s, spec = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
pool = subprocess.Popen([sys.executable, "-m", "wogan.ray", "--address", "local", "--actors", str(actors),
                         "--actor-cpus", "0.05", "--env", f"SLEEP_S={sleep_s}", "--log-level", "WARNING", spec],
                        stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)


def send(message):
    pool.stdin.write(json.dumps(message) + "\n")
    pool.stdin.flush()


road = [[100.0, 10.0], [100.0, 25.0], [99.9, 40.0], [95.5, 54.3]]
send({"type": "hello", "protocol": "wogan-executor", "version": 3, "units": "metres, seconds",
      "map_size_m": 200.0, "oob_tolerance": 0.85, "speed_limit_kmh": 70.0})
at_once = json.loads(pool.stdout.readline())["roads_at_once"]
started, sent, answered = time.monotonic(), 0, set()
while sent < min(at_once, roads):
    sent += 1
    send({"type": "road", "id": sent, "road_points": road})
while len(answered) < roads:
    answer = json.loads(pool.stdout.readline())
    assert answer["id"] not in answered and answer.get("outcome") != "ERROR", answer
    answered.add(answer["id"])
    if sent < roads:
        sent += 1
        send({"type": "road", "id": sent, "road_points": road})
wall = time.monotonic() - started
send({"type": "bye"})
pool.stdin.close()
assert pool.wait(timeout=120) == 0
print(json.dumps({"actors": actors, "roads": roads, "wall_s": round(wall, 3), "tests_per_s": round(roads / wall, 3),
                  "overhead_ms": round((wall * actors / roads - sleep_s) * 1000, 1)}))
EOF

declare -A rate=()
for actors in $sizes; do
  line=$("$python" "$work/drive.py" "$actors" $((rounds * actors)) "$sleep_s" "$work/sleeper.py:Sleeper")
  rate[$actors]=$(jq -r .tests_per_s <<< "$line")
  jq -r --arg s "$sleep_s" '"wogan executor python -m wogan.ray --actors \(.actors) (drive sleeps \($s) s, \(.roads) roads): \(.tests_per_s) tests per wall second, dispatch overhead \(.overhead_ms) ms per road"' <<< "$line"
done
if [ -n "${rate[1]:-}" ] && [ -n "${rate[32]:-}" ]; then
  awk -v a="${rate[1]}" -v b="${rate[32]}" \
    'BEGIN {printf "wogan executor python -m wogan.ray: 32 actors give %.1fx the tests per wall second of 1 (at least 20x wanted)\n", b / a}'
fi

if [ ! -x "$metadrive/bin/python" ]; then
  echo "wogan run MetaDrive: skipped ($metadrive is missing: bash examples/metadrive/setup.sh makes it)"
  exit 0
fi
executor=examples/metadrive/executor.py
args=(--algorithm random --max-tests "$metadrive_tests" --seed 1 --jobs 2 --quiet)
"$wogan" run "${args[@]}" --out "$work/metadrive.local.jsonl" \
  --executor "cmd:$metadrive/bin/python $executor --policy idm"
"$wogan" run "${args[@]}" --out "$work/metadrive.ray.jsonl" \
  --executor "cmd:$both/bin/python -m wogan.ray --address local --actors 2 --log-level WARNING --init '{\"policy\": \"idm\", \"wall_timeout_s\": 300}' $executor:MetaDriveExecutor"
for how in local ray; do
  jq -r --arg how "$how" --arg n "$metadrive_tests" 'select(.type == "summary") | "wogan run --algorithm random --max-tests \($n) --jobs 2, MetaDrive (idm) \(if $how == "ray" then "as 2 Ray actors (--address local, its start included)" else "as 2 local processes" end): \(.executed) tests in \(.wall_s * 100 | round / 100) s, \(.executed / .wall_s * 1000 | round / 1000) tests per wall second"' "$work/metadrive.$how.jsonl"
done
