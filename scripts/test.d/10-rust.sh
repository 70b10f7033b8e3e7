#!/usr/bin/env bash
# Rust: clippy (warnings are errors) over the whole workspace, then the unit, integration and
# doc tests (the README's Rust example among them) of the core, lab, CLI and FFI crates; every
# test binary runs (--no-fail-fast). Tests that need the datasets are marked
# #[ignore = "needs ../shared/datasets ..."] (cargo reports them as ignored); when
# $DUALSPECTRA_DATA exists they run afterwards with --ignored, in whichever crates hold them.
# The `bless_*` tests, ignored because they rewrite committed listings, never run here.
set -euo pipefail
cd "$(dirname "$0")/../.."
status=0
cargo clippy --workspace --all-targets -- -D warnings 2>&1 || { echo "clippy failed" >&2; status=1; }
cargo test --workspace --exclude dualspectra-py --exclude dualspectra-reference --no-fail-fast 2>&1 || status=1
# The optional nalgebra interop (feature `nalgebra`).
cargo clippy -p dualspectra --features nalgebra --all-targets -- -D warnings 2>&1 || { echo "clippy (nalgebra) failed" >&2; status=1; }
cargo test -p dualspectra --features nalgebra --test nalgebra_interop 2>&1 || status=1
# The crates (folder names under rust/, which are the package names) with dataset tests.
crates=$(grep -rl --include='*.rs' '#\[ignore = "needs ../shared/datasets' rust | cut -d/ -f2 | sort -u | grep -vx dualspectra-py || true)
if [ -z "$crates" ]; then
  echo "== dataset tests: none marked"
elif [ -d "${DUALSPECTRA_DATA:-}" ]; then
  echo "== dataset tests (ignored above) on $DUALSPECTRA_DATA: $(echo $crates)"
  cargo test $(printf -- '-p %s ' $crates) --no-fail-fast -- --ignored --skip bless_ 2>&1 || status=1
else
  echo "== dataset tests skipped: no data (set DUALSPECTRA_DATA or put the datasets in ../shared/datasets)"
fi
exit $status
