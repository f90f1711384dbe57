#!/usr/bin/env bash
# Build femto and run every test: a normal build, then the whole suite under
# AddressSanitizer + UndefinedBehaviorSanitizer, then the fuzzers and valgrind (scripts/check-*.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
jobs=$(nproc 2>/dev/null || echo 2)

cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build build -j"$jobs"
(cd build && ctest --output-on-failure -j"$jobs")

cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_C_FLAGS_DEBUG="-O1 -g" -DFEMTO_SANITIZE=ON
cmake --build build-asan -j"$jobs"
(cd build-asan && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j"$jobs")

for extra in scripts/check-*.sh; do
  [ -f "$extra" ] && bash "$extra"
done
echo "all femto tests passed"
