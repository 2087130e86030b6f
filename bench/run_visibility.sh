#!/bin/bash
# Speed of the fast visibility (--visibility=appel) against the reference (rays): bench_frame's
# frame_appel (features + visibility), frame_appel_session (the same with storage reused from
# frame to frame, as the viewer runs it), frame_rays and visibility_appel (visibility alone) on each
# sample mesh, pinned to one core; on the subdivided armadillo also visibility_appel_2threads
# (build_pieces and assign_qi_appel on two threads, wall time, not pinned). With a second binary (an older build of
# bench_frame), the two run one after the other per mesh, so that both see the same machine load:
# compare within a run.
# Usage: bench/run_visibility.sh [bench_frame] [older bench_frame]   (a few minutes)
set -euo pipefail
cd "$(dirname "$0")/.."
NEW="${1:-build/bench/bench_frame}"
OLD="${2:-}"
run() {  # label, binary, mesh
    local f="^(frame_appel|frame_appel_session|frame_rays|visibility_appel)/$3\$"
    echo "== $3 $1 ($2)"
    taskset -c 1 "$2" --benchmark_filter="$f" 2>/dev/null | grep -E "^(frame|visibility)" || true
    case "$3" in *@*)
        "$2" --benchmark_filter="^visibility_appel_2threads/$3/real_time\$" 2>/dev/null | grep -E "^visibility" || true ;;
    esac
}
for m in fandisk bunny00 armadillo elephant ChineseDragon-10kv knot1 armadillo@1 armadillo@2; do
    if [ -n "$OLD" ]; then run before "$OLD" "$m"; fi
    run after "$NEW" "$m"
done
