#!/bin/bash
# Speed of the fast visibility (--visibility=appel) against the reference (rays): bench_frame's
# frame_appel (features + visibility), frame_rays and visibility_appel (visibility alone) on each
# sample mesh, pinned to one core. With a second binary (an older build of bench_frame), the two
# run one after the other per mesh, so that both see the same machine load: compare within a run.
# Usage: bench/run_visibility.sh [bench_frame] [older bench_frame]   (a few minutes)
set -euo pipefail
cd "$(dirname "$0")/.."
NEW="${1:-build/bench/bench_frame}"
OLD="${2:-}"
for m in fandisk bunny00 armadillo elephant ChineseDragon-10kv knot1 armadillo@1 armadillo@2; do
    f="^(frame_appel|frame_rays|visibility_appel)/$m\$"
    if [ -n "$OLD" ]; then
        echo "== $m before ($OLD)"
        taskset -c 1 "$OLD" --benchmark_filter="$f" 2>/dev/null | grep -E "^(frame|visibility)"
    fi
    echo "== $m after ($NEW)"
    taskset -c 1 "$NEW" --benchmark_filter="$f" 2>/dev/null | grep -E "^(frame|visibility)"
done
