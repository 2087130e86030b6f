#!/usr/bin/env bash
# One-command set-up on a fresh Debian 12 machine: installs the Debian packages inkline uses,
# extracts the sample meshes of libcgal-demo into data/, builds in Release (build/), and renders
# an example drawing into examples/. Safe to run again. Needs root (or sudo) for apt-get.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake ninja-build pkg-config
  libopenmesh-dev libcgal-dev libcgal-demo libeigen3-dev libgmp-dev libmpfr-dev libboost-dev
  libembree-dev libtbb-dev libglm-dev libcairo2-dev nlohmann-json3-dev
  libgtest-dev libbenchmark-dev
  libassimp-dev assimp-testmodels
  librsvg2-bin poppler-utils parallel
  libglfw3-dev libimgui-dev libgl-dev libglx-mesa0 libgl1-mesa-dri xvfb xauth
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends "${missing[@]}"
fi

# Sample meshes (armadillo, bunny, fandisk, elephant, dragon, ...) from libcgal-demo; not committed.
archive=/usr/share/doc/libcgal-dev/data.tar.gz
[ -f "$archive" ] || archive=/usr/share/doc/libcgal-demo/data.tar.gz
if [ ! -f data/meshes/armadillo.off ]; then
  mkdir -p data
  tar -xzf "$archive" -C data --strip-components=1 data/meshes
fi

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build

# The example: the fandisk with its hidden lines, as SVG and PNG.
mkdir -p examples/out
build/src/inkline render data/meshes/fandisk.off -o examples/out/fandisk.svg --hidden
build/src/inkline render data/meshes/fandisk.off -o examples/out/fandisk.png --hidden --quiet
echo "setup: done; example drawing in examples/out/fandisk.svg and .png"
