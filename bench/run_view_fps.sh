#!/bin/bash
# Frames per second of the preview window's own loop (`inkline view --frames=N --orbit --fps`):
# the pipeline on the CPU every frame (features -> visibility), line quads, OpenGL draw and swap,
# the ImGui panel, under Xvfb with Mesa's software OpenGL (llvmpipe). Armadillo Loop-subdivided
# twice (832 k triangles), a 1024x768 window, an orbit of 3 degrees per frame (as run_tradeoff.sh);
# the exhaustive finder, and the randomized one with and without frame coherence; then the issue's
# command (200 frames over 180 degrees: 0.9 degrees a frame, where the window computes two views at
# once) and the same one view at a time; last, armadillo subdivided three times (3.3 M triangles)
# with the window's defaults at 0.9 degrees a frame.
# Writes its table to bench/results/view_fps.md (the file holds the current table only; earlier
# ones are in git's history).
# Usage: bench/run_view_fps.sh [build-dir] [frames]
set -euo pipefail
cd "$(dirname "$0")/.."
BIN="${1:-build}/src/inkline"
FRAMES="${2:-60}"
OUT=bench/results/view_fps.md
MODEL=data/meshes/armadillo.off
ARC=$((3 * FRAMES))
run() {  # label, then view arguments
    local label=$1; shift
    echo "== $label" >&2
    local line
    line=$(xvfb-run -a -s "-screen 0 1280x800x24" "$BIN" view "$MODEL" --subdivide=2 --size=1024x768 \
        --frames="$FRAMES" --orbit --arc="$ARC" --fps "$@" | grep -E '^(fps|cpu):' | tr '\n' ' ')
    line=${line#fps: }
    echo "| $label | \`$*\` | ${line/ cpu: /; CPU: } |" >>"$OUT.tmp"
}
{
    echo "### inkline view: armadillo@2 (832000 triangles), 1024x768, orbit 3 deg/frame, $FRAMES frames (unless the flags say otherwise)"
    echo
    echo "$(date -u +%Y-%m-%d) on $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at the start; $(xvfb-run -a glxinfo -B 2>/dev/null | grep -m1 'renderer string' | sed 's/.*: //' || echo 'renderer unknown')"
    echo
    echo "| setting | flags | measured |"
    echo "|---|---|---|"
} >"$OUT.tmp"
run "exhaustive" --finder=exhaustive
run "randomized 0.05, coherence" --finder=randomized
run "randomized 0.05, no coherence" --finder=randomized --no-coherence
run "randomized 0.002, coherence" --finder=randomized --fraction=0.002
run "randomized 0.002, no coherence" --finder=randomized --fraction=0.002 --no-coherence
run "exhaustive, no panel" --finder=exhaustive --no-panel
run "exhaustive, shading" --finder=exhaustive --shading
run "exhaustive, 2 threads" --finder=exhaustive --threads=2
run "randomized 0.002, coherence, 2 threads" --finder=randomized --fraction=0.002 --threads=2
# (the later --frames and --arc win)
run "randomized 0.05, coherence, 0.9 deg/frame" --finder=randomized --frames=200 --arc=180
run "randomized 0.05, coherence, 0.9 deg/frame, one view at a time" --finder=randomized --frames=200 --arc=180 --in-flight=1
# Issue 46's big model: armadillo@3 (3.3 M triangles), the window's defaults (the later --subdivide wins)
run "armadillo@3, defaults, 0.9 deg/frame" --subdivide=3 --frames=100 --arc=90
cat "$OUT.tmp"
mv "$OUT.tmp" "$OUT"
