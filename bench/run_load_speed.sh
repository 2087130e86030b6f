#!/bin/bash
# Loading and the whole render command (issue 46, item 3), before and after: `inkline render FILE
# -o OUT.svg` of an earlier build (BEFORE, e.g. main's binary before the loading work) against this
# build's, in alternated pairs (before, after, before, ...; one warm-up each), on the sample meshes
# and on armadillo subdivided twice (832 k triangles) written as ASCII OFF, binary PLY and binary STL
# by bench/load_probe. Per file: the median of the load's seconds as `render` reports them, the
# median whole-process wall time, the median of the per-pair ratios after/before, whether both
# drew the same SVG, and this build's stages in process (load_probe stages: CPU seconds of the
# thread, the least of 3), and the wall time until a render's first view can start (load_probe
# load: Model::load and the self-intersections, the least of 3) on one thread and on two (the
# Hilbert sorts side by side, the search beside the topology). Per render also the CPU time and
# the minor page faults (perf stat: task-clock, minor-faults) and the peak memory (/usr/bin/time,
# one run each). Then start-up alone (`--version`): times, the dynamic loader's cycles and
# relocations, the libraries an SVG render loads. Then issue 46's million triangles: Model::load of
# bunny00 subdivided twice (1.2 M triangles, binary PLY and ASCII OFF) on two threads, before
# (BEFORE_PROBE, default the load_probe beside BEFORE_INKLINE) and after, in alternated pairs twice:
# back to back, and after 6 s idle each (on a virtual machine whose host takes back freed memory,
# pages not touched for a few seconds cost 2-4 ms a MB to touch again: the case of a user's first
# render), with the peak resident memory. Writes bench/results/load_speed.md.
# Usage: bench/run_load_speed.sh BEFORE_INKLINE [build-dir] [pairs] [BEFORE_PROBE]
set -euo pipefail
cd "$(dirname "$0")/.."
BEFORE="${1:?usage: bench/run_load_speed.sh BEFORE_INKLINE [build-dir] [pairs] [BEFORE_PROBE]}"
BUILD="${2:-build}"
PAIRS="${3:-7}"
AFTER="$BUILD/src/inkline"
PROBE="$BUILD/bench/load_probe"
BEFORE_PROBE="${4:-$(dirname "$BEFORE")/load_probe}"
[ -x "$BEFORE_PROBE" ] || BEFORE_PROBE="$(dirname "$BEFORE")/../bench/load_probe"
DATA=$(sed -n 's/^INKLINE_DATA_DIR:[A-Z]*=//p' "$BUILD/CMakeCache.txt")
OUT=bench/results/load_speed.md
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$PROBE" write armadillo@2 "$tmp" >/dev/null
"$PROBE" write bunny00@2 "$tmp" >/dev/null
files=("$DATA/meshes/armadillo.off" "$DATA/meshes/fandisk.off" "$DATA/meshes/bunny00.off"
       "$tmp/armadillo@2.off" "$tmp/armadillo@2.ply" "$tmp/armadillo@2.stl")

# "wall_ms load_ms cpu_ms minor_faults" of one render (perf stat's own start-up is in the wall time
# of both builds alike).
run_once() {
    local t0 t1 load
    t0=$(date +%s%N)
    perf stat -x, -e task-clock,minor-faults -o "$tmp/stat" "$1" render "$2" -o "$3" >"$tmp/stdout" 2>/dev/null
    t1=$(date +%s%N)
    load=$(sed -n 's/^seconds: load \([0-9.]*\).*/\1/p' "$tmp/stdout")
    awk -F, -v w="$(( (t1 - t0) / 1000 ))" -v l="$load" '/task-clock/ { c = $1 } /minor-faults/ { f = $1 }
        END { printf "%.1f %.1f %.1f %d\n", w / 1000, l * 1000, c, f }' "$tmp/stat"
}
# Peak resident memory of one render, MiB.
peak_mib() { /usr/bin/time -f %M -o "$tmp/rss" "$1" render "$2" -o "$tmp/peak.svg" >/dev/null 2>&1; awk '{ printf "%.1f", $1 / 1024 }' "$tmp/rss"; }
# "cpu_ms wall_ms" of `BIN --version`: perf stat's task-clock (the process's CPU time, to the
# microsecond: /usr/bin/time counts in 10 ms) and the wall time of a run of its own (no perf).
cpu_wall() {
    local t0 t1
    perf stat -x, -e task-clock -o "$tmp/time" "$1" --version >/dev/null
    t0=$(date +%s%N)
    "$1" --version >/dev/null
    t1=$(date +%s%N)
    awk -F, -v w="$(( (t1 - t0) / 1000 ))" '/task-clock/ { printf "%.2f %.2f\n", $1, w / 1000 }' "$tmp/time"
}
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
{
    echo "### Loading and the whole render command, before and after"
    echo
    echo "$(date -u +%Y-%m-%d), $(git rev-parse --short HEAD), $(nproc) cores, load average $(cut -d' ' -f1 /proc/loadavg) at the start."
    echo "Whole process: \`inkline render FILE -o OUT.svg\`, $PAIRS alternated pairs (before, after) after one warm-up"
    echo "each; medians of the runs and of the per-pair ratios after/before. 'load' is the load's wall time as"
    echo "render prints it (Model::load: parse, repairs, Hilbert order, topology). In process, this build only:"
    echo "load_probe stages, CPU ms of the thread, the least of 3; 'ready' is load_probe load's wall ms of"
    echo "Model::load with the self-intersections, the least of 3, on 1 / 2 threads. CPU: the render's"
    echo "task-clock (all threads); faults: its minor page faults (medians); peak: its peak RSS (one run)."
    echo
    echo "| file | format | triangles | load ms before | load ms after | render ms before | render ms after | after/before | CPU ms before | CPU ms after | CPU after/before | faults before | faults after | peak MiB before | peak MiB after | same SVG | parse+repair | Hilbert | topology | self-intersections | ready 1 / 2 threads |"
    echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|"
    for f in "${files[@]}"; do
        name=$(basename "$f")
        ext="${name##*.}"
        format=$ext
        [ "$ext" = off ] && format="OFF (ASCII)"
        [ "$ext" = ply ] && format="PLY (binary)"
        [ "$ext" = stl ] && format="STL (binary)"
        run_once "$BEFORE" "$f" "$tmp/before.svg" >/dev/null
        run_once "$AFTER" "$f" "$tmp/after.svg" >/dev/null
        same=yes
        cmp -s "$tmp/before.svg" "$tmp/after.svg" || same=no
        : >"$tmp/pairs"
        for _ in $(seq "$PAIRS"); do
            read -r bw bl bc bf < <(run_once "$BEFORE" "$f" "$tmp/before.svg")
            read -r aw al ac af < <(run_once "$AFTER" "$f" "$tmp/after.svg")
            echo "$bw $bl $aw $al $bc $bf $ac $af" >>"$tmp/pairs"
        done
        col_median() { awk -v c="$1" '{ print $c }' "$tmp/pairs" | median; }
        bw=$(col_median 1) bl=$(col_median 2) aw=$(col_median 3) al=$(col_median 4)
        bc=$(col_median 5) bf=$(col_median 6) ac=$(col_median 7) af=$(col_median 8)
        ratio=$(awk '{ printf "%.3f\n", $3 / $1 }' "$tmp/pairs" | median)
        cpu_ratio=$(awk '{ printf "%.3f\n", $7 / $5 }' "$tmp/pairs" | median)
        s=$("$PROBE" stages "$f" 3)
        tris=$(echo "$s" | sed -n 's/.*: \([0-9]*\) triangles.*/\1/p')
        ms() { echo "$s" | sed -n "s/.*$1 \([0-9.]*\) s.*/\1/p" | awk '{ printf "%.1f", $1 * 1000 }'; }
        ready() { "$PROBE" load "$f" 3 "$1" | sed -n 's/.*load and self-intersections \([0-9.]*\) s.*/\1/p' | awk '{ printf "%.1f", $1 * 1000 }'; }
        echo "| $name | $format | $tris | $bl | $al | $bw | $aw | $ratio | $bc | $ac | $cpu_ratio | $bf | $af | $(peak_mib "$BEFORE" "$f") | $(peak_mib "$AFTER" "$f") | $same | $(ms 'parse+repair') | $(ms hilbert) | $(ms topology) | $(ms self-intersections) | $(ready 1) / $(ready 2) |"
    done
    echo
    echo "#### Start-up"
    echo
    echo "\`inkline --version\` (nothing but start-up and exit), $((3 * PAIRS)) alternated pairs: medians of the wall and"
    echo "CPU ms (perf stat's task-clock) and of the per-pair CPU ratio after/before; the"
    echo "dynamic loader's own figures (LD_DEBUG=statistics: its start-up cycles, the symbol relocations);"
    echo "the shared libraries an SVG render of armadillo loads (LD_DEBUG=files)."
    echo
    echo "| | wall ms | CPU ms | loader cycles | relocations | libraries loaded by an SVG render |"
    echo "|---|---:|---:|---:|---:|---:|"
    : >"$tmp/version"
    for _ in $(seq $((3 * PAIRS))); do
        b=$(cpu_wall "$BEFORE"); a=$(cpu_wall "$AFTER")
        echo "$b $a" >>"$tmp/version"
    done
    cpu_ratio=$(awk '{ printf "%.3f\n", $3 / $1 }' "$tmp/version" | median)
    for which in before after; do
        bin=$BEFORE; col=1
        [ "$which" = after ] && bin=$AFTER && col=3
        cpu=$(awk -v c=$col '{ print $c }' "$tmp/version" | median)
        wall=$(awk -v c=$((col + 1)) '{ print $c }' "$tmp/version" | median)
        stats=$(LD_DEBUG=statistics "$bin" --version 2>&1 >/dev/null)
        cycles=$(echo "$stats" | sed -n 's/.*total startup time in dynamic loader: \([0-9]*\) cycles.*/\1/p' | head -1)
        relocs=$(echo "$stats" | sed -n 's/.*final number of relocations: \([0-9]*\).*/\1/p' | head -1)
        libs=$(LD_DEBUG=files "$bin" render "$DATA/meshes/armadillo.off" -o "$tmp/libs.svg" 2>&1 >/dev/null | grep -c 'file=.*\[0\];  \(needed\|dynamically loaded\)' || true)
        echo "| $which | $wall | $cpu | $cycles | $relocs | $libs |"
    done
    echo
    echo "CPU ratio after/before (median of the pairs): $cpu_ratio."
    echo
    echo "#### A million triangles: Model::load"
    echo
    echo "bunny00 subdivided twice, \`load_probe load FILE 1 2\` (Model::load first in its process, as in a render;"
    echo "two threads), $PAIRS alternated pairs (before, after) back to back, then $PAIRS with 6 s idle before each run"
    echo "(a virtual machine's host takes back memory freed seconds ago: touching it again costs 2-4 ms a MB, the"
    echo "case of a user's first render). Medians of the seconds the probe prints, of the per-pair ratios"
    echo "after/before and of the peak resident memory (MiB); 'ready' is Model::load and the self-intersections"
    echo "that every view needs. Before: $BEFORE_PROBE."
    echo
    echo "| file | triangles | case | Model::load s before | after | s a million after | after/before | ready s before | after | peak MiB before | after |"
    echo "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|"
    # "model_s ready_s peak_mib" of one load.
    probe_once() {
        /usr/bin/time -f %M -o "$tmp/rss" "$1" load "$2" 1 2 >"$tmp/probe" 2>/dev/null
        sed -n 's/.*Model::load \([0-9.]*\) s, load and self-intersections \([0-9.]*\) s.*/\1 \2/p' "$tmp/probe" |
            awk -v k="$(cat "$tmp/rss")" '{ printf "%s %s %.1f\n", $1, $2, k / 1024 }'
    }
    for f in "$tmp/bunny00@2.ply" "$tmp/bunny00@2.off"; do
        tris=$("$PROBE" load "$f" 1 2 | sed -n 's/.*: \([0-9]*\) triangles.*/\1/p')
        for case in "back to back" "6 s idle"; do
            : >"$tmp/million"
            for _ in $(seq "$PAIRS"); do
                [ "$case" = "6 s idle" ] && sleep 6
                read -r bm br bp < <(probe_once "$BEFORE_PROBE" "$f")
                [ "$case" = "6 s idle" ] && sleep 6
                read -r am ar ap < <(probe_once "$PROBE" "$f")
                echo "$bm $br $bp $am $ar $ap" >>"$tmp/million"
            done
            col_median() { awk -v c="$1" '{ print $c }' "$tmp/million" | median; }
            am=$(col_median 4)
            per_million=$(awk -v s="$am" -v n="$tris" 'BEGIN { printf "%.3f", s * 1e6 / n }')
            ratio=$(awk '{ printf "%.3f\n", $4 / $1 }' "$tmp/million" | median)
            echo "| $(basename "$f") | $tris | $case | $(col_median 1) | $am | $per_million | $ratio | $(col_median 2) | $(col_median 5) | $(col_median 3) | $(col_median 6) |"
        done
    done
    echo
} >"$OUT.tmp"
mv "$OUT.tmp" "$OUT"
cat "$OUT"
