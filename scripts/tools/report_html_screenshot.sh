#!/usr/bin/env bash
# The README's picture of `wogan report --html`: a seeded 300-test WOGAN search on beamng-ai-proxy,
# its page with the 10 worst failing roads driven again, opened in chromium (headless) by
# scripts/ci/browser_check.py, which sorts by max BOLP, opens the worst road and takes the picture.
#
#   scripts/tools/report_html_screenshot.sh [BIN]   # writes docs/pictures/report-html.png
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=${1:-target/release/wogan}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin" run --max-tests 300 --seed 1 --out "$work/run.jsonl" 2> /dev/null
"$bin" report "$work/run.jsonl" --out "$work/report" --html --traces 10
mkdir -p docs/pictures
python3 scripts/ci/browser_check.py --page "$work/report/report.html" --run "$work/run.jsonl" \
  --expect-trace --screenshot docs/pictures/report-html.png
