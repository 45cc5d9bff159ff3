#!/usr/bin/env bash
# Makes target/metadrive-venv: a Python venv with MetaDrive (examples/metadrive/requirements.txt,
# pinned) that starts offline, so that
#   target/metadrive-venv/bin/python examples/metadrive/executor.py --policy idm
# is the executor. Run from anywhere; idempotent (a complete venv of the same requirements is kept).
#
# Offline start: at its first start MetaDrive downloads an asset archive from GitHub unless
# metadrive/assets/version.txt holds the package's version and the grass texture its check looks
# for exists (metadrive/engine/asset_loader.py `should_update_asset`, called by
# base_engine.py `try_pull_asset`). A headless drive loads no asset, so both are written here: the
# version, and an empty texture file.
#
# Environment: PYTHON (default python3, 3.9 to 3.12), FORCE=1 to rebuild the venv.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
venv="$root/target/metadrive-venv"
requirements="$here/requirements.txt"
python=${PYTHON:-python3}
marker="$venv/.wogan-metadrive-complete"

die() { echo "setup.sh: $*" >&2; exit 1; }

wanted=$(sha256sum "$requirements" | cut -d' ' -f1)

if [[ "${FORCE:-0}" != 1 && -f "$marker" && "$(cat "$marker")" == "$wanted" \
      && -x "$venv/bin/python" ]]; then
    echo "setup.sh: $venv is complete (requirements unchanged); FORCE=1 rebuilds it" >&2
else
    command -v "$python" >/dev/null || die "no $python (set PYTHON to a Python 3.9 to 3.12)"
    "$python" -c 'import sys; sys.exit(not ((3, 9) <= sys.version_info[:2] <= (3, 12)))' \
        || die "$python is Python $("$python" -c 'import platform; print(platform.python_version())'); MetaDrive 0.4.3 needs 3.9 to 3.12"
    rm -rf "$venv"
    mkdir -p "$root/target"
    echo "setup.sh: making $venv with $("$python" --version 2>&1)" >&2
    "$python" -m venv "$venv" || die "python -m venv failed (Debian: apt-get install python3-venv)"
    "$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r "$requirements" \
        || die "pip install -r $requirements failed"
    "$venv/bin/python" -m pip check >&2 || die "pip check found broken requirements"
fi

# The offline asset check, written every time (cheap) and then verified.
"$venv/bin/python" - <<'EOF' || die "could not prepare MetaDrive's offline start"
import os
import metadrive
from metadrive.version import VERSION
assets = os.path.join(os.path.dirname(metadrive.__file__), "assets")
texture = os.path.join(assets, "textures", "grass1", "GroundGrassGreen002_COL_1K.jpg")
os.makedirs(os.path.dirname(texture), exist_ok=True)
with open(os.path.join(assets, "version.txt"), "w") as f:
    f.write(VERSION + "\n")
if not os.path.exists(texture):
    open(texture, "wb").close()
from metadrive.engine.asset_loader import AssetLoader
if AssetLoader.should_update_asset():
    raise SystemExit("MetaDrive would still download its assets: " + assets)
EOF

# A drive of one straight road, offline: the executor must answer PASS.
answer=$(printf '%s\n' \
    '{"type":"hello","protocol":"wogan-executor","version":3,"units":"metres, seconds","map_size_m":200.0,"oob_tolerance":0.85,"speed_limit_kmh":70.0}' \
    '{"type":"road","id":1,"road_points":[[100.0,10.0],[100.0,40.0],[100.0,70.0],[100.0,85.0]]}' \
    '{"type":"bye"}' \
    | "$venv/bin/python" "$here/executor.py" --policy idm --log-level WARNING) \
    || die "the executor failed on a straight road"
case "$answer" in
    *'"outcome": "PASS"'*) ;;
    *) die "the executor did not pass a straight road: $answer" ;;
esac
echo "$wanted" > "$marker"
echo "setup.sh: ready: $venv/bin/python $here/executor.py --policy idm" >&2
