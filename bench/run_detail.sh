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
  cat <<'TEXT'
## Reading

- **Adaptation a frame** (the front's update, one core) on the 1 M-triangle models along the slow
  dolly, this run (load average 10-11 on 2 cores): median 3.8 ms (armadillo@2) and 3.7 ms
  (bunny00@2) without geomorphs, 7.5 and 6.2 ms with them; along the orbit 2.0-2.4 ms. The
  target (< 5 ms) holds without geomorphs and is missed with them on the dolly. Alternated runs
  of main and this code in one window (armadillo@2, load 10): with geomorphs on the dolly 7.5 ms
  (16.2 worst) on main, 6.0 (18.3) with the retry stamps, 5.3 (13.4) with the band guard measured
  without a trial collapse; on the orbit 5.5-5.6 ms on main, 1.0-1.8 ms with the stamps (blocked
  vertices no longer retried each frame). What remains on the dolly is the operations themselves
  (~280 a frame, each O(degree^2) in the link test and the rings' areas). The worst frames,
  10-17 ms, are those where a band of vertices crosses a threshold together.
- **Size follows the image**: 87 k -> 7 k triangles over the 4x dolly on armadillo@2 (106 k -> 8 k
  on bunny00@2), the same order as the 52 k armadillo at the same image size (5.6 k).
- **Memory kept**: pm keeps the hierarchy (8 B a vertex) and the front (115 B a vertex on
  armadillo@2, 125 on bunny00@2, geomorphs or not): 123-133 B a vertex against multi-scale's 147
  for its levels, 16 % below on armadillo@2 -- not "well below". pm also keeps its own copy of the
  input (48 B a vertex) where multi-scale uses the model's. The builds' peak RSS: 283 against
  698 MiB (armadillo@2), 402 against 990 MiB (bunny00@2).
- **Whole frame**: pm 52-80 ms CPU against multi-scale's 11-20 ms (armadillo and bunny00, both
  paths; was 127-150 ms): the adapted mesh is no longer searched for self-intersections when the
  input has none, but pm still builds a new Model (topology, curvature, ray index) of the adapted
  mesh each frame while multi-scale moves the vertices of one kept Model.
- **Density and coherence**: both methods draw about the same line density along both paths
  (armadillo dolly 0.0209 -> 0.0088 pm, 0.0228 -> 0.0088 multi-scale) and change the same share
  of their lines between frames (0.48 / 0.47 on the dolly, 0.21 / 0.21 on the orbit: mostly the
  camera's motion, which this measure does not tell from popping). Largest geomorph move a frame:
  0.5-2.3 px.
- **Build**: pm's hierarchy is OpenMesh's decimater, about twice multi-scale's pre-process (23 s
  against 10 s CPU on armadillo@2).
TEXT
} > "$tmp"
chmod 644 "$tmp"
mv "$tmp" "$out"
