#!/usr/bin/env bash
# Renders the README's pictures into docs/images/ (400 x 400 PNG), with the program built in build/:
# the README's "render your own model" commands, at that size.
# Usage: scripts/make_pictures.sh [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-docs/images}
inkline=build/src/inkline
mkdir -p "$out"
size=--size=400x400

# The default look: silhouettes, creases and borders.
$inkline render data/meshes/armadillo.off -o "$out/armadillo.png" $size --eye=-170,110,-330 --target=-5,20,0 \
  --fov=29 --quiet
# Hidden lines too, dashed and lighter by QI (the number of surfaces in front).
$inkline render data/meshes/bunny00.off -o "$out/bunny-hidden.png" $size --eye=-1.25,1.1,2.6 --target=0,-0.05,0 \
  --fov=27 --hidden --quiet
# A style preset: the illustration look, with suggestive contours in the folds.
$inkline render data/meshes/elephant.off -o "$out/elephant-illustration.png" $size --style=illustration \
  --eye=1.1,0.62,1.6 --quiet
# Freeform surfaces: Newell's teapot as Bezier patches, with Elber's isophote strokes.
$inkline render examples/teapot.bpt -o "$out/teapot-strokes.png" $size --strokes=isophote --points=6000 \
  --up=0,0,1 --eye=7,-9,5.5 --quiet
