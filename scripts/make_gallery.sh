#!/usr/bin/env bash
# Renders every style preset on the six sample meshes, and the lines from curvature on three, into examples/gallery/ (512 x 512 PNG),
# the pictures of examples/gallery.md. Usage: scripts/make_gallery.sh [OUT_DIR] [FORMAT]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-examples/gallery}
fmt=${2:-png}
mkdir -p "$out"
for mesh in fandisk bunny00 armadillo elephant ChineseDragon-10kv knot1; do
  for style in clean technical sketchy charcoal ink-brush hatched illustration; do
    build/src/inkline render "data/meshes/$mesh.off" -o "$out/$mesh-$style.$fmt" --size=512x512 --style="$style" --quiet
  done
done

# Lines from the surface's curvature (clean look): suggestive contours with the outline, and
# ridges and valleys.
for mesh in bunny00 armadillo elephant; do
  build/src/inkline render "data/meshes/$mesh.off" -o "$out/$mesh-suggestive.$fmt" --size=512x512 \
    --lines=silhouette,crease,border,suggestive --quiet
  build/src/inkline render "data/meshes/$mesh.off" -o "$out/$mesh-ridges.$fmt" --size=512x512 \
    --lines=silhouette,border,ridge,valley --quiet
done

# Each shipped offset table alone on the bunny (a style file per table, in a temporary directory
# next to the styles so that table names resolve).
tmp=$(mktemp -d styles/.gallery-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/offsets"
cp styles/offsets/*.txt "$tmp/offsets/"
for table in sawtooth lazy jittery jerky dashes circles; do
  printf '{"lines": {"default": {"colour": "#000000", "width": 1.0, "spacing": 1.0, "offsets": {"table": "%s"}}}}\n' \
    "$table" > "$tmp/table-$table.json"
  build/src/inkline render data/meshes/bunny00.off -o "$out/offsets-$table.$fmt" --size=512x512 \
    --style="$tmp/table-$table.json" --quiet
done
