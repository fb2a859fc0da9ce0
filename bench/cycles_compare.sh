#!/usr/bin/env bash
# The speed comparison with Blender's Cycles (docs/PERFORMANCE.md): the bunny's 1280x720, 16-spp
# frame, render only, meshtour (tracer_bench's BM_RenderFrame/1280: the whole Renderer::render of
# the frame, 2 threads) and Cycles (bench/cycles_frame.py: Cycles on the CPU, 16 samples, 2
# threads, its default light paths, no denoiser) in turns, A B A B, with the ratio of each pair.
#
#   bench/cycles_compare.sh [PAIRS] [GROUND]   (from the repository root, after scripts/build.sh --tests;
#                                              needs Debian's blender; GROUND as in cycles_frame.py)
set -euo pipefail
cd "$(dirname "$0")/.."
pairs=${1:-3}
ground=${2:-catcher}
mesh=../shared/meshes/bunny.ply
[ -f "$mesh" ] || { echo "cycles_compare: $mesh not found (the shared test meshes)" >&2; exit 2; }
command -v blender >/dev/null || { echo "cycles_compare: blender not found (scripts/install-deps.sh --bench)" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for ((i = 1; i <= pairs; ++i)); do
  ours=$(build-test/bench/tracer_bench --benchmark_filter='RenderFrame/1280' --benchmark_min_time=3 2>/dev/null |
         sed -n 's/.*renderer at width 1280: \([0-9.]*\) s\/frame wall clock.*/\1/p')
  theirs=$(blender -b --factory-startup --python bench/cycles_frame.py -- "$mesh" "$out/cycles.exr" 16 2 1280 720 "$ground" 2>/dev/null |
           sed -n 's/^cycles: \([0-9.]*\) seconds.*/\1/p')
  awk -v a="$ours" -v b="$theirs" -v i="$i" -v g="$ground" 'BEGIN { printf "pair %d (Cycles ground: %s): meshtour %.3f s, Cycles %.3f s: %.2fx\n", i, g, a, b, b / a }'
done
