#!/usr/bin/env bash
# Quick start, first command: install what is needed, build, and render the default tour
# (a built-in procedural sculpture, no download) to meshtour-default.mp4. It builds the program
# alone, into build/ (scripts/test.sh builds the tests into build-test/).
# Arguments are passed to `meshtour tour`, e.g. scripts/tour.sh mesh.ply -o mesh.mp4
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
./scripts/build.sh
exec ./build/cli/meshtour tour "$@"
