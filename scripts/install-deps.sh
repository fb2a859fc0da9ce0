#!/usr/bin/env bash
# Installs the Debian 12 packages that meshtour needs:
#   scripts/install-deps.sh           to build and run the program (scripts/tour.sh)
#   scripts/install-deps.sh --tests   also to build and run the tests, the benchmarks and the fuzz
#                                     targets, with Node.js and the tests' npm packages (scripts/test.sh)
#   scripts/install-deps.sh --bench   also the independent renderer the comparisons run against
#                                     (Blender's Cycles, with the numpy its glTF importer needs:
#                                     bench/cycles_*.sh); not needed by any test
# The first command installs only the first list: the tests' tools (Chromium, Slurm, clang, ...)
# are most of the download.
# Idempotent: packages already present are not touched, and nothing is printed for them.
set -euo pipefail

with_tests=0 with_bench=0
if [ "${1:-}" = --tests ]; then
  with_tests=1
elif [ "${1:-}" = --bench ]; then
  with_tests=1 with_bench=1
elif [ $# -gt 0 ]; then
  echo "usage: scripts/install-deps.sh [--tests | --bench]" >&2
  exit 2
fi

packages=(
  build-essential cmake pkg-config ninja-build
  libembree-dev libtbb-dev                  # tracer: Embree 3 with TBB tasking
  libopenimageio-dev libopenexr-dev         # frames: PNG/EXR through OpenImageIO
  openimageio-tools                         # OpenImageIO's CMake config refers to its tools (iconvert, ...)
  libopenmesh-dev libeigen3-dev             # pathgen: mesh I/O and linear algebra
  libqhull-dev                              # mesh: convex hulls (reentrant libqhull_r) for fast framing
  libtinygltf-dev libdraco-dev              # mesh: glTF/GLB input, Draco-compressed primitives
  libmeshoptimizer-dev                      # mesh: glTF EXT_meshopt_compression (gltfpack's output)
  zlib1g-dev                                # mesh: the PNG textures' structure checked before libpng reads them
  libavcodec-dev libavformat-dev libavutil-dev libswscale-dev  # video encoder
  libavfilter-dev                           # video encoder: the GIF palette (palettegen, paletteuse), captions (drawtext, xfade)
  libfreetype-dev libfontconfig-dev         # captions: measuring the text, finding the font
  fonts-dejavu-core                         # captions: the default font, DejaVu Sans
  nlohmann-json3-dev libcli11-dev           # scene/path files, command line
)
test_packages=(
  draco                                     # tests: draco_encoder, draco_transcoder make Draco-compressed inputs
  chromium                                  # tests: the contact sheet of batch --web in a real browser (tests/browser)
  libgtest-dev libgmock-dev libbenchmark-dev  # tests and benchmarks
  ffmpeg                                    # ffprobe, used by tests as an independent reader
  slurmctld slurmd slurm-client munge       # farm: the single-node Slurm cluster of tests/slurm/
  clang libclang-rt-14-dev                  # fuzz targets: clang with libFuzzer and the sanitizers
  python3                                   # the soak test's driver (scripts/soak.py)
)
bench_packages=(
  blender python3-numpy                     # bench/cycles_*: Cycles, and the numpy of Blender's glTF importer
)
[ "$with_tests" = 1 ] && packages+=("${test_packages[@]}")
[ "$with_bench" = 1 ] && packages+=("${bench_packages[@]}")

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done
# Node.js runs the Khronos glTF validator in the tests (tests/gltf). Checked by command, not by
# package name, so that a Node.js from another source (which bundles npm) is left alone.
if [ "$with_tests" = 1 ] && { ! command -v node >/dev/null || ! command -v npm >/dev/null; }; then
  missing+=(nodejs npm)
fi

# npm packages the tests call through Node.js, each pinned by its folder's package-lock.json;
# `npm ci` only when node_modules is missing or the lock file changed since the last install:
# tests/gltf holds the Khronos glTF validator, tests/browser puppeteer-core (it drives Debian's
# Chromium and never downloads a browser).
npm_ci_if_stale() {
  local folder="$1" what="$2" dir
  dir="$(cd "$(dirname "$0")/.." && pwd)/$folder"
  if [ ! -f "$dir/node_modules/.package-lock.json" ] || [ "$dir/package-lock.json" -nt "$dir/node_modules/.package-lock.json" ]; then
    echo "install-deps: npm ci in $folder ($what)"
    (cd "$dir" && npm ci --no-audit --no-fund --loglevel=error >/dev/null)
  fi
}
install_npm_packages() {
  [ "$with_tests" = 1 ] || return 0
  npm_ci_if_stale tests/gltf "Khronos glTF validator"
  npm_ci_if_stale tests/browser "puppeteer-core"
}

if [ ${#missing[@]} -eq 0 ]; then
  install_npm_packages
  exit 0
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
# Without systemd, package scripts fall back to /etc/init.d and would start a system munged (and
# try slurmctld/slurmd); a temporary policy-rc.d (exit 101) stops that. The tests start their own.
added_policy=0
if [ ! -e /usr/sbin/policy-rc.d ]; then
  printf '#!/bin/sh\nexit 101\n' | $sudo tee /usr/sbin/policy-rc.d >/dev/null
  $sudo chmod 755 /usr/sbin/policy-rc.d
  added_policy=1
fi
status=0
$sudo apt-get -o DPkg::Lock::Timeout=600 update -qq &&
  $sudo apt-get -o DPkg::Lock::Timeout=600 install -y -qq --no-install-recommends "${missing[@]}" >/dev/null || status=$?
[ "$added_policy" = 1 ] && $sudo rm -f /usr/sbin/policy-rc.d
[ "$status" = 0 ] || exit "$status"
install_npm_packages
