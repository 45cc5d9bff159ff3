#!/usr/bin/env bash
# The cold install from the source distribution, measured (issue 73): `maturin sdist`, then
# `pip install wogan-VERSION.tar.gz` into a fresh venv with an empty cargo target folder, as a user
# without a wheel meets it, with cargo's --timings (through MATURIN_PEP517_ARGS) to name the crates
# that cost most. Writes target/bench-output/cold-build.LABEL.json (scripts/results/, section
# `release`) and keeps cargo's HTML report beside it. Run it with nothing else busy on the machine.
#
#   scripts/bench/cold_build.sh LABEL        e.g. scripts/bench/cold_build.sh before
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: scripts/bench/cold_build.sh LABEL" >&2; exit 2; }
label=$1
cd "$(dirname "$0")/../.."
out=target/bench-output
work=target/cold-build
rm -rf "$work" && mkdir -p "$work" "$out"
maturin=target/maturin-venv/bin/maturin
[ -x "$maturin" ] || { python3 -m venv target/maturin-venv && target/maturin-venv/bin/pip install -q "maturin>=1.7,<2"; }
# The sources are what the sdist holds when it is made: the commit and whether the build's files
# differ from it are taken now.
commit=$(git rev-parse --short HEAD)
changed=$(git status --porcelain -- Cargo.toml Cargo.lock crates pyproject.toml | head -c 1)
"$maturin" sdist --out "$work" > /dev/null
sdist=$(echo "$work"/wogan-*.tar.gz)
python3 -m venv "$work/venv"
"$work/venv/bin/pip" install -q --upgrade pip > /dev/null
load=$(cut -d' ' -f1 /proc/loadavg)
start=$(date +%s.%N)
# The build backend (maturin, from PyPI) is fetched before cargo starts: its seconds count, as a
# user's would.
env -u CARGO_BUILD_TARGET CARGO_TARGET_DIR="$PWD/$work/target" MATURIN_PEP517_ARGS="--timings" \
  "$work/venv/bin/pip" install -q "$sdist"
end=$(date +%s.%N)
cp "$work"/target/cargo-timings/cargo-timing.html "$out/cold-build.$label.html"
python3 - "$label" "$commit" "$changed" "$start" "$end" "$load" "$sdist" "$out/cold-build.$label.html" "$out/cold-build.$label.json" <<'PY'
import datetime, json, os, re, sys, tarfile
label, commit, changed, start, end, load, sdist, html, target = sys.argv[1:]
# cargo's report carries its units as a JSON array in its script.
data = re.search(r"^const UNIT_DATA = (\[.*?^\]);$", open(html).read(), re.S | re.M)[1]
units = [{"crate": f"{u['name']} {u['version']}", "target": u["target"].strip() or "lib", "seconds": u["duration"]}
         for u in json.loads(data)]
units.sort(key=lambda u: -u["seconds"])
# The release profile the sdist was built with: its own workspace manifest.
with tarfile.open(sdist) as archive:
    manifest = next(m for m in archive.getmembers() if m.name.count("/") == 1 and m.name.endswith("/Cargo.toml"))
    manifest_text = archive.extractfile(manifest).read().decode()
# `[profile.release]` and its per-package tables, one "key = value" line each, comments left out.
profile, table = [], None
for line in manifest_text.splitlines():
    line = line.split("#", 1)[0].strip()
    if line.startswith("["):
        table = line.strip("[]") if line.startswith("[profile.release") else None
    elif line and table:
        profile.append(line if table == "profile.release" else f"{table.split('.', 3)[-1].strip(chr(34))}: {line}")
profile = "; ".join(profile)
result = {
    "label": label,
    "commit": commit,
    "changed": bool(changed),
    "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
    "cores": os.cpu_count(),
    "load_before": float(load),
    "install_s": round(float(end) - float(start), 1),
    "sdist_bytes": os.path.getsize(sdist),
    "units": len(units),
    "unit_seconds": round(sum(u["seconds"] for u in units), 1),
    "costliest": units[:10],
    "profile_release": profile,
}
json.dump(result, open(target, "w"), indent=1)
print(f"cold_build: {label}: pip install from the sdist took {result['install_s']} s on {result['cores']} cores "
      f"({result['units']} units, {result['unit_seconds']} unit-seconds); costliest: "
      + ", ".join(f"{u['crate']} {u['seconds']:.0f} s" for u in units[:5]))
PY
