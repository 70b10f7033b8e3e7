#!/usr/bin/env bash
# MeshLab 2025.07 / PyMeshLab 2025.7 filter plugin (meshlab_filter/, -DMESHLAB_VERSION=2025.07):
#  - apt: Qt5, GLEW, Eigen (the headers MeshLab's plugin interface includes), cmake, g++, xz.
#  - from Debian sid, through a private apt configuration in target/meshlab-2025.07-src/apt
#    (the system's apt sources are left as they are):
#    . MeshLab 2025.07's sources (src/common: the plugin interface; src/vcglib): the upstream
#      tarball of Debian's source package, checked against the sha256 pinned below (not apt's
#      exit status: the mirror may serve the tarball without the .dsc), unpacked into
#      target/meshlab-2025.07-src/tree;
#    . the MeshLab 2025.07 application's libmeshlab-common.so (float scalars, from Debian's
#      binary package, checked by apt against sid's signed index), into
#      target/meshlab-2025.07-src/app: the float build of the plugin is linked against it in
#      the tests, so that every MeshLab symbol the plugin uses is known to exist there. Optional:
#      when sid has no 2025.07 binary any more, the float build is linked with MeshLab's symbols
#      left undefined (as for users) and this check is skipped.
#    Reruns with both in place are no-ops.
#  - PyMeshLab 2025.7.post1 (PyPI; needs only numpy, which .venv pins) into the project venv
#    .venv made by 30-python.sh (skipped, with a note, when there is none): the headless host
#    the plugin is tested in, and the libmeshlab-common.so (double scalars) the PyMeshLab build
#    of the plugin links against.
# DUALSPECTRA_SKIP_MESHLAB=1 skips this stage. DUALSPECTRA_SID_MIRROR: the Debian mirror
# (default http://deb.debian.org/debian).
set -euo pipefail
cd "$(dirname "$0")/../.."
[ "${DUALSPECTRA_SKIP_MESHLAB:-0}" = 1 ] && { echo "meshlab 2025.07: skipped (DUALSPECTRA_SKIP_MESHLAB=1)"; exit 0; }

version=2025.07
tarball="meshlab_${version}~dfsg.orig.tar.xz"
sha256=d22c98d362f2a284e481af8dbfc272b2222f5b9c67b3cf8bec57d1c3161886f4
pymeshlab=2025.7.post1
root=target/meshlab-${version}-src
say() { echo "meshlab $version: $*"; }

pkgs=(cmake g++ make xz-utils qtbase5-dev libqt5opengl5-dev libglew-dev libeigen3-dev)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  say "installing ${missing[*]}"
  ${SUDO:-} apt-get install -y -q --no-install-recommends -o DPkg::Lock::Timeout=900 "${missing[@]}"
fi

have_tree() { [ -f "$root/.sha256" ] && [ "$(cat "$root/.sha256")" = "$sha256" ] \
                && [ -f "$root/tree/src/common/plugins/interfaces/filter_plugin.h" ]; }
have_app() { [ -f "$root/app/libmeshlab-common.so" ] || [ -f "$root/app/none" ]; }

if have_tree && have_app; then
  say "source tree cached in $root/tree; application library: $(cat "$root/app/version" 2>/dev/null || echo none)"
else
  have_tree || rm -rf "$root"
  mkdir -p "$root/apt/lists/partial" "$root/apt/cache/archives/partial" "$root/apt/download" "$root/app"
  root_abs=$(cd "$root" && pwd)
  mirror=${DUALSPECTRA_SID_MIRROR:-http://deb.debian.org/debian}
  keyring=/usr/share/keyrings/debian-archive-keyring.gpg
  printf 'deb-src [signed-by=%s] %s sid main\ndeb [arch=amd64 signed-by=%s] %s sid main\n' \
    "$keyring" "$mirror" "$keyring" "$mirror" >"$root/apt/sources.list"
  touch "$root/apt/status"
  apt_private=(-o "Dir::Etc::SourceList=$root_abs/apt/sources.list" -o Dir::Etc::SourceParts=/nonexistent
               -o "Dir::State::Lists=$root_abs/apt/lists" -o "Dir::Cache=$root_abs/apt/cache"
               -o "Dir::State::status=$root_abs/apt/status" -o APT::Sandbox::User=root)
  say "fetching Debian sid's package indexes from $mirror"
  apt-get -qq "${apt_private[@]}" update

  if ! have_tree; then
    # The source package version whose upstream tarball is the pinned one.
    pkg_version=$(apt-cache "${apt_private[@]}" showsrc meshlab 2>/dev/null | awk -v sum="$sha256" -v file="$tarball" '
      /^Package: / { v = "" }
      /^Version: / { v = $2 }
      $1 == sum && $3 == file && v != "" { print v; exit }')
    if [ -z "$pkg_version" ]; then
      echo "meshlab $version: Debian sid no longer has a meshlab source package with $tarball (sha256 $sha256);" \
           "the MeshLab $version plugin cannot be built from it. Point MESHLAB_SOURCE_DIR at a MeshLab $version" \
           "source tree (or unpack $tarball into $root/tree), or update the pin in $0." >&2
      exit 1
    fi
    # Exits non-zero when the mirror serves the tarball but not the .dsc/.debian.tar.xz: the
    # checksum below decides.
    ( cd "$root/apt/download" && apt-get -q "${apt_private[@]}" source --download-only "meshlab=$pkg_version" ) \
      >"$root/apt/source.log" 2>&1 || true
    if [ ! -f "$root/apt/download/$tarball" ] \
       || ! echo "$sha256  $root/apt/download/$tarball" | sha256sum -c --quiet -; then
      cat "$root/apt/source.log" >&2
      echo "meshlab $version: $tarball (meshlab $pkg_version) was not downloaded from $mirror, or its sha256 is" \
           "not $sha256" >&2
      exit 1
    fi
    tar -xJf "$root/apt/download/$tarball" -C "$root" --no-same-owner
    tree=$(find "$root" -maxdepth 1 -mindepth 1 -type d -name 'meshlab-*' | head -n1)
    [ -n "$tree" ] && [ -f "$tree/src/common/plugins/interfaces/filter_plugin.h" ] \
      || { echo "meshlab $version: no MeshLab source tree in $tarball" >&2; exit 1; }
    mv "$tree" "$root/tree"
    echo "$sha256" >"$root/.sha256"
    say "source tree ($tarball, meshlab $pkg_version) in $root/tree"
  fi

  # The application's library, from the binary package of the same upstream version.
  app_version=$(apt-cache "${apt_private[@]}" policy meshlab 2>/dev/null | awk '/Candidate:/ { print $2 }')
  rm -f "$root/app/"*
  if [[ "$app_version" == "$version"~* ]] \
     && ( cd "$root/apt/download" && apt-get -qq "${apt_private[@]}" download "meshlab=$app_version" ) 2>"$root/apt/download.log"; then
    dpkg-deb -x "$root/apt/download/meshlab_${app_version//:/%3a}_amd64.deb" "$root/apt/deb"
    lib=$(find "$root/apt/deb" -name libmeshlab-common.so -print -quit)
    [ -n "$lib" ] || { echo "meshlab $version: no libmeshlab-common.so in meshlab $app_version" >&2; exit 1; }
    cp "$lib" "$root/app/libmeshlab-common.so"
    echo "$app_version" >"$root/app/version"
    say "application library (meshlab $app_version) in $root/app"
  else
    touch "$root/app/none"
    say "no meshlab $version binary package in sid (candidate: ${app_version:-none}); the float build's" \
        "link check against the application's library will be skipped"
  fi
  rm -rf "$root/apt"
fi

if [ ! -x .venv/bin/python ]; then
  say "PyMeshLab not installed: no .venv (scripts/setup.d/30-python.sh makes it)"
  exit 0
fi
.venv/bin/python -m pip install -q --disable-pip-version-check "pymeshlab==$pymeshlab"
say "$(.venv/bin/python -c 'import importlib.metadata as m; print("pymeshlab", m.version("pymeshlab"))')"
