#!/usr/bin/env bash
# MeshLab filter plugin (meshlab_filter/): build deps and the MeshLab 2020.09 source tree.
#  - apt: meshlab (meshlabserver + libmeshlab-common.so), Qt5, GLEW, Eigen, cmake,
#    xvfb/xauth (meshlabserver aborts without a display), dpkg-dev (apt-get source).
#  - the plugin headers come from Debian's source package of the same version as the
#    binary package: a deb-src entry mirroring the existing apt sources is added once,
#    and the unpacked tree is cached under target/meshlab-src (reruns are no-ops).
# Set DUALSPECTRA_SKIP_MESHLAB=1 to skip this stage.
set -euo pipefail
cd "$(dirname "$0")/../.."
[ "${DUALSPECTRA_SKIP_MESHLAB:-0}" = 1 ] && { echo "meshlab: skipped (DUALSPECTRA_SKIP_MESHLAB=1)"; exit 0; }

pkgs=(meshlab xvfb xauth cmake g++ make dpkg-dev qtbase5-dev libqt5opengl5-dev libglew-dev libeigen3-dev)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "meshlab: installing ${missing[*]}"
  ${SUDO:-} apt-get install -y -q --no-install-recommends -o DPkg::Lock::Timeout=900 "${missing[@]}"
fi

src_root=target/meshlab-src
version=$(dpkg-query -W -f='${Version}' meshlab)
stamp="$src_root/.version"
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$version" ] && [ -d "$src_root/tree/src/common" ]; then
  echo "meshlab: source tree $version cached in $src_root/tree"
  exit 0
fi

# deb-src entries: the same mirrors and suites as the binary sources.
if ! apt-cache showsrc meshlab 2>/dev/null | grep -q '^Package: meshlab'; then
  list=/etc/apt/sources.list.d/dualspectra-deb-src.sources
  tmp=$(mktemp)
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] && [ "$f" != "$list" ] || continue
    # keep only stanzas of Debian archives (deb.debian.org, snapshot, mirrors of debian)
    awk 'BEGIN{RS=""; ORS="\n\n"} /Types:[^\n]*deb/ && /URIs:[^\n]*debian/ {
           gsub(/Types:[^\n]*/, "Types: deb-src"); print }' "$f" >>"$tmp"
  done
  if [ -f /etc/apt/sources.list ]; then
    grep -E '^deb[[:space:]]' /etc/apt/sources.list | grep debian | while read -r _ rest; do
      printf 'Types: deb-src\nURIs: %s\nSuites: %s\nComponents: %s\n\n' \
        "$(echo "$rest" | sed -E 's/^\[[^]]*\][[:space:]]*//' | awk '{print $1}')" \
        "$(echo "$rest" | sed -E 's/^\[[^]]*\][[:space:]]*//' | awk '{print $2}')" \
        "$(echo "$rest" | sed -E 's/^\[[^]]*\][[:space:]]*//' | cut -d' ' -f3-)"
    done >>"$tmp"
  fi
  [ -s "$tmp" ] || { echo "meshlab: no Debian apt source found to mirror as deb-src" >&2; exit 1; }
  ${SUDO:-} install -m 644 "$tmp" "$list"
  rm -f "$tmp"
  echo "meshlab: added $list"; cat "$list"
  ${SUDO:-} apt-get update -qq -o DPkg::Lock::Timeout=900
fi

rm -rf "$src_root"
mkdir -p "$src_root"
( cd "$src_root" && apt-get source -q "meshlab=$version" )
tree=$(find "$src_root" -maxdepth 1 -mindepth 1 -type d -name 'meshlab-*' | head -n1)
[ -n "$tree" ] && [ -d "$tree/src/common" ] || { echo "meshlab: unpacked source tree not found in $src_root" >&2; exit 1; }
mv "$tree" "$src_root/tree"
rm -f "$src_root"/*.tar.* "$src_root"/*.dsc
echo "$version" >"$stamp"
echo "meshlab: source tree $version in $src_root/tree"
