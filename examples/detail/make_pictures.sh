#!/bin/sh
# The armadillo at three distances (the framed view, 3x and 8x farther), with and without
# --detail (docs/detail.md): the plain drawing darkens as the model recedes, the detail one keeps
# about the same density of lines. Usage: examples/detail/make_pictures.sh [INKLINE] [MESHES_DIR]
set -e
INKLINE=${1:-build/src/inkline}
MESHES=${2:-data/meshes}
OUT=$(dirname "$0")
T=0.0086,21.4529,0.0072            # the framed view's target (bounding-box centre)
for f in 1 3 8; do
  # eye = target + f * (the framed eye - target)
  EYE=$(awk -v f=$f 'BEGIN { printf "%.6f,%.6f,%.6f", 0.0086+f*242.5858, 21.4529+f*145.5515, 0.0072+f*339.6202 }')
  "$INKLINE" render "$MESHES/armadillo.off" --lines=silhouette,suggestive --size=768x768 --eye=$EYE --target=$T \
    -o "$OUT/armadillo-${f}x-plain.png" --quiet
  "$INKLINE" render "$MESHES/armadillo.off" --lines=silhouette,suggestive --size=768x768 --eye=$EYE --target=$T \
    --detail=5 -o "$OUT/armadillo-${f}x-detail.png" --quiet
done
