#!/usr/bin/env bash
# Configures and builds meshtour (Release). Two build folders, so that neither command
# reconfigures the other's:
#   scripts/build.sh           the program alone into build/ (tests and benchmarks off): what
#                              scripts/tour.sh builds, then build/cli/meshtour
#   scripts/build.sh --tests   the program, the tests and the benchmarks into build-test/: what
#                              scripts/test.sh builds and runs (ctest --test-dir build-test)
# Further arguments go to the configure step.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = --tests ]; then
  shift
  cmake -S . -B build-test -G Ninja -DCMAKE_BUILD_TYPE=Release -DMESHTOUR_BUILD_TESTS=ON -DMESHTOUR_BUILD_BENCH=ON "$@" >/dev/null
  cmake --build build-test -j "$(nproc)"
else
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DMESHTOUR_BUILD_TESTS=OFF -DMESHTOUR_BUILD_BENCH=OFF "$@" >/dev/null
  cmake --build build -j "$(nproc)" --target meshtour
fi
