#!/usr/bin/env bash
# Installs every Debian 12 package that meshtour needs to build, run and test.
# Idempotent: packages already present are not touched, and nothing is printed for them.
set -euo pipefail

packages=(
  build-essential cmake pkg-config ninja-build
  libembree-dev libtbb-dev                  # tracer: Embree 3 with TBB tasking
  libopenimageio-dev libopenexr-dev         # frames: PNG/EXR through OpenImageIO
  openimageio-tools                         # OpenImageIO's CMake config refers to its tools (iconvert, ...)
  libopenmesh-dev libeigen3-dev             # pathgen: mesh I/O and linear algebra
  libavcodec-dev libavformat-dev libavutil-dev libswscale-dev  # video encoder
  nlohmann-json3-dev libcli11-dev           # scene/path files, command line
  libgtest-dev libgmock-dev libbenchmark-dev  # tests and benchmarks
  ffmpeg                                    # ffprobe, used by tests as an independent reader
  clang libclang-rt-14-dev                  # fuzz targets: clang with libFuzzer and the sanitizers
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
