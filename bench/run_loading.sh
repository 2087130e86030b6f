#!/bin/bash
# Loading a glTF (.glb) against loading the same mesh as OFF by inkline's own parser (issue 40,
# part 7: within 2x). The meshes are written by bench/load_probe (float positions in both files):
# bunny00 (75 k triangles) and armadillo@1 (208 k; armadillo@2, 832 k, with FULL=1). For each:
# whole-process timings of `inkline render FILE -o /dev/null --format=json` in alternated pairs
# (glb, OFF, glb, OFF, ...; after one warm-up each), the median of the per-pair ratios glb/OFF of
# CPU time (user + system) and of wall time; then the load alone in process (load_probe load, the
# fastest of 3: Assimp or the parser with the repairs, then the whole Model::load).
# Writes bench/results/loading.md. Usage: bench/run_loading.sh [build-dir] [pairs]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD="${1:-build}"
PAIRS="${2:-9}"
BIN="$BUILD/src/inkline"
PROBE="$BUILD/bench/load_probe"
OUT=bench/results/loading.md
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
meshes=(bunny00 armadillo@1)
[ "${FULL:-0}" = 1 ] && meshes+=(armadillo@2)
# CPU and wall seconds of one run: "cpu wall".
run_once() {
    /usr/bin/time -f "%U %S %e" -o "$tmp/time" "$BIN" render "$1" -o /dev/null --format=json >/dev/null 2>&1
    awk '{ printf "%.3f %.3f\n", $1 + $2, $3 }' "$tmp/time"
}
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
{
    echo "### Loading a .glb against the same mesh as OFF"
    echo
    echo "$(date -u +%Y-%m-%d), $(git rev-parse --short HEAD), $(nproc) cores, load average $(cut -d' ' -f1 /proc/loadavg) at the start."
    echo "Whole process: \`inkline render FILE -o /dev/null --format=json\`, $PAIRS alternated pairs (glb, OFF) after"
    echo "one warm-up each; medians of the runs and of the per-pair ratios glb/OFF. In process: load_probe load"
    echo "(fastest of 3): parse + repairs, then the whole Model::load (with Hilbert order and topology)."
    echo
    echo "| mesh | triangles | glb CPU s | OFF CPU s | glb/OFF CPU | glb/OFF wall | glb parse+repair s | OFF parse+repair s | glb Model::load s | OFF Model::load s |"
    echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    for m in "${meshes[@]}"; do
        "$PROBE" write "$m" "$tmp" >/dev/null
        run_once "$tmp/$m.glb" >/dev/null
        run_once "$tmp/$m.off" >/dev/null
        : >"$tmp/pairs"
        for _ in $(seq "$PAIRS"); do
            read -r gc gw < <(run_once "$tmp/$m.glb")
            read -r oc ow < <(run_once "$tmp/$m.off")
            echo "$gc $oc $gw $ow" >>"$tmp/pairs"
        done
        gcpu=$(awk '{ print $1 }' "$tmp/pairs" | median)
        ocpu=$(awk '{ print $2 }' "$tmp/pairs" | median)
        rcpu=$(awk '{ printf "%.3f\n", $1 / $2 }' "$tmp/pairs" | median)
        rwall=$(awk '{ printf "%.3f\n", $3 / $4 }' "$tmp/pairs" | median)
        g=$("$PROBE" load "$tmp/$m.glb" 3)
        o=$("$PROBE" load "$tmp/$m.off" 3)
        tris=$(echo "$g" | sed -n 's/.*: \([0-9]*\) triangles.*/\1/p')
        gp=$(echo "$g" | sed -n 's/.*parse+repair \([0-9.]*\) s.*/\1/p')
        op=$(echo "$o" | sed -n 's/.*parse+repair \([0-9.]*\) s.*/\1/p')
        gm=$(echo "$g" | sed -n 's/.*Model::load \([0-9.]*\) s.*/\1/p')
        om=$(echo "$o" | sed -n 's/.*Model::load \([0-9.]*\) s.*/\1/p')
        echo "| $m | $tris | $gcpu | $ocpu | $rcpu | $rwall | $gp | $op | $gm | $om |"
    done
} >"$OUT.tmp"
mv "$OUT.tmp" "$OUT"
cat "$OUT"
