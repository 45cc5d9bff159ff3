#!/usr/bin/env bash
# What a plug point costs (issue 36), wall seconds, medians of 3. Lines for docs/results.md:
# - the executor: the same 300-test search (beamng-ai-proxy, seed 1) with wogan's own simulator and
#   with `wogan simulate` as its external executor (a JSON line out, the drive, a line back);
# - the controller: the first 100 reference roads driven by beamng-ai-proxy and by
#   examples/controllers/pure_pursuit.py through the controller protocol (a step line out and a
#   command back at 20 Hz): steps per second and the cost of a whole road;
# - the camera network: the same 100 roads driven by dave2-proxy (its network in plain Rust) and
#   by the same network exported to ONNX (tests/fixtures/onnx/dave2-proxy.onnx, run by tract under
#   the settings that make it dave2-proxy), one job each: the cost of a road (goal: within 2x).
#
#   scripts/bench/plug_points_bench.sh | tee target/bench-output/plug-points.txt
set -euo pipefail
cd "$(dirname "$0")/../.."
wogan=$(realpath "${1:-target/release/wogan}")
work=target/plug-points-bench
rm -rf "$work" && mkdir -p "$work"
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
wall() { # COMMAND...: wall seconds
  local start end
  start=$(date +%s.%N)
  "$@" > /dev/null
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN {print b - a}'
}
own=() outside=()
for i in 1 2 3; do
  own+=("$(wall "$wogan" run --max-tests 300 --seed 1 --quiet --out "$work/own.$i.jsonl")")
  outside+=("$(wall "$wogan" run --max-tests 300 --seed 1 --quiet --out "$work/executor.$i.jsonl" \
    --executor "cmd:$wogan simulate")")
done
a=$(printf '%s\n' "${own[@]}" | median)
b=$(printf '%s\n' "${outside[@]}" | median)
same=$(cmp -s <(jq -c 'select(.type=="test") | [.outcome,.max_bolp]' "$work/own.1.jsonl") \
  <(jq -c 'select(.type=="test") | [.outcome,.max_bolp]' "$work/executor.1.jsonl") && echo yes || echo no)
echo "wogan run --max-tests 300 (beamng-ai-proxy): $a s wall with its own simulator, $b s with --executor cmd:\"wogan simulate\" ($(awk -v a="$a" -v b="$b" 'BEGIN {printf "%.2f", (b - a) / 300 * 1000}') ms more per road: the executor protocol's round trip); the same tests and outcomes: $same"

roads=$work/roads.jsonl
head -n 100 tests/reference/roads.jsonl > "$roads"
controller="cmd:python3 $(pwd)/examples/controllers/pure_pursuit.py"
builtin=() piped=()
for i in 1 2 3; do
  builtin+=("$(wall "$wogan" simulate --oracle beamng-ai-proxy "$roads")")
  start=$(date +%s.%N)
  "$wogan" simulate --oracle "$controller" "$roads" > "$work/controller.$i.jsonl"
  end=$(date +%s.%N)
  piped+=("$(awk -v a="$start" -v b="$end" 'BEGIN {print b - a}')")
done
c=$(printf '%s\n' "${builtin[@]}" | median)
d=$(printf '%s\n' "${piped[@]}" | median)
steps=$(jq -s '[.[].sim_time_s] | add * 20 | floor' "$work/controller.1.jsonl")
echo "wogan simulate of 100 reference roads: $c s wall with beamng-ai-proxy, $d s with the pure-pursuit controller process ($steps control steps through the protocol: $(awk -v s="$steps" -v d="$d" 'BEGIN {printf "%.0f", s / d}') steps per second; $(awk -v c="$c" 'BEGIN {printf "%.1f", c * 10}') ms against $(awk -v d="$d" 'BEGIN {printf "%.1f", d * 10}') ms per road)"

config=$work/onnx-as-proxy.json
echo '{"driver": {"crop_top_rows": 0, "crop_bottom_rows": 0, "throttle": "speed-controller"}}' > "$config"
proxy=() network=()
for i in 1 2 3; do
  proxy+=("$(wall "$wogan" simulate --oracle dave2-proxy --jobs 1 "$roads")")
  start=$(date +%s.%N)
  "$wogan" simulate --oracle onnx:tests/fixtures/onnx/dave2-proxy.onnx --config "$config" --jobs 1 "$roads" \
    > "$work/onnx.$i.jsonl"
  end=$(date +%s.%N)
  network+=("$(awk -v a="$start" -v b="$end" 'BEGIN {print b - a}')")
done
"$wogan" simulate --oracle dave2-proxy --jobs 1 "$roads" > "$work/proxy.jsonl"
e=$(printf '%s\n' "${proxy[@]}" | median)
f=$(printf '%s\n' "${network[@]}" | median)
same=$(cmp -s <(jq -c '.outcome' "$work/proxy.jsonl") <(jq -c '.outcome' "$work/onnx.1.jsonl") && echo yes || echo no)
echo "wogan simulate of 100 reference roads --jobs 1: $e s wall with dave2-proxy, $f s with onnx:tests/fixtures/onnx/dave2-proxy.onnx (the same network run by tract: $(awk -v e="$e" 'BEGIN {printf "%.1f", e * 10}') ms against $(awk -v f="$f" 'BEGIN {printf "%.1f", f * 10}') ms per road, $(awk -v e="$e" -v f="$f" 'BEGIN {printf "%.2f", f / e}')x); the same outcomes: $same"
