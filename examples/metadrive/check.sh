#!/usr/bin/env bash
# Dev-time smoke check of the MetaDrive executor (run examples/metadrive/setup.sh first):
#  1. protocol lines piped in: hello is answered first (protocol version 3); a straight road
#     PASSes, a tight left U-turn FAILs out of its lane with an oob_side, a road that is no road
#     is answered ERROR, with idm; the straight road PASSes with expert;
#  2. BOLP as wogan's lane monitor has it: the executor's lane monitor on the samples of
#     `wogan simulate --trace` gives wogan's BOLP;
#  3. `wogan run --executor ... --jobs 2 --max-tests 20`: every test answered, no executor left;
#  4. faults: a MetaDrive exception, a hang and a crash each end one road ERROR, the run goes on;
#  5. the cost: roads of that run (75 m) driven by one idm executor, roads per wall second.
# Environment: WOGAN (default target/release/wogan), TESTS (default 20).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
cd "$root"
py=target/metadrive-venv/bin/python
executor=examples/metadrive/executor.py
wogan=${WOGAN:-target/release/wogan}
tests=${TESTS:-20}
work=$(mktemp -d "${TMPDIR:-/tmp}/wogan-metadrive-check.XXXXXX")
trap 'rm -rf "$work"' EXIT
failures=0

[[ -x $py ]] || { echo "check.sh: no $py: run examples/metadrive/setup.sh" >&2; exit 1; }
[[ -x $wogan ]] || { echo "check.sh: no wogan binary at $wogan (set WOGAN)" >&2; exit 1; }

ok() { echo "ok   $*"; }
bad() { echo "FAIL $*"; failures=$((failures + 1)); }
executors() { pgrep -f "$executor" | sort || true; }

hello='{"type":"hello","protocol":"wogan-executor","version":3,"units":"metres, seconds","map_size_m":200.0,"oob_tolerance":0.85,"speed_limit_kmh":70.0}'
straight='[[100.0,10.0],[100.0,25.0],[100.0,40.0],[100.0,55.0],[100.0,70.0],[100.0,85.0]]'
u_turn='[[100.0,10.0],[100.0,25.0],[90.0,35.0],[75.0,35.0],[65.0,25.0],[65.0,10.0]]'

# Checks the reply to hello, then the answer lines (file $1) against expectations "ID:OUTCOME[:SIDE]".
expect() {
    "$py" - "$@" <<'EOF'
import json, sys
lines = [json.loads(line) for line in open(sys.argv[1])]  # stdout must hold protocol lines only
reply = lines.pop(0) if lines else None
if not (isinstance(reply, dict) and reply.get("type") == "hello" and reply.get("version") == 3
        and reply.get("executor", {}).get("name") == "wogan-metadrive-executor"):
    print(f"FAIL the first line is no reply to hello: {json.dumps(reply)}")
    sys.exit(1)
print(f"ok   reply to hello: {json.dumps(reply['executor'])}")
answers = {}
for a in lines:
    answers[a["id"]] = a
for spec in sys.argv[2:]:
    road, outcome, *side = spec.split(":")
    a = answers.get(int(road))
    got = a and (a["outcome"], a.get("oob_side"))
    want = (outcome, side[0] if side else None)
    verdict = "ok  " if got == want and 0.0 <= a["max_bolp"] <= 1.0 else "FAIL"
    print(f"{verdict} road {road}: want {want}, got {json.dumps(a)}")
    if verdict == "FAIL":
        sys.exit(1)
EOF
}

echo "== 1. protocol lines"
before=$(executors)
printf '%s\n' "$hello" \
    "{\"type\":\"road\",\"id\":1,\"road_points\":$straight}" \
    "{\"type\":\"road\",\"id\":2,\"road_points\":$u_turn}" \
    '{"type":"road","id":3,"road_points":[[100.0,10.0],[100.0,10.0]]}' \
    '{"type":"bye"}' | "$py" $executor --policy idm 2>"$work/idm.err" >"$work/idm.out" \
    && expect "$work/idm.out" 1:PASS 2:FAIL:right 3:ERROR || bad "idm on piped roads (stderr: $work/idm.err)"
printf '%s\n' "$hello" "{\"type\":\"road\",\"id\":1,\"road_points\":$straight}" '{"type":"bye"}' \
    | "$py" $executor --policy expert 2>"$work/expert.err" >"$work/expert.out" \
    && expect "$work/expert.out" 1:PASS || bad "expert on a straight road"

echo "== 2. BOLP against wogan's lane monitor"
"$wogan" run --algorithm random --max-tests 40 --seed 3 --quiet --out "$work/own.jsonl"
"$py" -c '
import json, sys
tests = [t for t in map(json.loads, open(sys.argv[1])) if t["type"] == "test"]
for t in [t for t in tests if t["max_bolp"] > 0.05][:3]:
    print(json.dumps(t["road_points"]))' "$work/own.jsonl" >"$work/bolp-roads.txt"
"$wogan" simulate --trace "$work/trace" "$work/bolp-roads.txt" >/dev/null
PYTHONPATH=examples/metadrive "$py" - "$work"/trace/trace.*.jsonl <<'EOF' || bad "BOLP differs from wogan's"
import json, sys
import numpy as np
from wogan_metadrive.lane_monitor import LaneMonitor
from wogan_metadrive.road import build_road
worst, samples = 0.0, 0
for name in sys.argv[1:]:
    lines = [json.loads(line) for line in open(name)]
    road = build_road(lines[0]["road_points"])
    assert np.array_equal(road.centre, np.array(lines[0]["interpolated_points"])), "interpolation differs"
    monitor = LaneMonitor(road, 4.6, 1.9, 1.0)  # wogan's car
    for s in lines[1:]:
        centre = np.array([s["x"], s["y"]])
        segment, lateral = monitor.project(centre)
        worst = max(worst, abs(monitor.bolp(centre, s["heading"], segment) - s["bolp"]),
                    abs(-lateral - s["dist_left_m"]))
        samples += 1
ok = samples > 0 and worst < 1e-9
print(f"{'ok  ' if ok else 'FAIL'} {samples} samples of {len(sys.argv) - 1} roads: largest difference {worst:.1e}")
sys.exit(0 if ok else 1)
EOF

echo "== 3. wogan run --executor, --jobs 2, $tests tests"
command="$py $executor --policy idm"
started=$EPOCHREALTIME
"$wogan" run --executor cmd:"$command" --max-tests "$tests" --jobs 2 --seed 1 --quiet \
    --out "$work/run.jsonl" 2>"$work/run.err" || bad "wogan run exited $? ($(tail -3 "$work/run.err"))"
run_wall=$("$py" -c "print($EPOCHREALTIME - $started)")
"$py" - "$work/run.jsonl" "$tests" <<'EOF' || bad "not every test was answered"
import json, sys
records = [json.loads(line) for line in open(sys.argv[1])]
tests = [r for r in records if r["type"] == "test"]
unanswered = [t["id"] for t in tests if t["outcome"] == "ERROR"]
failed = [t for t in tests if t["outcome"] == "FAIL"]
sides = sorted({t["oob"]["side"] for t in failed if t.get("oob")})
print(f"{len(tests)} tests: {len(tests) - len(failed) - len(unanswered)} PASS, {len(failed)} FAIL "
      f"(sides {sides}), {len(unanswered)} ERROR {unanswered}")
sys.exit(0 if len(tests) == int(sys.argv[2]) and not unanswered else 1)
EOF
sleep 1
left=$(comm -13 <(echo "$before") <(executors) | tr '\n' ' ')
[[ -z ${left// /} ]] && ok "no executor left after the run" || bad "executors left running: $left"

echo "== 4. faults: exception (road 2), hang (road 3), crash (road 4)"
for fault in exception:2 hang:3 crash:4; do
    WOGAN_METADRIVE_FAULT=$fault "$wogan" run \
        --executor cmd:"$command --road-wall-timeout 5" --max-tests 5 --seed 1 --quiet \
        --out "$work/fault.jsonl" 2>"$work/fault.err" || bad "wogan run with $fault exited $?"
    "$py" - "$work/fault.jsonl" "${fault#*:}" "$fault" <<'EOF' || bad "fault $fault"
import json, sys
tests = {t["id"]: t for t in map(json.loads, open(sys.argv[1])) if t["type"] == "test"}
road = int(sys.argv[2])
others = [t["outcome"] for i, t in tests.items() if i != road]
good = len(tests) == 5 and tests[road]["outcome"] == "ERROR" and "ERROR" not in others
print(f"{'ok  ' if good else 'FAIL'} {sys.argv[3]}: road {road} {tests[road]['outcome']}, the others {others}")
sys.exit(0 if good else 1)
EOF
done
sleep 1
left=$(comm -13 <(echo "$before") <(executors) | tr '\n' ' ')
[[ -z ${left// /} ]] && ok "no executor left after the faults" || bad "executors left running: $left"

echo "== 5. cost: the run's roads, one idm executor"
"$py" - "$work/run.jsonl" "$hello" >"$work/roads.jsonl" <<'EOF'
import json, sys
print(sys.argv[2])
for t in map(json.loads, open(sys.argv[1])):
    if t["type"] == "test":
        print(json.dumps({"type": "road", "id": t["id"], "road_points": t["road_points"]}))
print(json.dumps({"type": "bye"}))
EOF
started=$EPOCHREALTIME
"$py" $executor --policy idm <"$work/roads.jsonl" >"$work/cost.out" 2>"$work/cost.err"
total=$("$py" -c "print($EPOCHREALTIME - $started)")
"$py" - "$work/cost.out" "$total" "$run_wall" <<'EOF'
import json, sys
answers = [a for a in map(json.loads, open(sys.argv[1])) if a.get("type") != "hello"]  # after the reply
first, rest = answers[0], answers[1:]
driving = sum(a["wall_s"] for a in rest)
sim = sum(a["sim_time_s"] for a in rest)
print(f"{len(answers)} roads in {float(sys.argv[2]):.1f} s wall, the first (with MetaDrive's start) "
      f"{first['wall_s']:.2f} s; the other {len(rest)}: {len(rest) / driving:.1f} roads per wall "
      f"second ({driving / len(rest) * 1000:.0f} ms a road, {sim / driving:.0f}x real time)")
print(f"(wogan run --jobs 2 of the same {len(answers)} tests took {float(sys.argv[3]):.1f} s wall)")
EOF

echo
if ((failures)); then echo "$failures check(s) failed"; exit 1; fi
echo "all checks passed"
