#!/usr/bin/env bash
# Installs the Debian 12 packages libbrdf needs, only those that are missing.
# Usage: scripts/install_deps.sh [--with-renderers]   (renderers: blender, povray)
set -euo pipefail
packages=(cmake g++ make pkg-config libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev nlohmann-json3-dev
          libopenimageio-dev openimageio-tools libopenexr-dev libtbb-dev libhwy-dev libboost-dev zlib1g-dev
          python3 python3-dev python3-numpy python3-matplotlib python3-openimageio pybind11-dev)
if [[ "${1:-}" == "--with-renderers" ]]; then
  packages+=(povray blender)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "libbrdf: installing missing Debian packages: ${missing[*]}" >&2
  sudo_cmd=()
  [[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
