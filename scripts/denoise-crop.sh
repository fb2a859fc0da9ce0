#!/usr/bin/env bash
# The README's denoiser picture (docs/images/denoise-crop.png): one crop of the bunny tour's
# frame 30 at 1280x720 (its feet, the fur of its chest and the contact shadow), raw 16 spp |
# denoised 16 spp | 4096-spp reference, side by side, from the frames
# `denoise_quality --dump` writes.
#
#   build-test/bench/denoise_quality --case bunny --dump /tmp/dq
#   scripts/denoise-crop.sh /tmp/dq [X Y W H] [OUT.png]
set -euo pipefail
dir=${1:?usage: scripts/denoise-crop.sh DUMP_DIR [X Y W H] [OUT.png]}
x=${2:-540} y=${3:-430} w=${4:-280} h=${5:-260}
out=${6:-docs/images/denoise-crop.png}
for f in bunny-raw-16 bunny-denoised-16 bunny-reference; do
  [ -f "$dir/$f.exr" ] || { echo "denoise-crop: $dir/$f.exr is missing: run denoise_quality --case bunny --dump $dir first" >&2; exit 1; }
done
crop() { echo "$dir/$1.exr --ch R,G,B --cut ${w}x${h}+${x}+${y} --colorconvert linear sRGB"; }
# Three crops with a 4-pixel black gap between them.
# shellcheck disable=SC2046
oiiotool $(crop bunny-raw-16) $(crop bunny-denoised-16) $(crop bunny-reference) \
  --mosaic:pad=4 3x1 -d uint8 -o "$out"
echo "wrote $out"
