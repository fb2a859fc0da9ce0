#!/usr/bin/env bash
# Time to equal error against Blender's Cycles (docs/PERFORMANCE.md): how long each renderer takes
# to a frame as close to its own converged reference as meshtour's default frame (16 spp,
# denoised) is to meshtour's. Both render the bunny's studio frame at 1280x720 on 2 threads
# (bench/studio_frame.h; bench/cycles_frame.py sets up the same camera and lights in Cycles).
#
#   bench/cycles_equal_error.sh [GROUND] [SPP...]   (from the repository root, after
#                                                  scripts/build.sh --tests; needs Debian's blender)
#
# GROUND: none (default; the model on Cycles' world alone: less work per sample and a noise-free
# backdrop, so Cycles' error reads lower than on meshtour's frame with its shadow-catching ground:
# the conservative comparison) or catcher (a shadow catcher; its reference takes ~4x as long).
# SPP: Cycles' sample ladder (default 16 32 64 128 256 512 1024 2048), climbed until a rung's error
# is at or under meshtour's.
#
# The error is the relative RMSE over linear R, G, B of the whole frame,
# sqrt(sum (x - ref)^2 / sum ref^2) (denoise_quality's); each renderer's reference is its own raw
# 4096-spp frame with another seed than the frames measured against it (the same seed would share
# their first samples and make their error read low). meshtour's time is its default frame as a
# tour meets it (render and denoiser, best of 3, denoise_quality --case bunny-studio); Cycles' is
# its render alone (cycles_frame.py: no scene set-up or loading), one run per rung. Cycles' time at
# meshtour's error is interpolated between the two rungs that bracket it (log time linear in log
# error); the ratio is that time over meshtour's.
#
# A 4096-spp reference is not noise-free, and Cycles' is noisier than meshtour's: its own error
# adds to every rung's (independent seeds: measured^2 = true^2 + reference^2), so a rung near
# meshtour's error reads high and the measured crossing overstates Cycles' time. A second Cycles
# reference (seed 2) measures it: |ref1 - ref2|^2 = 2 reference^2. The table gives each rung's
# measured error and the error with the reference's share taken out; the headline ratio is the
# corrected one (in Cycles' favour), the measured one follows it. meshtour's own reference error is
# not taken out (raw 256 spp is about 0.3 %, so its 4096-spp reference about 0.06 %: it would
# lower meshtour's 0.46 % by under 0.01 point, in Cycles' favour again).
#
# The Cycles references (about 10 minutes each with GROUND none on 2 cores) are cached in
# build-test/cycles-references under the Blender version, the ground and the scene script's hash;
# meshtour's reference is denoise_quality's cache.
set -euo pipefail
cd "$(dirname "$0")/.."
ground=${1:-none}
shift || true
ladder=("$@")
[ ${#ladder[@]} -gt 0 ] || ladder=(16 32 64 128 256 512 1024 2048)
case $ground in none | catcher) ;; *) echo "cycles_equal_error: GROUND must be none or catcher, not '$ground'" >&2; exit 2 ;; esac
mesh=../shared/meshes/bunny.ply
[ -f "$mesh" ] || { echo "cycles_equal_error: $mesh not found (the shared test meshes)" >&2; exit 2; }
command -v blender >/dev/null || { echo "cycles_equal_error: blender not found (scripts/install-deps.sh --bench)" >&2; exit 2; }
dq=build-test/bench/denoise_quality
[ -x "$dq" ] || { echo "cycles_equal_error: $dq not found (scripts/build.sh --tests)" >&2; exit 2; }

cycles() {  # SPP SEED OUT.exr -> prints the render's seconds
  blender -b --factory-startup --python bench/cycles_frame.py -- "$mesh" "$3" "$1" 2 1280 720 "$ground" "$2" 2>/dev/null |
    sed -n 's/^cycles: \([0-9.]*\) seconds.*/\1/p'
}
error() {  # A.exr REFERENCE.exr -> prints the relative RMSE in per cent
  "$dq" --error "$1" "$2" | sed -n 's/^relative RMSE: \([0-9.]*\) %.*/\1/p'
}

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
version=$(blender --version 2>/dev/null | sed -n 's/^Blender \([0-9.]*\).*/\1/p' | head -1)
script_hash=$(sha256sum bench/cycles_frame.py | cut -c1-12)
cache=build-test/cycles-references
reference_for() {  # SEED -> the cached 4096-spp Cycles frame of that seed, rendered if missing
  local file=$cache/bunny-studio-1280x720-4096spp-$ground-seed$1-blender$version-$script_hash.exr
  if [ ! -f "$file" ]; then
    echo "Cycles reference, 4096 spp, seed $1 (cached as $file) ..." >&2
    mkdir -p "$cache"
    local seconds
    seconds=$(cycles 4096 "$1" "$work/reference.exr")
    [ -n "$seconds" ] && [ -f "$work/reference.exr" ] || { echo "cycles_equal_error: Cycles' reference render failed" >&2; exit 1; }
    mv "$work/reference.exr" "$file"  # whole or not at all: an interrupted run renders it again
    echo "  ${seconds} s" >&2
  fi
  echo "$file"
}
reference=$(reference_for 1)
second_reference=$(reference_for 2)
reference_error=$(awk -v e="$(error "$second_reference" "$reference")" 'BEGIN { printf "%.4f", e / sqrt(2) }')

echo "meshtour: denoise_quality --case bunny-studio (its reference is cached after the first run) ..." >&2
"$dq" --case bunny-studio >"$work/dq.txt"
ours_error=$(sed -n 's/^| bunny-studio | denoised 16 spp | \([0-9.]*\) %.*/\1/p' "$work/dq.txt")
ours_time=$(sed -n 's/^| bunny-studio (default frame[^|]*| \([0-9.]*\) s\/frame.*/\1/p' "$work/dq.txt")
[ -n "$ours_error" ] && [ -n "$ours_time" ] || { cat "$work/dq.txt" >&2; echo "cycles_equal_error: no figures from $dq" >&2; exit 1; }
echo "Cycles' 4096-spp reference's own error: ${reference_error} % (|ref(seed 1) - ref(seed 2)| / sqrt 2)"
echo
echo "| renderer | spp | relative RMSE | without the reference's error | seconds |"
echo "|---|---:|---:|---:|---:|"
grep '^| bunny-studio | raw ' "$work/dq.txt" | awk -F'|' '{ gsub(/ spp|raw|denoised| /, "", $3); printf "| meshtour raw | %s |%s| |%s |\n", $3, $4, $7 }'
echo "| meshtour denoised (the default frame) | 16 | $ours_error % | | $ours_time |"

# Cycles' time at meshtour's error from one of the two error columns: "<= T" when the first rung is
# already there, T interpolated between the bracketing rungs, or empty when no rung gets there.
crossing() {  # COLUMN (2: measured, 3: corrected) of $work/ladder.txt (spp error corrected seconds)
  awk -v col="$1" -v o="$ours_error" '
    { e = $col; t = $4 }
    e <= o && !done { if (NR == 1) printf "<= %.2f", t; else { f = (log(o) - log(pe)) / (log(e) - log(pe)); printf "%.2f", exp(log(pt) + f * (log(t) - log(pt))) } done = 1 }
    { pe = e; pt = t }' "$work/ladder.txt"
}
: >"$work/ladder.txt"
for spp in "${ladder[@]}"; do
  seconds=$(cycles "$spp" 0 "$work/cycles-$spp.exr")
  [ -n "$seconds" ] || { echo "cycles_equal_error: Cycles' $spp-spp render failed" >&2; exit 1; }
  err=$(error "$work/cycles-$spp.exr" "$reference")
  corrected=$(awk -v e="$err" -v r="$reference_error" 'BEGIN { d = e * e - r * r; printf "%.4f", (d > 0 ? sqrt(d) : 0) }')
  echo "$spp $err $corrected $seconds" >>"$work/ladder.txt"
  echo "| Cycles | $spp | $err % | $corrected % | $seconds |"
  # Climb until the measured error gets there (the corrected one is then there too).
  awk -v e="$err" -v o="$ours_error" 'BEGIN { exit !(e <= o) }' && break
done
echo
report() {  # LABEL COLUMN
  local t
  t=$(crossing "$2")
  if [ -z "$t" ]; then
    echo "$1: Cycles did not reach meshtour's ${ours_error} % within ${ladder[*]} spp"
  else
    awk -v t="${t#<= }" -v o="$ours_time" -v e="$ours_error" -v eq="$t" -v label="$1" 'BEGIN {
      printf "%s: Cycles at meshtour'"'"'s %.3f %% in %s s against meshtour'"'"'s %.3f s: %.1fx\n", label, e, eq, o, t / o }'
  fi
}
report "without the reference's error (the headline)" 3
report "as measured against the reference" 2
