#!/usr/bin/env bash
# Makes target/onnx-venv: a Python venv with what keras_to_onnx.py needs (examples/onnx/
# requirements.txt, pinned: h5py, numpy, onnx; no TensorFlow), so that
#   target/onnx-venv/bin/python examples/onnx/keras_to_onnx.py IN.h5 OUT.onnx
# converts a model. Run from anywhere; idempotent (a complete venv of the same requirements is
# kept). Ends by checking the converter on the committed fixture (check_keras_to_onnx.py).
#
# Environment: PYTHON (default python3, 3.9 or later), FORCE=1 to rebuild the venv.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
venv="$root/target/onnx-venv"
requirements="$here/requirements.txt"
python=${PYTHON:-python3}
marker="$venv/.wogan-onnx-complete"

die() { echo "setup.sh: $*" >&2; exit 1; }

wanted=$(sha256sum "$requirements" | cut -d' ' -f1)
if [[ "${FORCE:-0}" != 1 && -f "$marker" && "$(cat "$marker")" == "$wanted" \
      && -x "$venv/bin/python" ]]; then
    echo "setup.sh: $venv is complete (requirements unchanged); FORCE=1 rebuilds it" >&2
    exit 0
fi
command -v "$python" >/dev/null || die "no $python (set PYTHON to a Python 3.9 or later)"
rm -rf "$venv"
mkdir -p "$root/target"
"$python" -m venv "$venv" || die "python -m venv failed (Debian: apt-get install python3-venv)"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r "$requirements" \
    || die "pip install -r $requirements failed"
"$venv/bin/python" "$here/check_keras_to_onnx.py" > /dev/null \
    || die "the converter's check failed: $venv/bin/python $here/check_keras_to_onnx.py"
echo "$wanted" > "$marker"
echo "setup.sh: ready: $venv/bin/python $here/keras_to_onnx.py IN.h5 OUT.onnx" >&2
