#!/usr/bin/env bash
# The contact sheet in a real browser: a batch of the shared meshes with captions (UTF-8) and one
# broken item, run with --web, must exit 5 and give a page where every poster loads, every video
# plays in headless Chromium and the broken item shows its error (check-page.js). A screenshot goes
# to the build folder (browser-test/contact-sheet.png).
# Exit 77 = skipped, loudly: no ../shared/meshes, no Chromium, no puppeteer-core (npm ci in
# tests/browser, done by scripts/install-deps.sh --tests), or Chromium cannot start. Under
# MESHTOUR_REQUIRE_SHARED=1 (CI) each of these fails instead.
# Usage: run-browser-test.sh MESHTOUR_EXECUTABLE BUILD_DIR
set -uo pipefail
meshtour="$1"
build="$2"
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
meshes="$root/../shared/meshes"

skip() {
  if [ "${MESHTOUR_REQUIRE_SHARED:-0}" = 1 ]; then
    echo "FAIL (MESHTOUR_REQUIRE_SHARED=1): $*" >&2
    exit 1
  fi
  echo "SKIPPED: $*" >&2
  exit 77
}

[ -f "$meshes/bear.ply" ] && [ -f "$meshes/rocker.ply" ] && [ -f "$meshes/venus.ply" ] ||
  skip "$meshes is missing (the ../shared test data is not checked out)"
command -v node >/dev/null || skip "node is not installed (scripts/install-deps.sh --tests)"
[ -x "${CHROMIUM:-/usr/bin/chromium}" ] || skip "Chromium is not installed (Debian package chromium, scripts/install-deps.sh --tests)"
[ -d "$here/node_modules/puppeteer-core" ] || skip "puppeteer-core is not installed (cd tests/browser && npm ci)"

work="$(cd "$build" && pwd)/browser-test"
rm -rf "$work"
mkdir -p "$work"
cat > "$work/manifest.csv" <<CSV
mesh,caption,up,path
$meshes/bear.ply,Bear — Bär,y,turntable
$meshes/rocker.ply,Rocker arm 100%,y,turntable
$meshes/venus.ply,Vénus — plaster cast,z,turntable
$work/broken.ply,Broken item,y,turntable
CSV
# A file that is not a mesh: the item fails, the others are done.
printf 'ply\nthis is not a mesh\n' > "$work/broken.ply"

"$meshtour" batch "$work/manifest.csv" --out-dir "$work/out" --web --width 320 --height 180 --frames 12 --spp 1 -q
status=$?
if [ "$status" != 5 ]; then
  echo "FAIL: batch exited $status, expected 5 (some items failed)" >&2
  exit 1
fi
error_line=$(node -e 'const s=JSON.parse(require("fs").readFileSync(process.argv[1], "utf8")); const f=s.items.find(i=>i.status==="failed"); console.log(f ? f.error.split("\n")[0].slice(0, 40) : "")' "$work/out/batch-summary.json")
[ -n "$error_line" ] || { echo "FAIL: the summary has no failed item" >&2; exit 1; }

node "$here/check-page.js" "$work/out" "$work/contact-sheet.png" "$error_line"
status=$?
[ "$status" = 77 ] && skip "Chromium could not start (see above)"
exit "$status"
