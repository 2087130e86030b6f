#!/bin/sh
# The two detail-control methods side by side (issues 43 and 44) into bench/results/detail_methods.md:
# `inkline bench --detail=3` along a dolly and an orbit on armadillo and bunny00 (build time,
# stored memory, triangles, splits and collapses, ms a frame, line density, coherence), then the
# progressive mesh's incremental front on the 1 M-triangle models (bench/pm_frames: hierarchy and
# multi-scale build and memory, adaptation ms a frame on one core along a slow dolly and an orbit).
# Usage: bench/run_detail.sh [BUILD_DIR] [DATA_DIR]   (build the inkline and pm_frames targets first;
# the 1 M-triangle runs take several minutes: the hierarchy build is OpenMesh's decimater)
set -e
build=${1:-build}
data=${2:-data}
out=bench/results/detail_methods.md
tmp=$(mktemp)
{
  echo "# Detail control: multi-scale and progressive mesh side by side"
  echo
  echo "Made by \`bench/run_detail.sh\` at $(git rev-parse --short HEAD) on $(nproc) cores, load average" \
       "$(cut -d' ' -f1-3 /proc/loadavg) when it started. Times are the thread's CPU time on one core" \
       "(multi-scale's adapt column: its blend's wall time). 1024 x 1024, silhouettes and suggestive" \
       "contours, exhaustive finder, Appel visibility. pm: geomorphs of 0.5 s at 25 frames a second," \
       "temporal smoothing 0.8 s to 90 %; the front settled at the first view. Changed lines: visible" \
       "line samples (1 px apart) farther than 1 px from the other frame's lines, both ways, over both" \
       "frames' samples (camera motion included)."
  echo
  for m in armadillo bunny00; do
    "$build/src/inkline" bench "$data/meshes/$m.off" --detail=3 --path=dolly --frames=60 2>/dev/null
    echo
    "$build/src/inkline" bench "$data/meshes/$m.off" --detail=3 --path=orbit --frames=60 --arc=60 2>/dev/null
    echo
  done
  echo "## The incremental front on 1 M-triangle models (bench/pm_frames)"
  echo
  for m in armadillo armadillo@2 bunny00@2; do
    "$build/bench/pm_frames" "$m" 3
    echo
  done
} > "$tmp"
mv "$tmp" "$out"
