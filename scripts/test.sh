#!/usr/bin/env bash
# Build femto and run every test: a normal build, then the whole suite under
# AddressSanitizer + UndefinedBehaviorSanitizer, then the fuzzers, valgrind, ThreadSanitizer on the
# thread pool, the consumer projects, the determinism suite on clang, musl, AArch64 and
# WebAssembly, and the browser build (scripts/check-*.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
jobs=$(nproc 2>/dev/null || echo 2)

# Every option that decides what gets built is given, so a cache left by an earlier configure
# (a demo or a hand-made build with the tests off) cannot shrink the suite; and a ctest that
# finds no tests fails (--no-tests=error) instead of passing.
suite=(-DFEMTO_BUILD_TESTS=ON -DFEMTO_BUILD_CLI=ON -DFEMTO_BUILD_FUZZERS=OFF)
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFEMTO_SANITIZE=OFF "${suite[@]}"
cmake --build build -j"$jobs"
(cd build && ctest --no-tests=error --output-on-failure -j"$jobs")

cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_C_FLAGS_DEBUG="-O1 -g" -DFEMTO_SANITIZE=ON \
  "${suite[@]}"
cmake --build build-asan -j"$jobs"
(cd build-asan && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --no-tests=error --output-on-failure -j"$jobs")

for extra in scripts/check-*.sh; do
  [ -f "$extra" ] && bash "$extra"
done
echo "all femto tests passed"
