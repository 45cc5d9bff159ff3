#!/usr/bin/env bash
# `wogan report` on a run of 100,000 failing tests with lane exits (issue 74: the report's measures
# within a stated time whatever the run's size; docs/reference.md, `wogan report`). The run is
# made from a 100-test seeded run's failing tests, each copy turned about the map's centre by its
# own angle so that no two lane exits are alike (every exit profile and OOB segment differs: the
# costliest case for distinct failures and sparseness, which then measure their seeded samples).
# Prints wall seconds and peak memory (median of 3) for --table and for a report folder, at
# 5,000, 20,000 and 100,000 failing tests, as lines scripts/results/ keeps (section `report`):
#
#   scripts/bench/report_bench.sh [WOGAN] | tee target/bench-output/report.txt
set -euo pipefail
cd "$(dirname "$0")/../.."
wogan=$(realpath "${1:-target/release/wogan}")
work=target/report-bench
rm -rf "$work" && mkdir -p "$work"
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }

"$wogan" run --max-tests 100 --seed 1 --quiet --out "$work/seed.jsonl" || [ $? -eq 1 ]
for n in 5000 20000 100000; do
  python3 - "$work/seed.jsonl" "$work/failing.$n.jsonl" "$n" <<'PY'
import json, math, sys
source, target, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
records = [json.loads(line) for line in open(source)]
header = records[0]
failing = [r for r in records if r.get("type") == "test" and r.get("outcome") == "FAIL"]
if not failing:
    sys.exit("report_bench: the seed run has no failing test")

def turned(value, cos, sin):
    """Every [x, y] pair in value turned about the map's centre (100, 100)."""
    if isinstance(value, list) and len(value) == 2 and all(isinstance(v, (int, float)) for v in value):
        x, y = value[0] - 100.0, value[1] - 100.0
        return [100.0 + cos * x - sin * y, 100.0 + sin * x + cos * y]
    if isinstance(value, list):
        return [turned(v, cos, sin) for v in value]
    if isinstance(value, dict):
        return {k: turned(v, cos, sin) for k, v in value.items()}
    return value

with open(target, "w") as out:
    out.write(json.dumps(header) + "\n")
    for i in range(n):
        test = dict(failing[i % len(failing)])
        angle = 2.0 * math.pi * i / n
        cos, sin = math.cos(angle), math.sin(angle)
        test["id"] = i + 1
        test["road_points"] = turned(test["road_points"], cos, sin)
        if test.get("oob") is not None:
            test["oob"] = turned(test["oob"], cos, sin)
        out.write(json.dumps(test) + "\n")
    summary = next(r for r in records if r.get("type") == "summary")
    out.write(json.dumps(dict(summary, executed=n, failed=n)) + "\n")
PY
  for mode in table folder; do
    wall=() rss=()
    for i in 1 2 3; do
      if [ "$mode" = table ]; then args=(--table); else args=(--out "$work/out.$n"); fi
      /usr/bin/time -f "%e %M" -o "$work/time" "$wogan" report "$work/failing.$n.jsonl" "${args[@]}" \
        > /dev/null 2> "$work/stderr.$n.$mode" || [ $? -eq 1 ]
      read -r seconds kib < "$work/time"
      wall+=("$seconds") rss+=("$kib")
    done
    what="--table"; [ "$mode" = folder ] && what="--out DIR"
    echo "wogan report $what, one run of $n failing tests with lane exits: $(printf '%s\n' "${wall[@]}" | median) s wall, $(( $(printf '%s\n' "${rss[@]}" | median | cut -d. -f1) / 1024 )) MiB peak ($(nproc) cores; median of 3)"
  done
done
