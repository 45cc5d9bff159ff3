#!/usr/bin/env bash
# Checks a release that scripts/release/build.sh wrote into DIR, as a user would meet it:
# - auditwheel must find the wheel consistent with manylinux_2_17_x86_64 (manylinux2014);
# - the wheel installs into a fresh venv of the oldest and the newest Python the package supports
#   (pyenv's; the minor versions in PYTHONS, default "3.9 3.13"), the install timed; in each,
#   `wogan run --max-tests 20 --seed 1` writes a run the client reads back, and the Python
#   client's tests pass against the installed package (all but test_ray.py: .ci/run runs those
#   with Ray);
# - the sdist, unpacked into an empty directory, builds and installs with pip (maturin from PyPI,
#   the Rust toolchain on PATH) into a fresh venv, and the installed binary runs a search.
#
#   scripts/release/check.sh DIR
#
# Its figures (sizes, install seconds) go to target/bench-output/release-check.json too
# (scripts/results/, section `release`).
#
# The sdist's build compiles into CARGO_TARGET_DIR when it is set (CI points it at the workspace's
# target/, so the dependencies compiled for the tests are reused and only the workspace's crates
# are compiled from the sdist); otherwise into the unpacked directory, cold
# (scripts/bench/cold_build.sh measures that). The client's tests run in a network namespace with
# loopback alone when this runs as root (as in CI), like .ci/run's.
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: scripts/release/check.sh DIR" >&2; exit 2; }
dist=$(realpath "$1")
cd "$(dirname "$0")/../.."
shopt -s nullglob
wheels=("$dist"/wogan-*-manylinux*_x86_64.whl)
sdists=("$dist"/wogan-*.tar.gz)
[ ${#wheels[@]} -eq 1 ] || { echo "check.sh: expected one manylinux wheel in $dist, found ${#wheels[@]}" >&2; exit 1; }
[ ${#sdists[@]} -eq 1 ] || { echo "check.sh: expected one sdist in $dist, found ${#sdists[@]}" >&2; exit 1; }
wheel=${wheels[0]} sdist=${sdists[0]}
work=$(mktemp -d "${TMPDIR:-/tmp}/wogan-release-check.XXXXXX")
trap 'rm -rf "$work"' EXIT

# auditwheel (pinned) beside maturin.
venv=target/maturin-venv
[ -x "$venv/bin/auditwheel" ] || "$venv/bin/pip" install -q "auditwheel==6.8.2"
audit=$("$venv/bin/auditwheel" show "$wheel")
echo "$audit"
grep -q 'consistent with the following platform tag: "manylinux_2_17_x86_64"' <<< "$audit" \
  || { echo "check.sh: auditwheel does not accept $(basename "$wheel") as manylinux_2_17_x86_64" >&2; exit 1; }

# The client's tests, against what is installed in the venv whose python is $1.
client_tests() {
  local python=$1
  (cd python/tests && if [ "$(id -u)" -eq 0 ]; then
     env -u WOGAN_BIN WOGAN_TEST_INSTALLED=1 unshare -n sh -c \
       'ip link set lo up && exec "$0" -m pytest -q -p no:cacheprovider --ignore=test_ray.py .' "$python"
   else
     env -u WOGAN_BIN WOGAN_TEST_INSTALLED=1 "$python" -m pytest -q -p no:cacheprovider --ignore=test_ray.py .
   fi)
}

# A 20-test search with the installed binary, read back by the installed client.
search_runs() {
  local venv=$1 run=$2
  "$venv/bin/wogan" run --max-tests 20 --seed 1 --quiet --out "$run"
  "$venv/bin/python" -c "import sys, wogan; run = wogan.read_run(sys.argv[1]); assert len(run.tests) == 20, len(run.tests)" "$run"
}

installs=()
pyenv_root=$(pyenv root 2> /dev/null || echo "${PYENV_ROOT:-$HOME/.pyenv}")
for minor in ${PYTHONS:-3.9 3.13}; do
  found=("$pyenv_root"/versions/"$minor".*/bin/python3)
  [ ${#found[@]} -ge 1 ] || { echo "check.sh: no Python $minor under $pyenv_root/versions" >&2; exit 1; }
  python=${found[-1]}
  version=$("$python" -c 'import platform; print(platform.python_version())')
  "$python" -m venv "$work/py$minor"
  "$work/py$minor/bin/pip" install -q pytest jsonschema
  start=$(date +%s.%N)
  "$work/py$minor/bin/pip" install -q "$wheel"
  end=$(date +%s.%N)
  seconds=$(python3 -c "print(f'{$end - $start:.2f}')")
  echo "check.sh: the wheel installed into Python $version in $seconds s"
  installs+=("$version=$seconds")
  search_runs "$work/py$minor" "$work/py$minor-run.jsonl"
  client_tests "$work/py$minor/bin/python"
done

# The sdist from an empty directory.
mkdir "$work/sdist"
tar -xzf "$sdist" -C "$work/sdist"
source_dir=("$work"/sdist/wogan-*)
# The unpacked files are dated now, so that cargo compiles the sdist's own sources even where
# CARGO_TARGET_DIR holds units built from the checkout (a path package's units are keyed by its
# path within the workspace, so they would otherwise count as fresh): the workspace's crates are
# compiled from the sdist, the dependencies reused.
find "${source_dir[0]}" -type f -exec touch {} +
python3 -m venv "$work/sdist-venv"
start=$(date +%s.%N)
"$work/sdist-venv/bin/pip" install -q "${source_dir[0]}"
end=$(date +%s.%N)
sdist_seconds=$(python3 -c "print(f'{$end - $start:.0f}')")
echo "check.sh: the sdist ($(du -k "$sdist" | cut -f1) KiB) built and installed in $sdist_seconds s" \
  "(CARGO_TARGET_DIR ${CARGO_TARGET_DIR:-unset: a cold build})"
search_runs "$work/sdist-venv" "$work/sdist-run.jsonl"
mkdir -p target/bench-output
python3 - "$wheel" "$sdist" "$sdist_seconds" "${CARGO_TARGET_DIR:-}" "${installs[@]}" > target/bench-output/release-check.json <<'PY'
import json, os, sys
wheel, sdist, sdist_seconds, target_dir, *installs = sys.argv[1:]
json.dump({"wheel": os.path.basename(wheel), "wheel_bytes": os.path.getsize(wheel),
           "wheel_installs_s": {v: float(s) for v, s in (i.split("=") for i in installs)},
           "sdist": os.path.basename(sdist), "sdist_bytes": os.path.getsize(sdist),
           "sdist_install_s": float(sdist_seconds), "sdist_cargo_target_dir": target_dir or None},
          sys.stdout, indent=1)
PY
echo "check.sh: $(basename "$wheel") and $(basename "$sdist") pass"
