#!/bin/sh
# Instructions an operation of the progressive mesh's front (issue 44), into
# bench/results/pm_instructions.md: callgrind counts the instructions of AdaptiveFront::update alone
# (load-independent, where the ms a frame of bench/pm_frames move with the shared machine's load)
# along pm_frames' slow dolly with geomorphs and the sessions' budget, and divides the inclusive
# counts of try_collapse (a geomorph start with the refused tries around it) and advance_morphs
# (the running morphs advanced each frame and each end's collapse) by the starts and ends made.
# Usage: bench/run_pm_instructions.sh [BUILD_DIR] [MODEL...]   (build the pm_frames target first;
# about a minute a 52 k-triangle model under valgrind)
set -e
build=${1:-build}
shift 2>/dev/null || true
models=${*:-armadillo bunny00}
out=bench/results/pm_instructions.md
tmp=$(mktemp -d)
{
  echo "# Instructions an operation of the pm front (callgrind)"
  echo
  echo "Made by \`bench/run_pm_instructions.sh\` at $(git rev-parse --short HEAD): \`pm_frames MODEL 3"
  echo "--no-multiscale --path=dolly --geomorphs=on --budget=lag --per-frame\` under"
  echo "\`valgrind --tool=callgrind --toggle-collect='inkline::AdaptiveFront::update*'\`. A start's count"
  echo "is try_collapse's inclusive instructions over the geomorphs started (refused tries included),"
  echo "an end's advance_morphs' over the geomorphs ended (every running morph advanced each frame"
  echo "included); the scan is update's own instructions (every active vertex tested a frame)."
  echo
  echo "| model | instructions in update | geomorph starts | ends | splits | a start | an end | the scan and the rest, update's own |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|"
  for m in $models; do
    valgrind --tool=callgrind --callgrind-out-file="$tmp/cg.$m" --toggle-collect='inkline::AdaptiveFront::update*' \
      "$build/bench/pm_frames" "$m" 3 --no-multiscale --path=dolly --geomorphs=on --budget=lag --per-frame \
      >/dev/null 2>"$tmp/$m.err"
    inclusive() { callgrind_annotate --inclusive=yes "$tmp/cg.$m" | grep "AdaptiveFront::$1(" | head -1 | awk '{gsub(",", "", $1); print $1}'; }
    self() { callgrind_annotate "$tmp/cg.$m" | grep "AdaptiveFront::$1(" | head -1 | awk '{gsub(",", "", $1); print $1}'; }
    total=$(inclusive update) starts=$(awk '/^run 0 frame/ {s += $11} END {print s}' "$tmp/$m.err")
    ends=$(awk '/^run 0 frame/ {s += $13} END {print s}' "$tmp/$m.err")
    splits=$(awk '/^run 0 frame/ {s += $7} END {print s}' "$tmp/$m.err")
    echo "| $m | $total | $starts | $ends | $splits | $(( $(inclusive try_collapse) / starts )) | $(( $(inclusive advance_morphs) / ends )) | $(self update) |"
  done
} > "$out"
rm -rf "$tmp"
echo "wrote $out"
