#!/usr/bin/env bash
# Builds the libFuzzer targets with Debian's clang (ASan + UBSan) and runs each for SECONDS
# (default 150) on one core. Not part of CI. Usage: fuzz/run.sh [SECONDS] [TARGET...]
# Targets: off obj ply stl (each through load_mesh); glb gltf (glTF 2.0 through load_scene:
# Assimp's reader, then inkline's checks and repairs; fuzz/scene_checks.hpp); pipeline (small random closed meshes and
# cameras through render_view, both visibility methods); offsets (offset tables, applied along a
# stroke), style (JSON style files, then stylize), bpt (Bezier patches) and surfaces (freeform
# JSON), the last two evaluated, stroked and tessellated (fuzz/parser_checks.hpp). All but the
# mesh formats link the library built with clang (a few minutes the first time; objects cached).
# Seeds: fuzz/corpus/<target>/ (committed); new inputs go to fuzz/out/corpus-<target>/ and
# crashes to fuzz/out/crash-<target>-* (neither committed). A crash is replayed by running
# fuzz/out/fuzz_<target> on the file; once fixed, copy it to fuzz/regressions/<target>-<what>
# (tests/test_fuzz_regressions.cpp and Extremes.PipelineFuzzRegressions replay those).
# Environment: FUZZ_JOBS (parallel compiles of the library, default 2).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-150}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(off obj ply stl glb gltf offsets style bpt surfaces pipeline)
mkdir -p fuzz/out
# Leaks inside Debian's libraries are not findings (scripts/lsan.supp: Assimp leaks a stream when
# one of its importers gives up on a malformed file).
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/scripts/lsan.supp:print_suppressions=0}
flags=(-std=c++20 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined -Isrc)
lib=(-I/usr/include/cairo -DBOOST_ALL_NO_LIB -DCGAL_USE_GMPXX=1)
libs=(-lOpenMeshTools -lOpenMeshCore -lgmpxx -lmpfr -lgmp -lembree3 -lcairo)
# The library (src/ but the executables and the GL preview), instrumented for coverage
# (fuzzer-no-link) and ASan/UBSan, as a static archive; objects rebuilt when their source or any
# header under src/ is newer.
build_library() {
  mkdir -p fuzz/out/obj
  local newest_header objs=() pending=()
  newest_header=$(find src -name '*.hpp' -newer fuzz/out/libinkline.a 2>/dev/null | head -1 || true)
  for src in $(find src -name '*.cpp' ! -path 'src/app/*' ! -path 'src/view/*' ! -path 'src/api/*' | sort); do
    local obj=fuzz/out/obj/$(echo "$src" | tr / _).o
    if [ ! -f "$obj" ] || [ "$src" -nt "$obj" ] || [ -n "$newest_header" ]; then pending+=("$src:$obj"); fi
    objs+=("$obj")
  done
  if ((${#pending[@]})); then
    printf '%s\n' "${pending[@]}" | xargs -P "${FUZZ_JOBS:-2}" -I{} sh -c 'src=${1%%:*}; obj=${1#*:}; shift;
      clang++ "$@" -c "$src" -o "$obj"' _ {} "${flags[@]/-fsanitize=fuzzer,/-fsanitize=fuzzer-no-link,}" "${lib[@]}"
    rm -f fuzz/out/libinkline.a
  fi
  [ -f fuzz/out/libinkline.a ] || ar rcs fuzz/out/libinkline.a "${objs[@]}"
}
for t in "${targets[@]}"; do
  bin=fuzz/out/fuzz_$t
  case $t in
    off|obj|ply|stl)
      if [ ! -x "$bin" ] || [ src/model/mesh_io.cpp -nt "$bin" ] || [ fuzz/fuzz_mesh.cpp -nt "$bin" ]; then
        clang++ "${flags[@]}" "${lib[@]}" -DFUZZ_EXT="\"$t\"" fuzz/fuzz_mesh.cpp src/model/mesh_io.cpp -o "$bin" \
          -lgmpxx -lmpfr -lgmp
      fi ;;
    glb|gltf)
      # The Assimp reader linked in (the program's own reader is used before the module's).
      scene_src=(fuzz/fuzz_scene.cpp fuzz/scene_checks.hpp src/scene/scene.cpp src/scene/assimp_reader.cpp
                 src/core/shared_library.cpp src/model/mesh_io.cpp src/core/camera.cpp)
      if [ ! -x "$bin" ] || [ -n "$(find "${scene_src[@]}" src/scene/scene.hpp src/scene/scene_reader.hpp src/model/mesh_io.hpp -newer "$bin")" ]; then
        clang++ "${flags[@]}" "${lib[@]}" -DFUZZ_EXT="\"$t\"" fuzz/fuzz_scene.cpp src/scene/scene.cpp \
          src/scene/assimp_reader.cpp src/core/shared_library.cpp src/model/mesh_io.cpp src/core/camera.cpp \
          -o "$bin" -lassimp -lgmpxx -lmpfr -lgmp
      fi ;;
    pipeline)
      build_library
      clang++ "${flags[@]}" "${lib[@]}" fuzz/fuzz_pipeline.cpp fuzz/out/libinkline.a -o "$bin" "${libs[@]}" ;;
    offsets|style|bpt|surfaces)
      build_library
      clang++ "${flags[@]}" "${lib[@]}" -DFUZZ_PARSER="\"$t\"" -DFUZZ_STYLES_DIR="\"$PWD/styles\"" \
        fuzz/fuzz_parsers.cpp fuzz/out/libinkline.a -o "$bin" "${libs[@]}" ;;
    *) echo "fuzz/run.sh: unknown target '$t'" >&2; exit 2 ;;
  esac
done
for t in "${targets[@]}"; do
  mkdir -p "fuzz/out/corpus-$t"
  echo "fuzz/run.sh: $t for ${seconds}s ($(date -u '+%Y-%m-%d %H:%M UTC'))"
  (cd fuzz/out && ./fuzz_$t -max_total_time="$seconds" -rss_limit_mb=2048 -malloc_limit_mb=1024 -timeout=10 \
      -max_len=65536 -print_final_stats=1 -artifact_prefix="crash-$t-" "corpus-$t" "../corpus/$t") 2>&1 |
    grep -E "^#[0-9]+ +DONE|^stat::number_of_executed_units|^stat::peak_rss|ERROR|crash-|Test unit written|^fuzz_" || true
  echo "fuzz/run.sh: $t findings: $(ls fuzz/out/crash-$t-* 2>/dev/null | wc -l) file(s) fuzz/out/crash-$t-* (all runs so far)"
done
