#!/usr/bin/env bash
# Rust: clippy (warnings are errors) over the whole workspace, then the unit, integration and
# doc tests (the README's Rust example among them) of the core, CLI and FFI crates; every test
# binary runs (--no-fail-fast).
set -euo pipefail
cd "$(dirname "$0")/../.."
status=0
cargo clippy --workspace --all-targets -- -D warnings 2>&1 || { echo "clippy failed" >&2; status=1; }
cargo test --workspace --exclude dualspectra-py --no-fail-fast 2>&1 || status=1
exit $status
