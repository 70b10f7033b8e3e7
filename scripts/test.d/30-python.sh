#!/usr/bin/env bash
# Python bindings: pytest on tests/python (against libigl + scipy), mypy --strict and
# mypy.stubtest on the typed package, and no native module committed in the source tree.
# pytest's exit code 5 (no tests collected) is a failure here. Then the package itself: the
# wheel scripts/setup.d/30-python.sh built is manylinux_2_28 by `auditwheel show`, carries the
# licence texts, and installs into a fresh venv where it imports and localizes; the sdist
# (`maturin sdist`) has what a build from it needs. (Building a wheel from the sdist, or
# `pip install .`, compiles everything again, about 2 minutes on 2 cores: checked by hand, see README.)
set -uo pipefail
cd "$(dirname "$0")/../.."
PY=.venv/bin/python
[ -x "$PY" ] || { echo "no .venv: run scripts/setup.d/30-python.sh" >&2; exit 1; }
# A build product in git (e.g. from `maturin develop`) would shadow the wheel for whoever checks out.
if command -v git >/dev/null && git rev-parse --git-dir >/dev/null 2>&1; then
  committed=$(git ls-files -- '*.so' '*.pyd' '*.dylib')
  [ -z "$committed" ] || { echo "native modules are committed: $committed" >&2; exit 1; }
fi
# Run from outside the source tree so the installed wheel is imported.
"$PY" -m pytest -rs -p no:cacheprovider tests/python
rc=$?
if [ "$rc" -eq 5 ]; then echo "pytest collected no tests" >&2; exit 1; fi
[ "$rc" -eq 0 ] || exit "$rc"
"$PY" -m mypy --strict rust/dualspectra-py/python/dualspectra || exit 1
( cd /tmp && "$OLDPWD/$PY" -m mypy.stubtest dualspectra --allowlist "$OLDPWD/tests/python/stubtest-allowlist.txt" ) || exit 1

root=$(pwd)
t0=$(date +%s)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
wheels=(target/wheels/dualspectra-*.whl)
[ ${#wheels[@]} -eq 1 ] && [ -f "${wheels[0]}" ] || { echo "want one wheel in target/wheels: ${wheels[*]}" >&2; exit 1; }
wheel=${wheels[0]}
echo "wheel: $wheel, $(( $(stat -c %s "$wheel") / 1024 )) KiB"
case "$wheel" in *-cp39-abi3-manylinux_2_28_x86_64.whl) ;; *) echo "not a cp39-abi3-manylinux_2_28 wheel" >&2; exit 1;; esac
.venv/bin/auditwheel show "$wheel" | tee "$tmp/auditwheel.txt" || exit 1
# auditwheel names the most compatible tag the wheel's symbols allow: 2.28 or older, no libraries bundled.
tag=$(grep -o 'manylinux_2_[0-9]*_x86_64' "$tmp/auditwheel.txt" | head -1)
[ -n "$tag" ] && [ "$(echo "$tag" | cut -d_ -f3)" -le 28 ] || { echo "auditwheel: not manylinux_2_28 ($tag)" >&2; exit 1; }
"$PY" - "$wheel" <<'PYEOF' || exit 1
import sys, zipfile
names = zipfile.ZipFile(sys.argv[1]).namelist()
meta = zipfile.ZipFile(sys.argv[1]).read(next(n for n in names if n.endswith(".dist-info/METADATA"))).decode()
want = ["licenses/LICENSE-MIT", "licenses/LICENSE-APACHE", "dualspectra/py.typed", "dualspectra/_dualspectra.pyi"]
missing = [w for w in want if not any(n.endswith(w) for n in names)]
missing += [h for h in ("License-Expression: MIT OR Apache-2.0", "Description-Content-Type: text/markdown") if h not in meta]
if missing:
    sys.exit(f"wheel lacks {missing}")
print("wheel: licence texts, typing files, metadata ok")
PYEOF
# A fresh venv (numpy from PyPI or pip's cache), run from outside the source tree.
"${PYTHON:-python3}" -m venv "$tmp/venv" && "$tmp/venv/bin/python" -m pip install -q --disable-pip-version-check "$wheel" || exit 1
( cd "$tmp" && "$tmp/venv/bin/python" "$root/tests/python/installed_wheel.py" ) || { echo "fresh venv: localize failed" >&2; exit 1; }
# The sdist: crates, Cargo.lock, the typed package, README and licence texts.
.venv/bin/maturin sdist -o "$tmp/sdist" >"$tmp/sdist.log" 2>&1 || { cat "$tmp/sdist.log"; exit 1; }
sdist=$(ls "$tmp"/sdist/dualspectra-*.tar.gz)
tar tzf "$sdist" | sed 's|^[^/]*/||' | sort >"$tmp/sdist.txt"
for f in pyproject.toml Cargo.toml Cargo.lock README.md LICENSE-MIT LICENSE-APACHE PKG-INFO \
    rust/dualspectra/src/lib.rs rust/dualspectra-py/Cargo.toml rust/dualspectra-py/python/dualspectra/__init__.py; do
  grep -qx "$f" "$tmp/sdist.txt" || { echo "sdist lacks $f" >&2; exit 1; }
done
echo "sdist: $(basename "$sdist"), $(wc -l <"$tmp/sdist.txt") files, $(( $(stat -c %s "$sdist") / 1024 )) KiB"
echo "python: package checks $(( $(date +%s) - t0 )) s"
