#!/usr/bin/env bash
# The refactoring safety net: runs a fixed set of meshtour commands (every command, both looks,
# every path mode, every codec and output kind, at small sizes) and writes one line per output,
# "sha256  name", to OUT. Run it with the binary before and after a change that must not change
# any output, and diff the two files: golden-image tolerances are too loose for "no pixel changes".
#
#   scripts/output-hashes.sh BINARY OUT [WORKDIR]   (WORKDIR: emptied first; default a new /tmp folder)
#
# Every output is hashed: videos, frames (PNG, EXR), posters, captions, contact sheets and web
# pages, path files, plots, overviews, camera exports, farm scripts, manifests and summaries, the
# stdout of info/evaluate/options/--help, and each command's exit code. Lines that hold a time or
# the run's own folder are normalised first (see normalise()). Uses ../shared/meshes/bunny.ply
# when present (the paper path, a textured-less scan); the built-in scene otherwise.
set -uo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
[ $# -ge 2 ] || { echo "usage: $0 BINARY OUT [WORKDIR]" >&2; exit 2; }
bin="$(realpath "$1")"
out="$(realpath -m "$2")"
if [ $# -ge 3 ]; then work="$(realpath -m "$3")"; rm -rf "$work"; mkdir -p "$work"; else work="$(mktemp -d /tmp/meshtour-hashes.XXXXXX)"; fi
cd "$work" || exit 1
bunny="$here/../shared/meshes/bunny.ply"
[ -f "$bunny" ] || { echo "output-hashes: $bunny is missing; the bunny cases need it" >&2; exit 2; }
cp "$bunny" bunny.ply

log="$work/commands.log"
: > "$log"
# run NAME ARGS...: runs meshtour, records its exit code, keeps stdout as NAME.stdout.
run() {
  local name="$1"; shift
  "$bin" "$@" > "$name.stdout" 2> "$name.stderr"
  echo "$name exit $?" >> "$log"
}
small=(--width 64 --height 36 --spp 2)

# tour: looks, path modes, backgrounds, frames kept as PNG and EXR with layers, denoise on/off,
# exports, poster and caption.
run tour_default tour -o tour_default.mp4 --frames 3 "${small[@]}" --threads 2
run tour_plain tour bunny.ply --up y --preset plain --path turntable --frames 3 "${small[@]}" -o tour_plain.mp4 \
  --frames-dir frames_plain --format png+exr --exr-layers albedo,normal,depth
run tour_paper tour bunny.ply --up y --path paper --frames 3 "${small[@]}" -o tour_paper.mp4 --denoise off \
  --background transparent --frames-dir frames_paper
run tour_feature tour bunny.ply --up auto --path feature-orbit --frames 3 "${small[@]}" -o tour_feature.mp4 \
  --gltf tour_feature.gltf --camera-frames tour_feature.csv --poster tour_feature_poster.png \
  --caption "Bunny" --caption-size 7 --title-card 1 --fps 10
run tour_seconds tour --seconds 0.2 --fps 10 "${small[@]}" --exposure 0.5 --crease-angle 30 --fov 40 \
  --elevation 10 -o tour_seconds.mp4

# render + encode, every codec
run render render --out-dir render_frames --frame-count 4 --frames 0-3 "${small[@]}" --format png+exr
for codec in h264 prores ffv1 vp9 gif; do
  case $codec in h264) ext=mp4 ;; prores) ext=mov ;; ffv1) ext=mkv ;; vp9) ext=webm ;; gif) ext=gif ;; esac
  run "encode_$codec" encode render_frames -o "encoded.$ext" --codec "$codec"
done
run encode_exr encode render_frames -o encoded_exr.mp4 --input-format exr --tone-mapping clamp --crf 23

# batch with a web page, farm scripts (not submitted)
printf 'mesh,output,preset,frame-count,width,height,spp\n%s,a.mp4,studio,2,64,36,2\n%s,b.mp4,plain,2,64,36,2\n' \
  "$work/bunny.ply" "$work/bunny.ply" > manifest.csv
run batch batch manifest.csv --out-dir batch_out --web
run farm farm slurm bunny.ply --out-dir "$work/farm_out" --chunk-size 2 --frames 4 "${small[@]}" \
  --executable meshtour

# path, evaluate, info, options, help
run path_paper path bunny.ply -o path_paper.json --plot path_paper.png --overview path_overview.png \
  --overview-size 160x90
run path_turntable path bunny.ply --path turntable --camera-frames path_turntable.csv --gltf path_turntable.gltf
run evaluate evaluate bunny.ply --compare --samples 2000 --frames 12 --width 64 --height 36
run info_text info bunny.ply
run info_json info bunny.ply --json
run options options
for c in tour render encode batch farm evaluate path info; do run "help_$c" "$c" --help; done
run help_farm_slurm farm slurm --help
run help_top --help

# Times, the run's own folder and progress lines differ between runs; everything else must not:
# text outputs lose their timing fields (JSON keys, "times" lines, the batch table's seconds
# column) and the run's folder; an EXR is hashed as its pixels and header without renderSeconds.
normalise() {
  python3 - "$1" "$work" "$bin" <<'PY'
import json, re, sys
path, work, binary = sys.argv[1], sys.argv[2], sys.argv[3]
text = open(path, encoding="utf-8", errors="replace").read().replace(work, "WORK").replace(binary, "MESHTOUR")
timing = re.compile(r"^(times?|timings?|elapsed|seconds|duration|started|finished|date|render_?seconds)([_a-z]*)$", re.I)
def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items() if not timing.match(k)}
    if isinstance(v, list):
        return [strip(x) for x in v]
    return v
if path.endswith(".json"):
    try:
        text = json.dumps(strip(json.loads(text)), sort_keys=True)
    except ValueError:
        pass
lines = []
for line in text.splitlines():
    if re.match(r"^\s*times\b", line):
        continue
    if path.endswith("batch.stdout"):
        line = " ".join(re.sub(r"^(\d+\s+\S+\s+)\d+(\.\d+)?", r"\1T", line).split())
    line = re.sub(r"\b\d+(\.\d+)? ?(ms|s|min)\b", "T", line)
    lines.append(line)
sys.stdout.write("\n".join(lines))
PY
}
{
  cat "$log"
  find . -type f ! -name '*.stderr' ! -name commands.log ! -name bunny.ply ! -name manifest.csv -print | LC_ALL=C sort |
    while read -r f; do
      case "$f" in
        *.stdout|*.json|*.sh|*.sbatch|*.csv|*.html|*.txt|*.md) printf '%s  %s\n' "$(normalise "$f" | sha256sum | cut -c1-64)" "$f" ;;
        *.exr) printf '%s  %s\n' "$(iinfo -v --hash "$f" | grep -v renderSeconds | sed "s#$work#WORK#" | sha256sum | cut -c1-64)" "$f" ;;
        *) printf '%s  %s\n' "$(sha256sum < "$f" | cut -c1-64)" "$f" ;;
      esac
    done
} > "$out"
echo "output-hashes: $(wc -l < "$out") lines in $out (outputs kept in $work)"
