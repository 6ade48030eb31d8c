#!/usr/bin/env bash
# The test command (README; .ci/run calls it): installs what is missing, builds everything,
# runs the benchmark smoke versions, then the whole test suite inside a private network
# namespace (tests open DDS sockets; nothing may leave loopback).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
# Real ROS 2 Jazzy (rclpy on Fast DDS) and our interfaces, for the rclpy suite: a venv in
# .ros/venv, rebuilt only when the wheels or interface files change (a no-op otherwise).
scripts/ros-venv.sh
# Debian's chromium and playwright-core for the live view's browser test (must run, not skip).
scripts/browser-setup.sh
export MOTION_REQUIRE_BROWSER=1
export CARGO_TERM_COLOR=${CARGO_TERM_COLOR:-never}
# A one-shot build gains nothing from incremental state, which would add GBs on disk.
export CARGO_INCREMENTAL=${CARGO_INCREMENTAL:-0}
# setup.sh installed cyclonedds: the Rust/Python CDR cross-check must run, not skip.
export MOTION_MSGS_REQUIRE_CYCLONEDDS=1
export MOTION_MSGS_REQUIRE_MCAP=1
# ros-venv.sh built the rclpy venv: the rclpy suite must run, not skip.
export MOTION_REQUIRE_RCLPY=1
cargo build --workspace --all-targets --quiet
# The vendored RustDDS's own unit tests (see below) are built here, outside the namespace: it has
# its own lock file, and on a fresh machine its dependencies are fetched (no network in there).
CARGO_TARGET_DIR=target/vendor-rustdds \
  cargo test --quiet --locked --no-run --manifest-path vendor/rustdds/Cargo.toml --lib
echo "== disk: target $(du -sh target 2>/dev/null | cut -f1), free $(df -h . | awk 'NR==2 {print $4}')"
echo "== architecture (issue 16: import circles and long files of the engine crates)"
# Fails on any import circle (also between top-level module trees) or a file over 1 200 lines.
python3 scripts/arch-report.py --max-circle 1 --max-lines 1200
echo "== benchmark smoke runs"
scripts/netns-run cargo run --quiet -p system_tests --bin bench -- --smoke
echo "== tests"
log=$(mktemp)
trap 'rm -f "$log"' EXIT
set +e
scripts/netns-run cargo test --workspace --no-fail-fast "$@" 2>&1 | tee "$log"
rc=${PIPESTATUS[0]}
# The vendored RustDDS's own unit tests (upstream's and the regression tests of our patches,
# vendor/README.md), built apart: it is outside the workspace, with its own lock file.
if [ $# -eq 0 ]; then
  echo "== vendor/rustdds unit tests"
  CARGO_TARGET_DIR=target/vendor-rustdds scripts/netns-run \
    cargo test --quiet --locked --offline --manifest-path vendor/rustdds/Cargo.toml --lib 2>&1 | tee -a "$log"
  [ "${PIPESTATUS[0]}" = 0 ] || rc=1
fi
set -e
# One closing line over all test binaries (cargo's last line is often an empty doc-test run).
awk '/^test result:/ { for (i = 1; i <= NF; i++) { if ($(i+1) ~ /^passed/) p += $i; if ($(i+1) ~ /^failed/) f += $i; if ($(i+1) ~ /^ignored/) s += $i } }
     END { printf "tests: %d passed, %d failed, %d skipped\n", p, f, s }' "$log"
exit "$rc"
