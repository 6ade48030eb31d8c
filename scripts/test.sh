#!/usr/bin/env bash
# The test command (README; .ci/run calls it): installs what is missing, builds everything,
# runs the benchmark smoke versions, then the whole test suite inside a private network
# namespace (tests open DDS sockets; nothing may leave loopback).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
export CARGO_TERM_COLOR=${CARGO_TERM_COLOR:-never}
cargo build --workspace --all-targets --quiet
echo "== benchmark smoke runs"
scripts/netns-run cargo run --quiet -p system_tests --bin bench -- --smoke
echo "== tests"
exec scripts/netns-run cargo test --workspace --no-fail-fast "$@"
