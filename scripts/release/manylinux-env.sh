# Sourced, not run: makes every cargo build of this shell a manylinux2014 build. Cargo builds for
# the explicit target x86_64-unknown-linux-gnu (CARGO_BUILD_TARGET) and links, and compiles
# tract-linalg's C and assembly, with zig's cc for glibc 2.17 (scripts/release/zig-cc), so the
# binary needs nothing newer than glibc 2.17.
#
#   . scripts/release/manylinux-env.sh
#
# Both scripts/release/build.sh and .ci/run source it: `cargo test` and the wheel's `maturin build`
# then see the same target and the same linker, so the wheel reuses what the tests compiled
# instead of compiling the workspace a second time (maturin's own `--zig` points the linker at a
# script of its cache, a path the test build would not share). Artifacts go to
# $CARGO_TARGET_DIR/x86_64-unknown-linux-gnu/release/. maturin and zig (ziglang from PyPI,
# pinned) are installed into target/maturin-venv when missing, kept when present.
wogan_release_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
wogan_release_venv=$wogan_release_root/target/maturin-venv
[ -x "$wogan_release_venv/bin/maturin" ] || {
  python3 -m venv "$wogan_release_venv" && "$wogan_release_venv/bin/pip" install -q "maturin>=1.7,<2"
}
"$wogan_release_venv/bin/python" -c "import ziglang" 2> /dev/null \
  || "$wogan_release_venv/bin/pip" install -q "ziglang==0.17.1"
export WOGAN_RELEASE_TARGET=x86_64-unknown-linux-gnu
export CARGO_BUILD_TARGET=$WOGAN_RELEASE_TARGET
export CARGO_TARGET_X86_64_UNKNOWN_LINUX_GNU_LINKER=$wogan_release_root/scripts/release/zig-cc
export CC_x86_64_unknown_linux_gnu=$wogan_release_root/scripts/release/zig-cc
export AR_x86_64_unknown_linux_gnu=$wogan_release_root/scripts/release/zig-ar
