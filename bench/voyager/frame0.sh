#!/usr/bin/env bash
# Voyager scenes: frame 0 of the tour against the document's opening view, in every path mode
# (docs/EVALUATION.md#voyager-scenes-frame-0-and-the-opening-view). Writes four .svx.json
# documents from the SVX schema for the shared meshes (../shared/meshes; Venus is stored +Z, the
# kitten is turned by a node matrix and back by the model's rotation) into WORK, links the meshes
# in as their derivatives, and runs `meshtour path --camera-frames` on them and on any further
# documents given (a real delivery, with its model files beside it). Models stay out of the
# repository. Usage: bench/voyager/frame0.sh [WORK] [more.svx.json ...]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
M=${MESHTOUR:-$ROOT/build/cli/meshtour}
[ -x "$M" ] || M=$ROOT/build-test/cli/meshtour
WORK=${1:-/tmp/meshtour-voyager}
shift || true
SHARED=$(cd "$ROOT/../shared/meshes" && pwd)
mkdir -p "$WORK"
cd "$WORK"
document() {  # name mesh units model-pose orbit title node
  ln -sf "$SHARED/$2.ply" "$2.ply"
  cat > "$1.svx.json" <<DOC
{"asset": {"type": "application/si-dpo-3d.document+json", "version": "1.0", "generator": "meshtour bench/voyager"},
 "scene": 0, "scenes": [{"units": "cm", "nodes": [0, 1], "setup": 0, "meta": 0}],
 "nodes": [{"translation": [0, 0, 15], "name": "Camera", "camera": 0}, $7],
 "cameras": [{"type": "perspective", "perspective": {"yfov": 52, "znear": 0.1, "zfar": 100000}}],
 "setups": [{"units": "cm", "navigation": {"type": "Orbit", "enabled": true, "autoZoom": true,
   "orbit": {"orbit": $5, "offset": [0, 0, 150], "minOrbit": [-90, null, null], "maxOrbit": [90, null, null]}}}],
 "metas": [{"collection": {"title": "$6"}}],
 "models": [{"units": "$3", $4 "derivatives": [
   {"usage": "Web3D", "quality": "Highest", "assets": [{"uri": "$2-highest.glb", "type": "Model"}]},
   {"usage": "Web3D", "quality": "High", "assets": [{"uri": "$2.ply", "type": "Model"}]}]}]}
DOC
  echo "$1.svx.json"
}
docs=(
  "$(document venus venus mm '"rotation": [-0.70710678, 0, 0, 0.70710678],' '[-15, 40, 0]' 'Venus' '{"name": "Venus", "model": 0}')"
  "$(document bunny bunny m '' '[-24, -26, 0]' 'Stanford Bunny' '{"name": "Bunny", "model": 0}')"
  "$(document horse horse m '"translation": [0.01, 0, 0],' '[-30, 120, 0]' 'Horse' '{"name": "Horse", "model": 0}')"
  "$(document kitten kitten mm '"rotation": [0, 0, -0.70710678, 0.70710678],' '[-35, -150, 0]' 'Kitten' \
     '{"name": "Kitten", "matrix": [0,1,0,0, -1,0,0,0, 0,0,1,0, 0,0,0,1], "model": 0}')"
  "$@")
for doc in "${docs[@]}"; do
  name=$(basename "$doc" .svx.json)
  for mode in feature-orbit turntable paper; do
    if ! "$M" path "$doc" --path "$mode" --frames 120 -q -o "$name.$mode.path.json" --camera-frames "$name.$mode.csv" 2>"$name.$mode.err"; then
      echo "$name $mode: $(tail -1 "$name.$mode.err")"
      continue
    fi
    python3 - "$doc" "$name.$mode.csv" "$name" "$mode" <<'PY'
import csv, json, math, sys
doc, frames, name, mode = sys.argv[1:]
d = json.load(open(doc))
setup = d["setups"][d["scenes"][d.get("scene", 0)].get("setup", 0)]
pitch, head, _ = setup.get("navigation", {}).get("orbit", {}).get("orbit", [-25, -25, 0])
rows = list(csv.DictReader(open(frames)))
def view(r):
    v = [float(r[f"eye_{a}"]) - float(r[f"target_{a}"]) for a in "xyz"]
    return math.degrees(math.atan2(v[0], v[2])), math.degrees(math.asin(v[1] / math.sqrt(sum(c * c for c in v))))
az, el = view(rows[0])
want = max(0.0, -pitch)  # the floor rule: never below level with the centre
print(f"{name:8s} {mode:13s} opening az {head:7.1f} el {-pitch:5.1f} | frame 0 az {az:8.3f} el {el:6.3f} | "
      f"off by {(az - head + 180) % 360 - 180:+.3f}, {el - want:+.3f} deg | lowest eye {min(view(r)[1] for r in rows):6.2f} deg")
PY
  done
done
