#!/usr/bin/env bash
# ThreadSanitizer over femto's thread pool (src/parallel.c hands out ranges without a lock): the
# test suite built with -fsanitize=thread in build-tsan/, then the tests that run loops on several
# workers: the pool's own (thousands of back-to-back loops on 2-4 workers) and the SIMD kernels'
# across worker counts. Any data race fails the run.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFEMTO_SANITIZE=OFF \
  -DFEMTO_BUILD_TESTS=ON -DFEMTO_BUILD_CLI=OFF -DFEMTO_BUILD_FUZZERS=OFF \
  -DCMAKE_C_FLAGS="-fsanitize=thread" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread" \
  -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=thread" >/dev/null
cmake --build build-tsan -j"$jobs" --target femto_tests >/dev/null
export TSAN_OPTIONS="halt_on_error=1 exitcode=66"
for run in "parallel the_pool_runs_every_item_exactly_once" "parallel worker_count_and_callbacks_are_validated" "simd"; do
  echo "check-tsan: tests $run"
  # shellcheck disable=SC2086 # suite and test name
  build-tsan/tests/femto_tests $run >/dev/null
done
echo "check-tsan: no data race"
