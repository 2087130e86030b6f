#!/bin/bash
# The speed/accuracy trade of the silhouette finders (issue: randomized seed-and-seek), on the
# CGAL sample meshes, the same meshes Loop-subdivided (about 200 k, 800 k and 3 M triangles for
# armadillo), and two linked tori at several resolutions. One core (taskset), a smooth orbit
# (3 degrees per frame). Writes bench/results/<model>.{csv,md,svg} and bench/results/all.{csv,md}.
# Usage: bench/run_tradeoff.sh [build-dir]   (takes a few minutes; the 3 M model about ten)
set -euo pipefail
cd "$(dirname "$0")/.."
BIN="${1:-build}/src/inkline"
OUT=bench/results
mkdir -p "$OUT"
run() {  # name, then inkline bench arguments
    local name=$1; shift
    echo "== $name" >&2
    taskset -c 1 "$BIN" bench "$@" --path=orbit --arc=90 --csv="$OUT/$name.csv" --markdown="$OUT/$name.md" \
        --plot="$OUT/$name.svg" >/dev/null
}
M=data/meshes
run fandisk $M/fandisk.off --frames=30
run bunny00 $M/bunny00.off --frames=30
run armadillo $M/armadillo.off --frames=30
run elephant $M/elephant.off --frames=30
run ChineseDragon-10kv $M/ChineseDragon-10kv.off --frames=30
run knot1 $M/knot1.off --frames=30
run armadillo@1 $M/armadillo.off --subdivide=1 --frames=30
run armadillo@2 $M/armadillo.off --subdivide=2 --frames=30
run bunny00@1 $M/bunny00.off --subdivide=1 --frames=30
run bunny00@2 $M/bunny00.off --subdivide=2 --frames=30
run tori-64 tori:64 --frames=30
run tori-256 tori:256 --frames=30
run tori-1024 tori:1024 --frames=20
if [ "${INKLINE_BENCH_3M:-1}" = 1 ]; then
    run armadillo@3 $M/armadillo.off --subdivide=3 --frames=10
fi
# (the files of bench/run_finder_targets.sh, *dpf.* and levels-*, are not part of this set)
mine() { grep -v -e "/all\.$1\$" -e "dpf\.$1\$" -e "/levels-" -e "/finder_targets\.md\$" -e "/finder\.md\$"; }
{ head -1 "$OUT/fandisk.csv"; for f in $(ls "$OUT"/*.csv | mine csv); do tail -n +2 "$f"; done; } > "$OUT/all.csv"
cat $(ls "$OUT"/*.md | mine md) | grep -v '^$' | sed 's/^###/\n###/' > "$OUT/all.md.tmp" && mv "$OUT/all.md.tmp" "$OUT/all.md"
echo "wrote $OUT/all.csv and $OUT/all.md" >&2
