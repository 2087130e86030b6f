#!/bin/bash
# The exact frame on 1 and more threads (docs/threads.md): bench/frame_threads on armadillo@2,
# armadillo@3 and bunny00@2 along the bench's orbit, stage by stage (median ms per frame, wall
# clock), each stage's share of the frame, the frame's CPU time over all threads and whether every
# drawing equals the one-thread one. The thread counts take turns frame by frame in one process,
# so a burst of load slows each alike; on a shared machine read the ratios and the load average
# printed with each table. Writes bench/results/threads.md (to a temporary file, then renamed).
# Usage: bench/run_threads.sh [build dir (default build)] [thread counts (default 1,2)] [frames (default 30)]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD="${1:-build}"
COUNTS="${2:-1,2}"
FRAMES="${3:-30}"
OUT=bench/results/threads.md
TMP="$(mktemp "$OUT.XXXXXX")"
trap 'rm -f "$TMP"' EXIT
{
    echo "# The exact frame on several threads"
    echo
    echo "Written by bench/run_threads.sh on $(date -u +%Y-%m-%d), $(nproc) hardware threads"
    echo "($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')), load average at the start"
    echo "$(cut -d' ' -f1-3 /proc/loadavg). The frame: exhaustive finder and Appel visibility (visible lines,"
    echo "walks on), 1024x1024, the bench's orbit; ms are medians per frame, wall clock. \"frame, rest\" is"
    echo "the frame's time outside the stages (clock reads, bookkeeping)."
    echo
} > "$TMP"
for mesh in armadillo@2 armadillo@3 bunny00@2; do
    "$BUILD/bench/frame_threads" "$mesh" --frames="$FRAMES" --threads="$COUNTS" --markdown="$TMP" > /dev/null
done
mv "$TMP" "$OUT"
trap - EXIT
echo "wrote $OUT"
