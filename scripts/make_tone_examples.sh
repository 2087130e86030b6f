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
