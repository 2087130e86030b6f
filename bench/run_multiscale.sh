#!/bin/bash
# Detail control, multi-scale method (issue 43): the pre-process, the dolly's line density with and
# without --detail, frame times and temporal coherence for armadillo, bunny00, elephant and
# armadillo subdivided once, on one core (taskset). Writes bench/results/multiscale_run.md (the
# tables), bench/results/multiscale_density.svg (the density curves) and
# bench/results/multiscale_second_order.md (the second-order levels at r = 3/4 and 1/2) and
# bench/results/multiscale_thin_guard.md (the same at r = 3/4 with the thin-guarded implicit post-pass).
# Usage: bench/run_multiscale.sh [build-dir]   (a few minutes)
set -euo pipefail
cd "$(dirname "$0")/.."
BIN="${1:-build}/bench/bench_multiscale"
OUT=bench/results
mkdir -p "$OUT"
taskset -c 1 "$BIN" --plot="$OUT/multiscale_density.svg" armadillo bunny00 elephant armadillo@1 > "$OUT/multiscale_run.md.tmp"
mv "$OUT/multiscale_run.md.tmp" "$OUT/multiscale_run.md"
# The second-order functional (--detail-fairing=second-order: 8 sweeps, 32 tangential) at the seed's
# r = 3/4 and at 1/2.
for r in 0.75 0.5; do
    taskset -c 1 "$BIN" --second-order --sweeps=8 --tangential=32 --ratio=$r --no-coherence armadillo bunny00 elephant
done > "$OUT/multiscale_second_order.md.tmp"
mv "$OUT/multiscale_second_order.md.tmp" "$OUT/multiscale_second_order.md"
# The implicit post-pass (W + t_k L^2) x = p, t_k = 4 * 16^(k - 1), reach at most a tenth of the
# shape's thickness, on the second-order levels at r = 3/4 (MultiscaleOptions::smoothing, thin_guard).
taskset -c 1 "$BIN" --second-order --sweeps=8 --tangential=32 --ratio=0.75 --smoothing=4 --growth=16 --order=2 \
    --thin=0.1 --no-coherence armadillo bunny00 elephant armadillo@1 > "$OUT/multiscale_thin_guard.md.tmp"
mv "$OUT/multiscale_thin_guard.md.tmp" "$OUT/multiscale_thin_guard.md"
echo "wrote $OUT/multiscale_run.md, multiscale_second_order.md, multiscale_thin_guard.md and multiscale_density.svg" >&2
