#!/usr/bin/env bash
# Rust: clippy (warnings are errors) over the whole workspace, then the unit, integration and
# doc tests (the README's Rust example among them) of the core, lab, CLI, FFI and reference
# crates; every test binary runs (--no-fail-fast). The reference crate (rust/dualspectra-reference:
# laws, and CGAL 5.5 / Eigen 3 through autocxx) must find its C++ reference here (the setup
# installs it), so a missing one fails instead of skipping. Tests that need the datasets are
# marked #[ignore = "needs ../shared/datasets ..."] (cargo reports them as ignored); when
# $DUALSPECTRA_DATA exists they run afterwards with --ignored. The `bless_*` tests, ignored
# because they rewrite committed listings, never run here.
#
# Every cargo command selects the same packages (the workspace without the Python module, as the
# C++ stage does): cargo unifies dependency features over the selected packages, and another
# selection (`-p one-crate`) builds syn, serde, faer... again with other features (five builds of
# the dependency tree before, one now). The optional nalgebra interop adds its feature on top,
# which rebuilds only the core crate.
set -euo pipefail
cd "$(dirname "$0")/../.."
export DUALSPECTRA_REQUIRE_CPP_REFERENCE=1
select=(--workspace --exclude dualspectra-py)
status=0
# With the nalgebra feature on, clippy sees every line of the core (no code is compiled only
# without it).
cargo clippy --workspace --all-targets --features dualspectra/nalgebra -- -D warnings 2>&1 || { echo "clippy failed" >&2; status=1; }
cargo test "${select[@]}" --no-fail-fast 2>&1 || status=1
cargo test "${select[@]}" --features dualspectra/nalgebra --test nalgebra_interop 2>&1 || status=1
if [ -d "${DUALSPECTRA_DATA:-}" ]; then
  echo "== dataset tests (ignored above) on $DUALSPECTRA_DATA"
  # Test targets only: doc tests marked `ignore` are not meant to run.
  cargo test "${select[@]}" --lib --bins --tests --no-fail-fast -- --ignored --skip bless_ 2>&1 || status=1
else
  echo "== dataset tests skipped: no data (set DUALSPECTRA_DATA or put the datasets in ../shared/datasets)"
fi
exit $status
