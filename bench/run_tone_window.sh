#!/bin/sh
# The window's GLSL tone pass (src/view/tone_pass.hpp) under a virtual display: frames per second
# and the mean time per pass (each finished before the next) while the camera orbits, armadillo and
# bunny00 at 800x600 and 1024x768, with and without the tone pass; into bench/results/tone_window.md.
# Usage: bench/run_tone_window.sh [BUILD_DIR] [DATA_DIR]
set -e
build=${1:-build}
data=${2:-data}
out=bench/results/tone_window.md
tmp=$(mktemp)
{
  echo "# The window's tone pass (GLSL): frames per second"
  echo
  echo "Made by \`bench/run_tone_window.sh\` at $(git rev-parse --short HEAD) on $(nproc) cores under Xvfb (Mesa's" \
       "llvmpipe: the shaders run on the CPU), load average $(cut -d' ' -f1-3 /proc/loadavg) when it started. 30" \
       "frames turning the camera 1 degree a frame; the tone pass runs every frame. \`fps\` and \`tone pass\`" \
       "are the window's \`--fps\` report (wall time); \`cpu\` is the process's CPU time a frame (all threads," \
       "llvmpipe's included)."
  echo
  echo "| mesh | size | lines | fps | ms/frame | cpu ms/frame | tone pass ms: shade, blur, ridges + composite |"
  echo "|---|---|---|---|---|---|---|"
  for mesh in armadillo bunny00; do
    for size in 800x600 1024x768; do
      for lines in "silhouette" "silhouette,tone-dark,tone-highlight --base=toon"; do
        xvfb-run -a -s "-screen 0 1280x1024x24" "$build/src/inkline" view "$data/meshes/$mesh.off" --lines=$lines \
          --frames=30 --orbit --arc=30 --size=$size --fps > "$tmp" 2>&1
        fps=$(sed -n 's/^fps: \([0-9.]*\) over.*, \([0-9.]*\) ms\/frame.*/\1 | \2/p' "$tmp")
        cpu=$(sed -n 's/.*all threads of the process \([0-9.]*\) ms\/frame.*/\1/p' "$tmp")
        tone=$(sed -n 's/.*mean ms: shade \([0-9.]*\), blur \([0-9.]*\), ridges \([0-9.]*\).*/\1, \2, \3/p' "$tmp")
        echo "| $mesh | $size | $(echo $lines | sed 's/ --base=toon/, toon base/') | $fps | $cpu | ${tone:--} |"
      done
    done
  done
  cat <<'TEXT'

## Reading

- The pass runs its shaders on the CPU here (no GPU): about 150-165 ms of CPU a frame at 800 x 600
  and 235-265 ms at 1024 x 768 for armadillo (52 k triangles) and bunny00 (75 k), where the window
  without it takes 7-11 ms. Wall times are about three times the CPU time because the machine was
  shared (load average above); on two idle cores the CPU figures mean roughly 12 frames a second at
  800 x 600 and 7-8 at 1024 x 768. Interactive, the pass runs only when the camera, an option or
  the crease angle changes, so the panel stays responsive between moves.
- Where it goes (a probe of process CPU time around each pass, finished, 20 runs, armadillo at
  800 x 600, not kept in the tree): shade about 30-35 ms, blur 45-50, ridges and composite 80-90.
  The first version took 364 ms of CPU a frame in all (armadillo, 800 x 600; three searches inline
  in one shader, manual bilinear samples): a software rasterizer runs every branch of a shader for a
  block of pixels, so the searches are now behind one discard (whole blocks without a line skip
  them) and one loop over the channels due, and the search's samples are the texture unit's
  bilinear fetches; pairing the blur's taps into linear fetches did not change its cost there.
- The seed's figure: 7-20 fps for 60 k-200 k triangles at 800 x 600 on a 2007 GPU (GeForce 7900 GT).
  The CPU pass of `inkline render` (bench/results/tone.md: about 47 ms of one core for armadillo at
  800 x 600, tracing included) is cheaper than this software GLSL; on any GPU the GLSL pass is a
  handful of full-screen draws.
TEXT
} > "$out.new"
rm -f "$tmp"
mv "$out.new" "$out"
