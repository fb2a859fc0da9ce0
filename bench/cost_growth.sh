#!/usr/bin/env bash
# How a tour's cost grows with the mesh (docs/PERFORMANCE.md): the default tour of the shared bunny
# split 1-to-4 at edge midpoints 0, 2, 3 and 4 times (70k, 1.1M, 4.5M, 17.8M faces, the same shape),
# FRAMES frames at 1280x720, with one or more meshtour binaries in turns at each size (A B A B when
# two are given), so that a before/after pair shares the machine's load. Per run: the whole time,
# the render stage's time per frame (`--verbose`'s stage lines), every stage, and the peak memory
# (/usr/bin/time's maximum resident set).
#
#   bench/cost_growth.sh [--frames N] [--sizes "0 2 3 4"] BINARY [BINARY...]
#
# The split meshes are build-test/bench-meshes/bunny-split<N>.ply, written by load_bench on first
# use (`build-test/bench/load_bench --benchmark_filter='Ply/N/'`).
set -euo pipefail
cd "$(dirname "$0")/.."
frames=6
sizes="0 2 3 4"
while [ $# -gt 0 ]; do
  case "$1" in
    --frames) frames=$2; shift 2 ;;
    --sizes) sizes=$2; shift 2 ;;
    -h|--help) sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) break ;;
  esac
done
[ $# -ge 1 ] || { echo "usage: bench/cost_growth.sh [--frames N] [--sizes \"0 2 3 4\"] BINARY [BINARY...]" >&2; exit 2; }
bunny=../shared/meshes/bunny.ply
[ -f "$bunny" ] || { echo "cost_growth: $bunny not found (the shared test meshes)" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "cost_growth: /usr/bin/time not found (apt-get install time)" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
printf '%-6s %-28s %9s %12s %9s  %s\n' faces binary whole s/frame peak stages
for level in $sizes; do
  mesh=$bunny
  if [ "$level" != 0 ]; then
    mesh=build-test/bench-meshes/bunny-split$level.ply
    [ -f "$mesh" ] || build-test/bench/load_bench --benchmark_filter="Ply/$level/" >/dev/null
  fi
  for bin in "$@"; do
    log="$out/log.txt"
    /usr/bin/time -f 'TIME %e %M' "$bin" tour "$mesh" --frames "$frames" -o "$out/tour.mp4" --verbose --progress none >"$log" 2>&1 ||
      { echo "cost_growth: $bin failed on $mesh:" >&2; tail -5 "$log" >&2; exit 1; }
    awk -v faces="$level" -v bin="$bin" -v frames="$frames" '
      /stage [a-z]+ +[0-9.]+ s/ { for (i = 1; i <= NF; ++i) if ($i == "stage") { stages = stages sprintf("%s %.1f ", $(i + 1), $(i + 2)); if ($(i + 1) == "render") render = $(i + 2) } }
      /^TIME / { whole = $2; peak = $3 / 1048576 }
      END {
        split("70k - 1.1M 4.5M 17.8M", names, " ")
        printf "%-6s %-28s %8.1fs %11.3fs %7.2fGB  %s\n", names[faces + 1], substr(bin, length(bin) > 28 ? length(bin) - 27 : 1), whole, render / frames, peak, stages
      }' "$log"
  done
done
