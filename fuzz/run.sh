#!/usr/bin/env bash
# Builds the libFuzzer targets with Debian's clang (ASan + UBSan) and runs each for SECONDS
# (default 150) on one core. Not part of CI. Usage: fuzz/run.sh [SECONDS] [TARGET...]
# Targets: off obj ply stl (each through load_mesh) and pipeline (small random closed meshes and
# cameras through render_view, both visibility methods; builds the whole library with clang, a
# few minutes). Seeds: fuzz/corpus/<target>/ (committed);
# new inputs go to fuzz/out/corpus-<target>/ and crashes to fuzz/out/ (neither committed).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-150}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(off obj ply stl)
mkdir -p fuzz/out
flags=(-std=c++20 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined -Isrc)
lib=(-I/usr/include/cairo -DBOOST_ALL_NO_LIB -DCGAL_USE_GMPXX=1)
for t in "${targets[@]}"; do
  bin=fuzz/out/fuzz_$t
  if [ "$t" = pipeline ]; then
    # The library, instrumented for coverage (fuzzer-no-link) and ASan/UBSan; objects cached.
    mkdir -p fuzz/out/obj
    objs=()
    for src in $(find src -name '*.cpp' ! -path 'src/app/*' | sort); do
      obj=fuzz/out/obj/$(echo "$src" | tr / _).o
      if [ ! -f "$obj" ] || [ "$src" -nt "$obj" ]; then
        clang++ "${flags[@]/-fsanitize=fuzzer,/-fsanitize=fuzzer-no-link,}" "${lib[@]}" -c "$src" -o "$obj"
      fi
      objs+=("$obj")
    done
    clang++ "${flags[@]}" "${lib[@]}" fuzz/fuzz_pipeline.cpp "${objs[@]}" -o "$bin" \
      -lOpenMeshTools -lOpenMeshCore -lgmpxx -lmpfr -lgmp -lembree3 -lcairo
  elif [ ! -x "$bin" ] || [ src/model/mesh_io.cpp -nt "$bin" ] || [ fuzz/fuzz_mesh.cpp -nt "$bin" ]; then
    clang++ "${flags[@]}" -DFUZZ_EXT="\"$t\"" fuzz/fuzz_mesh.cpp src/model/mesh_io.cpp -o "$bin"
  fi
done
for t in "${targets[@]}"; do
  mkdir -p "fuzz/out/corpus-$t"
  echo "fuzz/run.sh: $t for ${seconds}s"
  (cd fuzz/out && ./fuzz_$t -max_total_time="$seconds" -rss_limit_mb=2048 -malloc_limit_mb=1024 -timeout=10 \
      -max_len=65536 -print_final_stats=1 -artifact_prefix="crash-$t-" "corpus-$t" "../corpus/$t") 2>&1 |
    grep -E "^#[0-9]+ +DONE|^stat::number_of_executed_units|^stat::peak_rss|ERROR|crash-|Test unit written" || true
done
