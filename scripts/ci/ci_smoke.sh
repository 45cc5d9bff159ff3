#!/usr/bin/env bash
# A CI user's pass with the built binary, as examples/ci/ runs it: replay the committed regression
# suite (it must replay unchanged), a 50-test seeded smoke search, both with JUnit reports, and
# check that the reports parse and count what was driven. Run by .ci/run after the tests.
#
#   scripts/ci/ci_smoke.sh [WOGAN]        # default target/release/wogan; writes into target/ci-smoke/
set -euo pipefail
cd "$(dirname "$0")/../.."
wogan=${1:-target/release/wogan}
out=target/ci-smoke
rm -rf "$out" && mkdir -p "$out"

# The suite's roads failed beamng-ai-proxy when they were kept: with --fail-on changed the build
# fails only if one of them drives differently now.
"$wogan" replay examples/ci/wogan-suite.jsonl --jobs 2 --fail-on changed \
  --junit "$out/replay.xml" > "$out/replay.jsonl"

# A smoke search: exit 1 means it found a failing road (--fail-on failure), which a team's CI
# treats as a failed build; here the driver is ours and failing roads are expected.
status=0
"$wogan" run --max-tests 50 --seed 1 --quiet --fail-on failure \
  --junit "$out/smoke.xml" --out "$out/smoke.jsonl" || status=$?
if [ "$status" -ne 0 ] && [ "$status" -ne 1 ]; then
  echo "ci_smoke: the smoke search ended with exit status $status" >&2
  exit 1
fi

python3 - "$out" <<'PY'
import json, sys, xml.etree.ElementTree as ET
out = sys.argv[1]
def suite(path):
    root = ET.parse(path).getroot()
    suites = root.findall("testsuite")
    assert len(suites) == 1, f"{path}: {len(suites)} test suites"
    return suites[0]
replay = suite(f"{out}/replay.xml")
roads = sum(1 for line in open("examples/ci/wogan-suite.jsonl") if '"type":"road"' in line)
assert int(replay.get("tests")) == roads, (replay.get("tests"), roads)
smoke = suite(f"{out}/smoke.xml")
tests = [json.loads(l) for l in open(f"{out}/smoke.jsonl") if '"type":"test"' in l]
failing = sum(t["outcome"] == "FAIL" for t in tests)
assert int(smoke.get("tests")) == len(tests) == 50, smoke.get("tests")
assert int(smoke.get("failures")) == failing, (smoke.get("failures"), failing)
print(f"ci_smoke: replay.xml {roads} roads replayed unchanged; smoke.xml 50 tests, {failing} failing")
PY
