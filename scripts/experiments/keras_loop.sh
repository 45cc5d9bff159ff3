#!/usr/bin/env bash
# The loop closed (issue 63): frames from wogan's world (`wogan dataset`), a Keras DAVE-2 trained
# on them the Udacity course's way (train_keras_dave2.py, tensorflow-cpu 2.15), converted without
# TensorFlow (examples/onnx/keras_to_onnx.py), then tested under the `udacity` contract: its
# failures on the 300 reference roads against dave2-proxy's, and WOGAN against random search on it
# (300 tests, 5 seeds). Everything goes to target/keras-loop/; a step whose output exists is kept.
#
#   scripts/experiments/keras_loop.sh [FRAMES] [EPOCHS] [STEPS] [SEEDS]
#   scripts/experiments/keras_loop.sh 20000 6 300 "1 2 3 4 5"
#
# Needs target/keras-venv (python3 -m venv target/keras-venv && target/keras-venv/bin/pip install
# tensorflow-cpu==2.15.1 "numpy<2" h5py pillow opencv-python-headless==4.10.0.84) and
# target/onnx-venv (examples/onnx/setup.sh). WOGAN=path uses another binary.
set -euo pipefail
cd "$(dirname "$0")/../.."
frames=${1:-20000}
epochs=${2:-6}
steps=${3:-300}
seeds=${4:-1 2 3 4 5}
out=target/keras-loop
mkdir -p "$out"
if [ -z "${WOGAN:-}" ]; then
  cargo build --release -q -p wogan-cli
  WOGAN=target/release/wogan
fi
udacity="$out/udacity.json"
echo '{"driver": {"contract": "udacity"}}' > "$udacity"

# 1. Frames: beamng-ai-proxy at the course's 25 mph limit on random roads.
[ -f "$out/data/driving_log.csv" ] && [ "$(wc -l < "$out/data/driving_log.csv")" -ge "$frames" ] \
  || { rm -rf "$out/data"; "$WOGAN" dataset --out "$out/data" --frames "$frames" --seed 1 --speed-limit 40; }
# 2. Training, 3. conversion.
[ -f "$out/dave2.h5" ] || target/keras-venv/bin/python scripts/experiments/train_keras_dave2.py \
  "$out/data" "$out/dave2.h5" --epochs "$epochs" --steps "$steps" > "$out/training.log" 2>&1
[ -f "$out/dave2.onnx" ] || target/onnx-venv/bin/python examples/onnx/keras_to_onnx.py "$out/dave2.h5" "$out/dave2.onnx"
# 4. The 300 reference roads, by the trained network and by dave2-proxy.
[ -s "$out/reference.keras.jsonl" ] || "$WOGAN" simulate --oracle "onnx:$out/dave2.onnx" \
  --config "$udacity" --jobs 2 tests/reference/roads.jsonl > "$out/reference.keras.jsonl"
[ -s "$out/reference.dave2-proxy.jsonl" ] || "$WOGAN" simulate --oracle dave2-proxy --jobs 2 \
  tests/reference/roads.jsonl > "$out/reference.dave2-proxy.jsonl"
for driver in keras dave2-proxy; do
  echo "$driver: $(grep -c '"outcome":"FAIL"' "$out/reference.$driver.jsonl") of 300 reference roads fail"
done
# 5. WOGAN and random search against it.
for algorithm in random wogan; do
  for seed in $seeds; do
    file="$out/$algorithm.$seed.jsonl"
    if [ -f "$file" ] && tail -n 1 "$file" | grep -q '"type":"summary"'; then continue; fi
    "$WOGAN" run --quiet --algorithm "$algorithm" --max-tests 300 --seed "$seed" \
      --oracle "onnx:$out/dave2.onnx" --config "$udacity" --out "$file"
  done
done
"$WOGAN" report "$out"/wogan.*.jsonl --vs "$out"/random.*.jsonl --table
