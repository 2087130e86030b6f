#!/bin/sh
# The window's tone pass (src/view/tone_pass.hpp) under a virtual display, in GLSL and on the CPU:
# frames per second and the mean time per pass (each finished before the next) while the camera
# orbits, armadillo and bunny00 at 800x600 and 1024x768, with and without the tone pass; into
# bench/results/tone_window.md.
# Usage: bench/run_tone_window.sh [BUILD_DIR] [DATA_DIR]
set -e
build=${1:-build}
data=${2:-data}
out=bench/results/tone_window.md
tmp=$(mktemp)
{
  echo "# The window's tone pass (GLSL and CPU): frames per second"
  echo
  echo "Made by \`bench/run_tone_window.sh\` at $(git rev-parse --short HEAD) on $(nproc) cores under Xvfb (Mesa's" \
       "llvmpipe: the shaders run on the CPU), load average $(cut -d' ' -f1-3 /proc/loadavg) when it started. 30" \
       "frames turning the camera 1 degree a frame; the tone pass runs every frame. \`fps\` and \`tone pass\`" \
       "are the window's \`--fps\` report (wall time); \`cpu\` is the process's CPU time a frame (all threads," \
       "llvmpipe's included)."
  echo
  echo "| mesh | size | lines | tone pass | fps | ms/frame | cpu ms/frame | tone pass ms: shade, blur, ridges + composite |"
  echo "|---|---|---|---|---|---|---|---|"
  for mesh in armadillo bunny00; do
    for size in 800x600 1024x768; do
      for run in "silhouette -" "silhouette,tone-dark,tone-highlight --base=toon glsl" \
                 "silhouette,tone-dark,tone-highlight --base=toon cpu"; do
        set -- $run
        lines="$1${3:+ $2}"
        pass=${3:-$2}
        xvfb-run -a -s "-screen 0 1280x1024x24" "$build/src/inkline" view "$data/meshes/$mesh.off" --lines=$lines \
          ${3:+--tone-pass=$pass} --frames=30 --orbit --arc=30 --size=$size --fps > "$tmp" 2>&1
        fps=$(sed -n 's/^fps: \([0-9.]*\) over.*, \([0-9.]*\) ms\/frame.*/\1 | \2/p' "$tmp")
        cpu=$(sed -n 's/.*all threads of the process \([0-9.]*\) ms\/frame.*/\1/p' "$tmp")
        tone=$(sed -n 's/.*mean ms: shade \([0-9.]*\), blur \([0-9.]*\), ridges \([0-9.]*\).*/\1, \2, \3/p' "$tmp")
        echo "| $mesh | $size | $(echo $lines | sed 's/ --base=toon/, toon base/') | $pass | $fps | $cpu | ${tone:--} |"
      done
    done
  done
  cat <<'TEXT'

## Reading

- `glsl`: the shaders on Mesa's llvmpipe (this machine has no GPU): about 150-170 ms of CPU a
  frame at 800 x 600 and 225-255 ms at 1024 x 768 for armadillo (52 k triangles) and bunny00 (75 k),
  where the window without the pass takes 6-12 ms. A software rasterizer runs every branch of a
  shader for a block of pixels, so the searches sit behind one discard and use the texture unit's
  bilinear fetches (the first version took 364 ms of CPU a frame).
- `cpu` (`--tone-pass=auto` picks it where OpenGL is a software renderer): render's stages on every
  thread, untraced, composited as the shader does and uploaded: 57-65 ms of CPU a frame at 800 x 600
  and 80-105 ms at 1024 x 768, 2.5-3x less than llvmpipe's GLSL and 2.5-3x the frame rate in the
  same run. The pass's own times (wall, on the loaded machine) are in the last column; on two idle
  cores the whole CPU pass of render takes 30.7 ms at 800 x 600 (bench/results/tone.md).
- Wall times are 2-3x the CPU time because the machine was shared (load average above).
  Interactive, the pass runs only when the camera, an option or the crease angle changes, so the
  panel stays responsive between moves.
- The seed's figure: 7-20 fps for 60 k-200 k triangles at 800 x 600 on a 2007 GPU (GeForce 7900 GT);
  the CPU pass reaches 6.7-7.8 fps at 800 x 600 here with the machine's load near 7 on 2 cores. On
  any GPU the GLSL pass is a handful of full-screen draws.
TEXT
} > "$out.new"
rm -f "$tmp"
mv "$out.new" "$out"
