#!/usr/bin/env bash
# The installed package, step by step (CTest fixture, tests/CMakeLists.txt):
#   install ROOT BUILD_DIR                      cmake --install into ROOT/prefix (ROOT emptied first)
#   example ROOT SOURCE_DIR CXX GENERATOR       builds examples/library against ROOT/prefix alone
#   run ROOT SOURCE_DIR BUILD_DIR MESH BUILD_TYPE
#       runs the example and the installed program from ROOT/run, with a copy of MESH, no
#       INKLINE_STYLES, and checks that nothing installed or built against the package holds a
#       path into the source or build tree (binaries only when the build has no debug information)
# Every failure prints one line naming what failed and exits 1.
set -euo pipefail
step=$1 root=$2
fail() { echo "install_check: $*" >&2; exit 1; }

case $step in
install)
  build=$3
  rm -rf "$root"
  mkdir -p "$root"
  cmake --install "$build" --prefix "$root/prefix" >"$root/install.log" || fail "cmake --install failed ($root/install.log)"
  for f in bin/inkline include/inkline/inkline.hpp include/inkline/version.hpp lib/cmake/inkline/inklineConfig.cmake \
           lib/cmake/inkline/inklineConfigVersion.cmake lib/cmake/inkline/inklineTargets.cmake \
           share/inkline/styles/sketchy.json share/inkline/styles/README.md share/man/man1/inkline.1 \
           share/bash-completion/completions/inkline share/doc/inkline/docs/freeform.md \
           share/doc/inkline/examples/teapot.bpt bin/inkline-window; do
    [ -e "$root/prefix/$f" ] || fail "not installed: $f"
  done
  # The scene reader, opened at the first scene file (LIBDIR/inkline; LIBDIR is lib or lib/<triplet>).
  compgen -G "$root/prefix/lib*/inkline/libinkline_assimp.so" >/dev/null ||
    compgen -G "$root/prefix/lib/*/inkline/libinkline_assimp.so" >/dev/null || fail "not installed: libinkline_assimp.so"
  ;;
example)
  src=$3 cxx=$4 generator=$5
  # Only the prefix is searched: no package registry, no system-wide inkline.
  cmake -S "$src/examples/library" -B "$root/example" -G "$generator" -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_PREFIX_PATH="$root/prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF \
        >"$root/example-configure.log" 2>&1 || fail "configuring examples/library failed ($root/example-configure.log)"
  cmake --build "$root/example" >"$root/example-build.log" 2>&1 || fail "building examples/library failed ($root/example-build.log)"
  ;;
run)
  src=$3 build=$4 mesh=$5 build_type=$6
  rm -rf "$root/run"
  mkdir -p "$root/run"
  cp "$mesh" "$root/run/model.off"
  cd "$root/run"
  unset INKLINE_STYLES
  "$root/example/draw_model" model.off plain.svg styled.png sketchy >example.out 2>&1 || fail "draw_model: $(cat example.out)"
  grep -q "visible and .* hidden pieces" example.out || fail "draw_model printed no counts: $(cat example.out)"
  head -c 5 plain.svg | grep -q '<?xml' || fail "draw_model wrote no SVG"
  head -c 4 styled.png | grep -q PNG || fail "draw_model wrote no styled PNG"
  inkline=$root/prefix/bin/inkline
  "$inkline" --version | grep -q '^inkline [0-9]' || fail "inkline --version: $("$inkline" --version 2>&1)"
  "$inkline" render model.off -o sketchy.png --size=200x150 --style=sketchy --quiet 2>err.txt ||
    fail "installed inkline render --style=sketchy: $(cat err.txt)"
  head -c 4 sketchy.png | grep -q PNG || fail "installed inkline wrote no PNG"
  # The man page holds every command's flags; bash completion offers fixed values and the installed presets.
  grep -q '^\.TH INKLINE 1' "$root/prefix/share/man/man1/inkline.1" && grep -q 'fB\\-\\-eye\\fR' "$root/prefix/share/man/man1/inkline.1" ||
    fail "the man page lacks its header or the render flags"
  complete_words() {
    PATH="$root/prefix/bin:$PATH" bash -c 'source "$1"; shift; COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _inkline
      echo "${COMPREPLY[*]}"' _ "$root/prefix/share/bash-completion/completions/inkline" "$@"
  }
  [ "$(complete_words inkline render --format =)" = "svg pdf png json" ] || fail "completion of --format=: $(complete_words inkline render --format =)"
  [ "$(complete_words inkline render --style = tech)" = "technical" ] || fail "completion of --style=tech: $(complete_words inkline render --style = tech)"
  # The window's program beside it: `inkline view` runs it (here only its help: no display).
  "$inkline" view --help >help.txt 2>err.txt || fail "installed inkline view --help: $(cat err.txt)"
  grep -q '^usage: inkline view' help.txt || fail "installed inkline view --help printed no usage: $(head -1 help.txt)"
  # The installed tree finds its styles and its scene module from where it is, so it can be moved.
  cp "$src/fuzz/corpus/glb/instances.glb" scene.glb
  mv "$root/prefix" "$root/moved"
  "$root/moved/bin/inkline" render model.off -o moved.svg --size=200x150 --style=technical --quiet 2>err.txt ||
    { mv "$root/moved" "$root/prefix"; fail "moved prefix: inkline render --style=technical: $(cat err.txt)"; }
  "$root/moved/bin/inkline" render scene.glb -o scene.svg --size=200x150 --camera=frame --quiet 2>err.txt ||
    { mv "$root/moved" "$root/prefix"; fail "moved prefix: inkline render scene.glb: $(cat err.txt)"; }
  mv "$root/moved" "$root/prefix"
  # No path into the source or build tree in what was installed or built against it.
  files=$(find "$root/prefix" "$root/example/draw_model" -type f)
  case $build_type in Debug|RelWithDebInfo) files=$(grep -L -e $'^\x7fELF' $files || true) ;; esac
  for tree in "$(realpath "$src")" "$(realpath "$build")"; do
    hits=$(grep -l -F "$tree" $files || true)
    [ -z "$hits" ] || fail "these name $tree: $hits"
  done
  ;;
*) fail "unknown step '$step'" ;;
esac
