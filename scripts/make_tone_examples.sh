#!/bin/sh
# Pictures of the tone lines (docs/tone.md) for examples/tone.md: bunny and armadillo, silhouettes
# only next to dark lines, highlight lines and the toon base coat, default camera and light.
# Usage: scripts/make_tone_examples.sh [BUILD_DIR] [DATA_DIR]
set -e
build=${1:-build}
data=${2:-data}
out=examples/tone
mkdir -p "$out"
# The bunny's folds are broad: a wider line (the seed's level of abstraction, section 3.4).
for spec in "bunny00 --tone-width=10" "armadillo --tone-width=6"; do
  set -- $spec
  mesh=$1 width=$2
  m="$data/meshes/$mesh.off"
  "$build/src/inkline" render "$m" -o "$out/$mesh-silhouette.png" --size=640x640 --lines=silhouette --quiet
  "$build/src/inkline" render "$m" -o "$out/$mesh-dark.png" --size=640x640 --lines=tone-dark $width --quiet
  "$build/src/inkline" render "$m" -o "$out/$mesh-tone.png" --size=640x640 $width \
    --lines=silhouette,tone-dark,tone-highlight --base=toon --quiet
  "$build/src/inkline" render "$m" -o "$out/$mesh-tone-sketchy.png" --size=640x640 $width \
    --lines=silhouette,tone-dark,tone-highlight --style=sketchy --quiet
done
# beta: tone edges kept (0) or only ridges (1), as the seed's Figure 4.
for beta in 0 1; do
  "$build/src/inkline" render "$data/meshes/armadillo.off" -o "$out/armadillo-beta$beta.png" --size=640x640 \
    --lines=tone-dark --tone-beta=$beta --quiet
done
# Section 3.4: the line width by depth and by edge length, a camera close to the armadillo's legs
# (a wide w so that the difference shows).
close="--eye=60,-10,140 --target=0,-10,0 --fov=40 --size=640x640 --tone-width=10 --lines=tone-dark,tone-highlight --base=toon"
for mode in constant depth edge-length; do
  "$build/src/inkline" render "$data/meshes/armadillo.off" -o "$out/armadillo-width-$mode.png" $close \
    --tone-line-width=$mode --quiet
done
# The window's GLSL pass (per-pixel lines, as the seed draws them) at render's default camera, under
# a virtual display when there is none.
run=""
[ -n "$DISPLAY" ] || run="xvfb-run -a -s '-screen 0 1280x1024x24'"
eval $run "$build/src/inkline" view "$data/meshes/armadillo.off" --frames=2 --size=640x640 --no-panel \
  --lines=silhouette,tone-dark,tone-highlight --base=toon --screenshot="$out/armadillo-window.png" > /dev/null
