#!/bin/sh
# The armadillo at three distances (the framed view, 3x and 8x farther), plain, with --detail
# (the default umbrella levels) and with --detail-fairing=second-order --detail-ratio=0.75
# (docs/detail.md): the plain drawing darkens as the model recedes, the detail ones keep about the
# same density of lines.
# Then, where ImageMagick is installed, the rows side by side (armadillo-rows.png) and the middle
# of the 3x and 8x pictures magnified 3x without smoothing (armadillo-far-zoom.png), so that the
# far drawings' pixels can be compared. See examples/detail.md.
# Usage: examples/detail/make_pictures.sh [INKLINE] [MESHES_DIR]
set -e
INKLINE=${1:-build/src/inkline}
MESHES=${2:-data/meshes}
OUT=$(dirname "$0")
T=0.0086,21.4529,0.0072            # the framed view's target (bounding-box centre)
for f in 1 3 8; do
  # eye = target + f * (the framed eye - target)
  EYE=$(awk -v f=$f 'BEGIN { printf "%.6f,%.6f,%.6f", 0.0086+f*242.5858, 21.4529+f*145.5515, 0.0072+f*339.6202 }')
  COMMON="render $MESHES/armadillo.off --lines=silhouette,suggestive --size=768x768 --eye=$EYE --target=$T --quiet"
  "$INKLINE" $COMMON -o "$OUT/armadillo-${f}x-plain.png"
  "$INKLINE" $COMMON --detail=5 -o "$OUT/armadillo-${f}x-detail.png"
  "$INKLINE" $COMMON --detail=5 --detail-fairing=second-order --detail-ratio=0.75 -o "$OUT/armadillo-${f}x-second-order.png"
done
if convert -version 2>/dev/null | grep -q ImageMagick; then
  cd "$OUT"
  row() { convert "armadillo-1x-$1.png" "armadillo-3x-$1.png" "armadillo-8x-$1.png" +append "$2"; }
  row plain /tmp/inkline_row_plain.png
  row detail /tmp/inkline_row_detail.png
  row second-order /tmp/inkline_row_second.png
  convert /tmp/inkline_row_plain.png /tmp/inkline_row_detail.png /tmp/inkline_row_second.png -append -resize 50% armadillo-rows.png
  zoom() { convert "armadillo-$1-$2.png" -gravity center -crop "$3x$3+0+0" +repage -filter point -resize "$4" "/tmp/inkline_zoom_$1_$2.png"; }
  for k in plain detail second-order; do
    zoom 3x $k 256 300%
    zoom 8x $k 96 800%
    convert "/tmp/inkline_zoom_3x_$k.png" "/tmp/inkline_zoom_8x_$k.png" +append "/tmp/inkline_zoom_$k.png"
  done
  convert /tmp/inkline_zoom_plain.png /tmp/inkline_zoom_detail.png /tmp/inkline_zoom_second-order.png -append -resize 50% armadillo-far-zoom.png
  rm -f /tmp/inkline_row_*.png /tmp/inkline_zoom_*.png
fi
