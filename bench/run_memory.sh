#!/bin/bash
# Peak memory of one render (load, Loop subdivision, topology, one frame's features, visibility
# with the self-intersection test, and the output) per triangle: /usr/bin/time -v's maximum
# resident set size divided by the triangle count. Armadillo Loop-subdivided 0..3 times (3 M
# triangles at 3). Issue 7's target: <= 200 bytes per triangle for the 3 M model.
# Writes bench/results/memory.md. Usage: bench/run_memory.sh [build-dir] [max-level]
set -euo pipefail
cd "$(dirname "$0")/.."
BIN="${1:-build}/src/inkline"
MAX="${2:-3}"
OUT=bench/results/memory.md
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
{
    echo "### Peak memory of \`inkline render data/meshes/armadillo.off --subdivide=N -o F.json\`"
    echo
    echo "$(date -u +%Y-%m-%d), $(git rev-parse --short HEAD), /usr/bin/time -v (maximum resident set size)"
    echo
    echo "| subdivide | triangles | peak RSS (KiB) | bytes per triangle | wall s |"
    echo "|---:|---:|---:|---:|---:|"
    for n in $(seq 0 "$MAX"); do
        /usr/bin/time -v "$BIN" render data/meshes/armadillo.off --subdivide="$n" -o "$tmp/a.json" 2>"$tmp/time" >/dev/null
        kb=$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$tmp/time")
        wall=$(sed -n 's/.*Elapsed (wall clock) time (h:mm:ss or m:ss): //p' "$tmp/time")
        tris=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['stats']['triangles'])" "$tmp/a.json")
        echo "| $n | $tris | $kb | $(python3 -c "print(round($kb * 1024 / $tris))") | $wall |"
    done
} >"$OUT.tmp"
mv "$OUT.tmp" "$OUT"
cat "$OUT"
