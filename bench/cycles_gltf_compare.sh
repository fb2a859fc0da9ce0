#!/usr/bin/env bash
# meshtour against Blender 3.4's Cycles on the same glTF file, the same camera and the same
# environment image, both converged: the relative RMSE of the linear beauty over the pixels both
# renderers cover (docs/FIDELITY.md, "Against Cycles"). A benchmark, not a test: it needs Debian's
# blender and python3-numpy (scripts/install-deps.sh --bench), and takes minutes per model.
#
#   bench/cycles_gltf_compare.sh [options] MODEL.gltf|glb ENV.exr [MODEL ENV ...]
#     --spp N           meshtour's samples (default 1024)
#     --cycles-spp N    Cycles' samples (default 512)
#     --size WxH        frame size (default 640x360)
#     --frame K         the turntable frame (of 8) both render (default 0)
#     --bounces B       light paths: meshtour --bounces B, Cycles' diffuse, glossy and total bounces B
#                       (default 0: direct light only, meshtour's default)
#     --lambert         light transport only: meshtour --materials look with the look's specular 0,
#                       Cycles with every Principled BSDF replaced by a Lambertian Diffuse BSDF of the
#                       same base colour and normal (what differs is then the light, not the BRDF)
#     --work DIR        where frames go (default a temporary folder, removed)
#     --reuse-cycles    keep a Cycles frame already in --work (to compare another meshtour build)
#     --meshtour FILE   the meshtour binary (default build-test/cli/meshtour)
#
# Per model: `meshtour path MODEL --up y --path turntable --frames 8 --elevation 18 --camera-frames` gives the
# camera (its eye, target, up and vertical field of view), meshtour renders the frame from a scene
# file with the look's lights and ground removed, transparent background, `--environment ENV`,
# no denoising, EXR; bench/cycles_gltf.py renders the same frame in Cycles. The
# environment is turned -90 degrees in Cycles: meshtour puts the image's centre (u = 0.5) along
# glTF's -z, Blender along +x (after its importer's +Y-to-+Z turn, glTF's -z is Blender's +y).
# Prints one line per model: RMSE, the ratio of the means (meshtour / Cycles), the share of covered
# pixels where the two disagree on coverage, and both renderers' times.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
spp=1024 cycles_spp=512 size=640x360 frame=0 bounces=0 work="" meshtour="$root/build-test/cli/meshtour" lambert=0 reuse=0
while [ $# -gt 0 ]; do
  case "$1" in
    --spp) spp=$2; shift 2 ;;
    --cycles-spp) cycles_spp=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --frame) frame=$2; shift 2 ;;
    --bounces) bounces=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --lambert) lambert=1; shift ;;
    --reuse-cycles) reuse=1; shift ;;
    --meshtour) meshtour=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    -*) echo "cycles_gltf_compare: unknown option $1 (--help lists them)" >&2; exit 2 ;;
    *) break ;;
  esac
done
[ $# -ge 2 ] && [ $(($# % 2)) -eq 0 ] || { echo "cycles_gltf_compare: give MODEL ENV pairs (--help)" >&2; exit 2; }
command -v blender >/dev/null || { echo "cycles_gltf_compare: blender not found (scripts/install-deps.sh --bench)" >&2; exit 2; }
[ -x "$meshtour" ] || { echo "cycles_gltf_compare: $meshtour not found (scripts/build.sh --tests)" >&2; exit 2; }
quality="$root/build-test/bench/denoise_quality"
[ -x "$quality" ] || { echo "cycles_gltf_compare: $quality not found (scripts/build.sh --tests)" >&2; exit 2; }
width=${size%x*} height=${size#*x}
suffix="" lambert_look=""
if [ "$lambert" = 1 ]; then
  suffix=-lambert lambert_look=', "materials": "look", "specular": 0'
fi
if [ -z "$work" ]; then
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
mkdir -p "$work"
printf '%-28s %-12s %8s %8s %9s %9s %9s\n' model environment rmse% ratio coverage% meshtour_s cycles_s
while [ $# -gt 0 ]; do
  model=$(realpath "$1") env=$(realpath "$2")
  shift 2
  name=$(basename "${model%.*}")-$(basename "${env%.*}")$suffix
  dir="$work/$name"
  mkdir -p "$dir"
  cat > "$dir/scene.json" <<JSON
{ "format": "meshtour-scene/1", "model": { "file": "$model" }, "up": "y",
  "look": { "preset": "studio", "lights": [], "ground": false, "background": "transparent"$lambert_look } }
JSON
  "$meshtour" path "$model" --up y --path turntable --frames 8 --elevation 18 --width "$width" --height "$height" \
      --camera-frames "$dir/cams.json" -q
  start=$(date +%s.%N)
  "$meshtour" render "$dir/scene.json" --path turntable --frame-count 8 --elevation 18 --frames "$frame" --width "$width" --height "$height" \
      --spp "$spp" --denoise off --format exr --environment "$env" --bounces "$bounces" --out-dir "$dir/meshtour" --overwrite -q
  ours=$(echo "$(date +%s.%N) - $start" | bc)
  if [ "$reuse" = 1 ] && [ -f "$dir/cycles.exr" ]; then
    theirs=reused
  else
    theirs=$(blender -b --factory-startup --python "$root/bench/cycles_gltf.py" -- "$model" "$dir/cams.json" "$frame" "$env" \
        "$dir/cycles.exr" "$cycles_spp" 2 "$width" "$height" "$bounces" 1 -90 "$lambert" 2>"$dir/blender.err" | sed -n 's/^cycles: \([0-9.]*\) seconds.*/\1/p')
    [ -n "$theirs" ] || { echo "cycles_gltf_compare: Cycles failed on $model (see $dir/blender.err)" >&2; exit 1; }
  fi
  ours_exr=$(printf '%s/meshtour/frame_%06d.exr' "$dir" "$frame")
  report=$("$quality" --model-error "$ours_exr" "$dir/cycles.exr")
  rmse=$(echo "$report" | sed -n 's/^relative RMSE over the model: \([0-9.]*\) %.*/\1/p')
  ratio=$(echo "$report" | sed -n 's/^mean ratio (A \/ REFERENCE): \([0-9.]*\).*/\1/p')
  coverage=$(echo "$report" | sed -n 's/.*coverage disagrees on \([0-9.]*\) %.*/\1/p')
  printf '%-28s %-12s %8s %8s %9s %9.1f %9s\n' "$(basename "$model")" "$(basename "$env")" "$rmse" "$ratio" "$coverage" "$ours" "$theirs"
done
