#!/bin/bash
# Issue 4's speed targets for the silhouette finders, measured with `inkline bench` (one core,
# taskset; every setting of one run sees the same frames, so compare within a run: the machine
# is shared and noisy).
#  1. armadillo Loop-subdivided twice (832 k triangles) along smooth orbits of 0.25, 0.5, 1 and
#     2 degrees per frame (60 frames each): at 60 frames/s, 15 to 120 degrees per second; a
#     turntable at 1 degree per frame turns once in 6 s. Settings: exhaustive; randomized 0.0005
#     without coherence; randomized + coherence from an exhaustive first view.
#  2. The same finders over subdivision levels (armadillo @0 to @3, 1 degree per frame).
#  3. armadillo@2, randomized + coherence from a random first view (fractions 0.0005 and 0.002)
#     at 0.5, 1, 2 and 3 degrees per frame.
#  4. armadillo@2 along a whole orbit at 0.25 degrees per frame (1440 frames): the one-time work
#     of both finders (the exhaustive one builds its face blocks and edge windows in its second
#     view, about 40 ms; the coherent one runs an exhaustive first view and builds its first band,
#     about 10 ms) weighs on a mean over 60 frames but not over a whole turn.
# Writes bench/results/armadillo@2-<deg>dpf.{csv,md}, bench/results/levels-<level>.{csv,md},
# bench/results/armadillo@2-orbit.{csv,md} and the summaries at the end of
# bench/results/finder_targets.md: from the heading of part 1's table to the end of the file (the
# dated sections above it are kept). Takes about twenty-five minutes.
# Usage: bench/run_finder_targets.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
BIN="${1:-build}/src/inkline"
OUT=bench/results
M=data/meshes
run() {  # name, then inkline bench arguments
    local name=$1; shift
    echo "== $name" >&2
    taskset -c 1 "$BIN" bench "$@" --path=orbit --csv="$OUT/$name.csv" --markdown="$OUT/$name.md" >/dev/null
}
# Columns of a bench Markdown row: 2 finder, 3 fraction, 4 coherence, 8 silhouette edges/frame,
# 10 recall, 13 search ms/frame (mean), 16 median search ms/frame.
row() {  # file, finder, coherence -> "search_ms sil_edges recall median_search_ms"
    awk -F'|' -v f="$2" -v c="$3" '$2 ~ " "f" " && $4 ~ " "c" " {gsub(/ /, ""); print $13, $8, $10, $16; exit}' "$1"
}
# Columns 18, 19: band faces/frame, faces turned/frame (coherence).
band() {  # file -> "band_faces faces_turned" of the coherence row
    awk -F'|' '$2 ~ " randomized " && $4 ~ " yes " {gsub(/ /, ""); print $18, $19; exit}' "$1"
}
ratio() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.2f", a / b}'; }
summary="$OUT/finder_targets.md"
{
    echo "## armadillo@2 (832000 triangles), search time per frame along orbits, one core"
    echo
    echo "Commands: \`bench/run_finder_targets.sh\` (inkline bench data/meshes/armadillo.off --subdivide=2"
    echo "--frames=60 --arc=A --fractions=0.0005 --first-view=exhaustive). Search = finding the silhouette"
    echo "edges (chaining excluded: the same work for every finder). Mean over the frames (coherence: with"
    echo "its exhaustive first view and first-use set-up) and median over the frames (steady state, and"
    echo "robust against the other processes of this shared machine)."
    echo
    echo "| deg/frame | exhaustive search ms (mean / median) | coherence search ms (mean / median) | speed-up (mean / median) | recall (coherence) | random 0.0005 search ms (mean) | recall (random) | silhouette edges/frame |"
    echo "|---:|---:|---:|---:|---:|---:|---:|---:|"
} > "$summary.tmp"
for dpf in 0.25 0.5 1 2; do
    arc=$(awk -v d="$dpf" 'BEGIN {print d * 60}')
    name="armadillo@2-${dpf}dpf"
    run "$name" $M/armadillo.off --subdivide=2 --frames=60 --arc="$arc" --fractions=0.0005 --first-view=exhaustive
    read -r ex sil _ exm < <(row "$OUT/$name.md" exhaustive no)
    read -r co _ cr com < <(row "$OUT/$name.md" randomized yes)
    read -r ra _ rr _ < <(row "$OUT/$name.md" randomized no)
    echo "| $dpf | $ex / $exm | $co / $com | $(ratio "$ex" "$co") / $(ratio "$exm" "$com") | $cr | $ra | $rr | $sil |" >> "$summary.tmp"
done
{
    echo
    echo "## Over subdivision levels (armadillo, 1 degree per frame, 30 frames), one core"
    echo
    echo "| level | triangles | silhouette edges/frame | exhaustive search ms (median) | coherence search ms (median) | speed-up (median) | coherence ns per silhouette edge | exhaustive ns per triangle | band faces/frame | faces turned/frame | turned faces per silhouette edge |"
    echo "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
} >> "$summary.tmp"
for level in 0 1 2 3; do
    name="levels-$level"
    run "$name" $M/armadillo.off --subdivide=$level --frames=30 --arc=30 --fractions=0.0005 --first-view=exhaustive
    tri=$(awk -F, 'NR == 2 {print $2}' "$OUT/$name.csv")
    read -r _ sil _ ex < <(row "$OUT/$name.md" exhaustive no)
    read -r _ _ _ co < <(row "$OUT/$name.md" randomized yes)
    read -r bf tu < <(band "$OUT/$name.md")
    echo "| @$level | $tri | $sil | $ex | $co | $(ratio "$ex" "$co") |" \
         "$(awk -v c="$co" -v s="$sil" 'BEGIN {printf "%.1f", 1e6 * c / s}') |" \
         "$(awk -v e="$ex" -v t="$tri" 'BEGIN {printf "%.2f", 1e6 * e / t}') |" \
         "$bf | $tu | $(awk -v t="$tu" -v s="$sil" 'BEGIN {printf "%.2f", t / s}') |" >> "$summary.tmp"
done
{
    echo
    echo "## armadillo@2, randomized + coherence from a random first view (the finder as the paper runs it)"
    echo
    echo "Commands: inkline bench data/meshes/armadillo.off --subdivide=2 --frames=60 --arc=A --fractions=0.0005,0.002"
    echo "(results in armadillo@2-random-<deg>dpf.md). Recall over the 60 frames, first view included."
    echo
    echo "| deg/frame | exhaustive search ms (mean / median) | fraction | coherence search ms (mean / median) | speed-up (mean / median) | recall | wrong visible px/frame |"
    echo "|---:|---:|---:|---:|---:|---:|---:|"
} >> "$summary.tmp"
for dpf in 0.5 1 2 3; do
    arc=$(awk -v d="$dpf" 'BEGIN {print d * 60}')
    name="armadillo@2-random-${dpf}dpf"
    run "$name" $M/armadillo.off --subdivide=2 --frames=60 --arc="$arc" --fractions=0.0005,0.002
    read -r ex _ _ exm < <(row "$OUT/$name.md" exhaustive no)
    for fr in 0.0005 0.002; do
        line=$(awk -F'|' -v f="$fr" '$2 ~ " randomized " && $3 ~ " "f" " && $4 ~ " yes " {gsub(/ /, ""); print $13, $16, $10, $11; exit}' "$OUT/$name.md")
        read -r co com rec wrong <<< "$line"
        echo "| $dpf | $ex / $exm | $fr | $co / $com | $(ratio "$ex" "$co") / $(ratio "$exm" "$com") | $rec | $wrong |" >> "$summary.tmp"
    done
done
{
    echo
    echo "## armadillo@2, a whole orbit at 0.25 deg/frame (1440 frames), one core"
    echo
    echo "Command: inkline bench data/meshes/armadillo.off --subdivide=2 --frames=1440 --arc=360"
    echo "--fractions=0.0005 --first-view=exhaustive (results in armadillo@2-orbit.md). The finders' one-time"
    echo "work is spread over the whole turn."
    echo
    echo "| exhaustive search ms (mean / median) | coherence search ms (mean / median) | speed-up (mean / median) | recall (coherence) | silhouette edges/frame | silhouette edges/s (exhaustive / coherence, by mean) |"
    echo "|---:|---:|---:|---:|---:|---:|"
} >> "$summary.tmp"
run armadillo@2-orbit $M/armadillo.off --subdivide=2 --frames=1440 --arc=360 --fractions=0.0005 --first-view=exhaustive
read -r ex sil _ exm < <(row "$OUT/armadillo@2-orbit.md" exhaustive no)
read -r co _ cr com < <(row "$OUT/armadillo@2-orbit.md" randomized yes)
echo "| $ex / $exm | $co / $com | $(ratio "$ex" "$co") / $(ratio "$exm" "$com") | $cr | $sil |" \
     "$(awk -v s="$sil" -v e="$ex" -v c="$co" 'BEGIN {printf "%.3g / %.3g", 1e3 * s / e, 1e3 * s / c}') |" >> "$summary.tmp"
# The dated sections of the file (before the first of the tables above) are kept.
first="## armadillo@2 (832000 triangles), search time per frame along orbits, one core"
if [ -f "$summary" ]; then
    awk -v h="$first" '$0 == h {exit} {print}' "$summary" > "$summary.keep"
    cat "$summary.keep" "$summary.tmp" > "$summary"
    rm -f "$summary.keep" "$summary.tmp"
else
    mv "$summary.tmp" "$summary"
fi
echo "wrote $summary" >&2
