#!/usr/bin/env bash
# Installs what pleat builds and tests with, from Debian 12 packages.
# Idempotent and quiet when everything is already there.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config binutils
  libeigen3-dev libsuitesparse-dev libspectra-dev libopenblas-dev
  libassimp-dev libflatbuffers-dev flatbuffers-compiler libgtest-dev libminizip-dev zlib1g-dev
  python3-numpy python3-scipy python3-matplotlib
  nlohmann-json3-dev libtinygltf-dev libpng-dev
  libtorch-dev libopenblas0-pthread
  abigail-tools
  blender
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "setup: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
