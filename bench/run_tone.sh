#!/bin/sh
# The tone pass's benchmark (bench/bench_tone.cpp) into bench/results/tone.md: per-stage wall
# times at 800x600 and 1024x1024 on 1 and 2 threads (armadillo), the single thread's CPU time,
# and the agreement with suggestive contours and the lines' movement under a 1 degree light turn.
# Usage: bench/run_tone.sh [BUILD_DIR]   (build the bench_tone target first)
set -e
build=${1:-build}
out=bench/results/tone.md
tmp=$(mktemp)
{
  echo "# Tone lines: per-stage times and agreement"
  echo
  echo "Made by \`bench/run_tone.sh\` at $(git rev-parse --short HEAD) on $(nproc) cores, load average" \
       "$(cut -d' ' -f1-3 /proc/loadavg) when it started. Times in ms: medians (and the least total) of 15" \
       "passes into the same storage after one warm-up; the defaults (w = 6, beta = 0.2, dark and highlight" \
       "lines, default light, framed camera)."
  echo
  "$build/bench/bench_tone" armadillo bunny00
  echo
  "$build/bench/bench_tone" --agreement
} > "$tmp"
mv "$tmp" "$out"
echo "wrote $out"
