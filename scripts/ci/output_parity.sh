#!/usr/bin/env bash
# Writes the outputs of a fixed set of wogan commands into DIR, with every timing field masked, so
# that two builds can be compared with `diff -r`: a refactoring that keeps behaviour leaves them equal.
#
#   scripts/ci/output_parity.sh BIN DIR      e.g. scripts/ci/output_parity.sh target/release/wogan /tmp/after
#
# Masked fields (they measure the machine, not the result): generation_ms, execution_ms, wall_s,
# generation_s, training_s, simulation_s, train records' train_ms and the SBST charges of real time
# (sbst_generation_ms, sbst_generation_s); in the export's CSV, the real-time columns. The report
# names its run files as given, so they are given relative to the checkout.
set -euo pipefail
bin=$(realpath "$1")
out=$(realpath -m "$2")
here=$(cd "$(dirname "$0")/../.." && pwd)
roads=$here/tests/reference/roads.jsonl
mkdir -p "$out"
mask='walk(if type == "object" then with_entries(if (.key | IN("generation_ms","execution_ms","wall_s","generation_s","training_s","simulation_s","train_ms","sbst_generation_ms","sbst_generation_s")) then .value = "masked" else . end) else . end)'
masked() { jq -c "$mask"; }

for oracle in beamng-ai-proxy dave2-proxy; do
  "$bin" run --oracle "$oracle" --seed 7 --max-tests 40 --quiet --out "$out/run.$oracle.raw.jsonl"
  masked < "$out/run.$oracle.raw.jsonl" > "$out/run.$oracle.jsonl"
  head -n 20 "$roads" | "$bin" simulate --oracle "$oracle" | masked > "$out/simulate.$oracle.jsonl"
done
"$bin" run --algorithm random --seed 7 --max-tests 40 --quiet --out "$out/run.random.raw.jsonl"
masked < "$out/run.random.raw.jsonl" > "$out/run.random.jsonl"
head -n 1 "$roads" | "$bin" simulate --trace "$out/trace" > /dev/null
masked < "$out/trace/trace.1.jsonl" > "$out/trace.1.jsonl"
rm -r "$out/trace"
# Valid, invalid and unreadable lines.
{ head -n 50 "$roads"; echo '[[0, 0], [1, 1]]'; echo '{"curvature": [0.5, 0.5, 0.5]}'; echo 'not json'; } \
  | "$bin" validate > "$out/validate.jsonl" || true
# Reports and the export are made from the committed fixtures, whose timings are fixed.
(cd "$here" && "$bin" report tests/fixtures/wogan.seed*.jsonl --vs tests/fixtures/random.seed*.jsonl --out "$out/report" > /dev/null)
"$bin" export "$out/run.beamng-ai-proxy.raw.jsonl" "$out/export" > /dev/null
for f in "$out"/export/*.json; do jq -S "$mask" "$f" > "$f.masked" && mv "$f.masked" "$f"; done
# generation_stats.csv: keep the counts and the simulated time, drop the two real-time columns.
cut -d, -f1-6,9 "$out/export/generation_stats.csv" > "$out/export/generation_stats.masked.csv"
rm "$out/export/generation_stats.csv"
rm "$out"/run.*.raw.jsonl
echo "wrote $out"
