"""Section `release`: the manylinux2014 wheel and the sdist (issue 73), from the saved output of
scripts/release/check.sh (target/bench-output/release-check.json, written on every CI run) and of
scripts/bench/cold_build.sh (target/bench-output/cold-build.LABEL.json, one per build setting).
"""

import glob
import json
import os

from common import num, out


def megabytes(size):
    return f"{size / 1e6:.1f} MB"


def release_section():
    out()
    out("## Release: the wheel and the sdist")
    out()
    check = "target/bench-output/release-check.json"
    if os.path.exists(check):
        found = json.load(open(check))
        installs = ", ".join(f"{s:.2f} s into Python {v}" for v, s in sorted(
            found["wheel_installs_s"].items(), key=lambda kv: [int(p) for p in kv[0].split(".")]))
        out(f"`scripts/release/build.sh DIR` then `scripts/release/check.sh DIR` (what .ci/run runs): "
            f"the wheel `{found['wheel']}` ({megabytes(found['wheel_bytes'])}), which auditwheel finds "
            f"consistent with manylinux_2_17_x86_64, installs with pip in {installs} (fresh venvs; a "
            f"20-test search and the Python client's tests then pass in each). The sdist "
            f"`{found['sdist']}` ({megabytes(found['sdist_bytes'])}) builds and installs from an empty "
            f"directory in {num(found['sdist_install_s'])} s "
            + ("with its dependencies already compiled (CI's CARGO_TARGET_DIR)." if found["sdist_cargo_target_dir"]
               else "from cold."))
    else:
        out("Not measured yet: `scripts/release/build.sh target/dist && scripts/release/check.sh target/dist`.")
    runs = sorted((json.load(open(p)) for p in glob.glob("target/bench-output/cold-build.*.json")),
                  key=lambda r: r["date"])
    out()
    if not runs:
        out("The cold build is not measured yet: `scripts/bench/cold_build.sh LABEL`.")
        return
    out("A cold `pip install wogan-VERSION.tar.gz` (an empty cargo target folder, maturin fetched "
        "from PyPI, cargo's `--timings`): `scripts/bench/cold_build.sh LABEL`. The load average as "
        "the build started is beside it: work beside the build slows it. Unit-seconds are the "
        "compile time of every crate summed; when it is about twice the wall time, both cores were "
        "busy throughout and only less work shortens the build. The target: well under 8 minutes "
        "on 2 quiet cores.")
    out()
    out("| build | commit | when | cores, load | pip install | units, unit-seconds | costliest units (s) |")
    out("|---|---|---|---|---|---|---|")
    for run in runs:
        costliest = ", ".join(f"{u['crate'].split(' ')[0]}{'' if u['target'] == 'lib' else ' (' + u['target'].split()[-1].strip(chr(34)) + ')'} {u['seconds']:.0f}"
                              for u in run["costliest"][:6])
        commit = run["commit"] + (" with changes" if run["changed"] else "")
        out(f"| {run['label']} (`[profile.release]` {run['profile_release']}) | {commit} | "
            f"{run['date']} | {run['cores']}, {run['load_before']:.1f} | {run['install_s'] / 60:.1f} min | "
            f"{run['units']}, {num(run['unit_seconds'])} | {costliest} |")
