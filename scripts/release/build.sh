#!/usr/bin/env bash
# A release of wogan into DIR: the manylinux2014 x86_64 wheel and the source distribution.
#
#   scripts/release/build.sh DIR        e.g. scripts/release/build.sh target/dist
#
# The wheel's binary is built by maturin for x86_64-unknown-linux-gnu, linked by zig against glibc
# 2.17 (manylinux-env.sh), and maturin refuses it unless every symbol it needs is in manylinux2014
# (`--compatibility manylinux2014`). It compiles into CARGO_TARGET_DIR (default target/) under
# x86_64-unknown-linux-gnu/release/, where `cargo test` under manylinux-env.sh (.ci/run) has
# already compiled everything but the last link. DIR receives
# wogan-VERSION-py3-none-manylinux_2_17_x86_64.whl (with the manylinux2014 alias) and
# wogan-VERSION.tar.gz.
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: scripts/release/build.sh DIR" >&2; exit 2; }
out=$(realpath -m "$1")
cd "$(dirname "$0")/../.."
. scripts/release/manylinux-env.sh
mkdir -p "$out"
rm -f "$out"/wogan-*.whl "$out"/wogan-*.tar.gz
maturin=target/maturin-venv/bin/maturin
"$maturin" build --release --compatibility manylinux2014 --target "$WOGAN_RELEASE_TARGET" --out "$out"
"$maturin" sdist --out "$out"
ls -l "$out"
