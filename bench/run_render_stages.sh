#!/bin/bash
# Where a whole `inkline render MESH -o OUT.svg` spends its CPU (issue 46 item 3): RUNS renders
# recorded with perf (call stacks by DWARF, FREQ samples a second), each sample given to a stage by
# bench/render_stages.py, per thread. perf's own overhead inflates the figures by some percent;
# compare the shares, and the whole-process times of bench/run_load_speed.sh.
# Usage: bench/run_render_stages.sh [MESH] [build-dir] [RUNS] [FREQ]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD="${2:-build}"
DATA=$(sed -n 's/^INKLINE_DATA_DIR:[A-Z]*=//p' "$BUILD/CMakeCache.txt")
MESH="${1:-$DATA/meshes/armadillo.off}"
RUNS="${3:-10}"
FREQ="${4:-5000}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$BUILD/src/inkline" render "$MESH" -o "$tmp/out.svg" --quiet  # warm the file cache
perf record -q --call-graph=dwarf,16384 -F "$FREQ" -o "$tmp/perf.data" -- \
    sh -c "for i in \$(seq $RUNS); do '$BUILD/src/inkline' render '$MESH' -o '$tmp/out.svg' --quiet; done" 2>/dev/null
echo "$(basename "$MESH"): $RUNS renders to SVG, $FREQ Hz, load average $(cut -d' ' -f1 /proc/loadavg)"
echo
perf script -i "$tmp/perf.data" --comm inkline -F comm,pid,tid,ip,sym 2>/dev/null | python3 bench/render_stages.py "$FREQ" "$RUNS"
