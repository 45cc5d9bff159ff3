#!/usr/bin/env bash
# A fuzz campaign against the wogan binary: the harness of tests/fuzz/ (whose small sample runs in
# `cargo test`) with as many cases as asked. It feeds mutated input lines, files and option values
# to validate, simulate, run, report, export, camera, replay, suite and sample, then prints per command the inputs tried,
# panics, aborts, hangs and output lines that are not JSON, and every failure class with the seed,
# command line, input and stderr that reproduce it. Exits non-zero when any input failed.
#
#   scripts/runs/fuzz_campaign.sh                                 600 cases from seed 1
#   FUZZ_SEED=7 FUZZ_CASES=5000 scripts/runs/fuzz_campaign.sh     5000 cases from seed 7
#   FUZZ_SEED=7 FUZZ_ONLY=1234 scripts/runs/fuzz_campaign.sh      case 1234 of seed 7 again
#   FUZZ_COMMANDS=run,export FUZZ_MINUTES=10 scripts/runs/fuzz_campaign.sh
#
# Other settings: FUZZ_JOBS (children at once; the number of cores), FUZZ_WATCHDOG_S (a child still
# running after this long is a hang; 30), FUZZ_MEM_MB (each child's address-space limit; 4096),
# FUZZ_KEEP=1 (keep every case's directory, not only the failing ones').
set -euo pipefail
cd "$(dirname "$0")/../.."
# The harness sets the children's backtraces itself; the test's own would only repeat the verdict.
RUST_BACKTRACE=0 exec cargo test --release --workspace --test end_to_end -- \
  --ignored --exact fuzz::fuzz_campaign --nocapture
