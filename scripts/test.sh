#!/usr/bin/env bash
# Quick start, second command: install what is needed, build, and run the whole test suite:
#  1. a Release build of the program, the tests and the benchmarks in build-test/ (scripts/tour.sh
#     builds the program alone in build/), and all tests;
#  2. an AddressSanitizer + UndefinedBehaviorSanitizer build and all tests again, under the
#     sanitizers (set MESHTOUR_SKIP_SANITIZERS=1 to skip this half on a slow machine);
#  3. the libFuzzer targets (fuzz/, clang) for a fixed number of inputs each (MESHTOUR_SKIP_FUZZ=1 skips).
# Tests that need ../shared/meshes skip when it is absent, unless MESHTOUR_REQUIRE_SHARED=1.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)
./scripts/install-deps.sh --tests

echo "== Release build and tests"
./scripts/build.sh --tests
ctest --test-dir build-test --output-on-failure -j "$jobs" --timeout 600

if [ "${MESHTOUR_SKIP_SANITIZERS:-0}" != 1 ]; then
  echo "== AddressSanitizer + UndefinedBehaviorSanitizer build and tests"
  # Clang 14 (the fuzz build's compiler): it builds this tree with both sanitizers in 1,122-1,240 s
  # of CPU against GCC 12's 3,018-3,268 s (docs/TESTING.md), which is most of CI's time budget.
  # Its tile kernel is checked by ASan only (tracer/CMakeLists.txt).
  CC=clang CXX=clang++ cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMESHTOUR_SANITIZE=ON -DMESHTOUR_BUILD_BENCH=OFF >/dev/null
  cmake --build build-asan -j "$jobs"
  # TBB keeps worker threads and their arenas alive until exit, which LeakSanitizer reports as
  # leaks of the runtime, not of meshtour; leaks are still checked, with TBB's suppressed.
  export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0"
  # new_delete_type_mismatch=0: OpenImageIO 2.4's own TextureSystem::destroy() frees its object with a
  # sized delete of the wrong size (inside libOpenImageIO, not meshtour); every other check stays on.
  export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:new_delete_type_mismatch=0"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
  ctest --test-dir build-asan --output-on-failure -j "$jobs" --timeout 900 -LE slow
fi
if [ "${MESHTOUR_SKIP_FUZZ:-0}" != 1 ]; then
  echo "== Fuzz targets (clang + libFuzzer), a fixed number of inputs each"
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMESHTOUR_FUZZ=ON >/dev/null
  cmake --build build-fuzz -j "$jobs"
  ctest --test-dir build-fuzz --output-on-failure -j "$jobs" --timeout 300
fi
echo "== all tests passed"
