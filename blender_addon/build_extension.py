#!/usr/bin/env python3
"""Package the Blender add-on with the dualspectra wheel (no Blender needed).

Two layouts:

* ``--legacy DIR``: ``DIR/dualspectra_blender/`` = the add-on + the ``dualspectra``
  package unzipped from the wheel as its subpackage ``dualspectra_blender/dualspectra/``
  (with the library's licence texts; Blender 3.4 - 4.1: copy DIR's content into
  ``<user scripts>/addons/`` or point ``BLENDER_USER_SCRIPTS`` at DIR's parent layout);
* ``--extension ZIP``: a Blender 4.2+ extension archive: the add-on files, its LICENSE and
  ``blender_manifest.toml`` at the root, the wheel(s) unmodified under ``wheels/`` and listed
  in the manifest, ``platforms`` derived from the wheels' tags. Give it the manylinux wheel
  (``scripts/setup.d/30-python.sh`` builds it), not a ``linux_x86_64`` one.

    python3 blender_addon/build_extension.py --wheel target/wheels/dualspectra-*.whl \\
        --legacy /tmp/scripts/addons --extension /tmp/dualspectra_blender-0.2.0.zip
"""

import argparse
import os
import re
import shutil
import sys
import zipfile

ADDON = os.path.join(os.path.dirname(os.path.abspath(__file__)), "dualspectra_blender")
PACKAGE = "dualspectra"


def addon_files():
    """Relative paths of the add-on's own files (sources and manifest, no caches)."""
    out = []
    for root, dirs, files in os.walk(ADDON):
        dirs[:] = [d for d in dirs if d not in ("__pycache__", PACKAGE, "wheels")]
        for f in files:
            if f.endswith((".py", ".toml")) or f == "LICENSE":
                out.append(os.path.relpath(os.path.join(root, f), ADDON))
    return sorted(out)


def wheel_platforms(wheel):
    """Blender platform names (``linux-x64``, ...) for a wheel file name's platform tag."""
    tag = os.path.basename(wheel)[:-len(".whl")].split("-")[-1]
    found = set()
    for t in tag.split("."):
        if t == "any":
            return {"linux-x64", "linux-arm64", "windows-x64", "windows-arm64", "macos-x64", "macos-arm64"}
        if t.startswith(("linux", "manylinux", "musllinux")):
            found.add("linux-arm64" if t.endswith("aarch64") else "linux-x64")
        elif t.startswith("win"):
            found.add("windows-arm64" if t.endswith("arm64") else "windows-x64")
        elif t.startswith("macosx"):
            if t.endswith(("arm64", "universal2")):
                found.add("macos-arm64")
            if t.endswith(("x86_64", "universal2", "intel")):
                found.add("macos-x64")
    if not found:
        raise SystemExit(f"unknown platform tag in {wheel}")
    return found


def build_legacy(wheel, out_dir):
    """Write ``out_dir/dualspectra_blender`` with the package from ``wheel`` beside the add-on."""
    dest = os.path.join(out_dir, "dualspectra_blender")
    if os.path.exists(dest):
        shutil.rmtree(dest)
    os.makedirs(dest)
    for rel in addon_files():
        if rel == "blender_manifest.toml":
            continue  # a legacy add-on has bl_info only
        os.makedirs(os.path.dirname(os.path.join(dest, rel)), exist_ok=True)
        shutil.copy2(os.path.join(ADDON, rel), os.path.join(dest, rel))
    with zipfile.ZipFile(wheel) as z:
        members = [n for n in z.namelist() if n.startswith(PACKAGE + "/")]
        if not any(re.search(r"/_dualspectra[^/]*\.(so|pyd|dylib)$", n) for n in members):
            raise SystemExit(f"{wheel} has no native {PACKAGE}/_dualspectra module")
        z.extractall(dest, members)
        # The library's licence texts (the wheel's .dist-info/licenses/) go with its copy.
        for n in z.namelist():
            if re.fullmatch(r"[^/]+\.dist-info/licenses/[^/]+", n):
                with open(os.path.join(dest, PACKAGE, os.path.basename(n)), "wb") as f:
                    f.write(z.read(n))
    return dest


def build_extension(wheels, out_zip):
    """Write the extension archive ``out_zip`` bundling ``wheels``."""
    with open(os.path.join(ADDON, "blender_manifest.toml"), encoding="utf-8") as f:
        manifest = f.read()
    names = [os.path.basename(w) for w in wheels]
    for n in names:
        if any(t.startswith("linux_") for t in n[:-len(".whl")].split("-")[-1].split(".")):
            raise SystemExit(f"{n}: a linux_* wheel is for this machine only; bundle a manylinux one "
                             "(maturin build --zig --compatibility manylinux_2_28)")
    platforms = sorted(set().union(*(wheel_platforms(w) for w in wheels)))
    listed = ", ".join(f'"./wheels/{n}"' for n in names)
    manifest, n_w = re.subn(r"(?m)^wheels = \[.*\]$", f"wheels = [{listed}]", manifest)
    manifest, n_p = re.subn(r"(?m)^platforms = \[.*\]$", "platforms = [" + ", ".join(f'"{p}"' for p in platforms) + "]", manifest)
    if n_w != 1 or n_p != 1:
        raise SystemExit("blender_manifest.toml must have one 'wheels = [...]' and one 'platforms = [...]' line")
    os.makedirs(os.path.dirname(os.path.abspath(out_zip)), exist_ok=True)
    with zipfile.ZipFile(out_zip, "w", zipfile.ZIP_DEFLATED) as z:
        for rel in addon_files():
            if rel == "blender_manifest.toml":
                z.writestr(rel, manifest)
            else:
                z.write(os.path.join(ADDON, rel), rel.replace(os.sep, "/"))
        for w, n in zip(wheels, names):
            z.write(w, "wheels/" + n)
    return out_zip


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--wheel", nargs="+", required=True, help="dualspectra wheel(s) built by maturin")
    parser.add_argument("--legacy", metavar="DIR", help="write DIR/dualspectra_blender (add-on + unzipped package)")
    parser.add_argument("--extension", metavar="ZIP", help="write a Blender 4.2+ extension archive")
    args = parser.parse_args(argv)
    for w in args.wheel:
        if not (w.endswith(".whl") and os.path.isfile(w)):
            raise SystemExit(f"not a wheel file: {w}")
    if not args.legacy and not args.extension:
        parser.error("give --legacy and/or --extension")
    if args.legacy:
        print("legacy add-on:", build_legacy(args.wheel[0], args.legacy))
    if args.extension:
        print("extension:", build_extension(args.wheel, args.extension))
    return 0


if __name__ == "__main__":
    sys.exit(main())
