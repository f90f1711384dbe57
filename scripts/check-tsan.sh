#!/usr/bin/env bash
# ThreadSanitizer over everything that runs on several threads: the test suite built with
# -fsanitize=thread in build-tsan/, then the whole parallel suite (the pool's thousands of
# back-to-back loops on 2-4 workers, explicit and implicit steps on 1-4 workers and on a toy
# engine's job system through the task callbacks), the SIMD kernels across worker counts, body
# contact across workers (FEMTO_TEST_QUICK: fewer frames, the houses still meet), the engine
# threads in another floating-point state, and examples/job_system.c (the engine-callback
# example). Any data race fails the run.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFEMTO_SANITIZE=OFF \
  -DFEMTO_BUILD_TESTS=ON -DFEMTO_BUILD_CLI=OFF -DFEMTO_BUILD_FUZZERS=OFF \
  -DCMAKE_C_FLAGS="-fsanitize=thread" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread" \
  -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=thread" >/dev/null
cmake --build build-tsan -j"$jobs" --target femto_tests femto_job_system >/dev/null
export TSAN_OPTIONS="halt_on_error=1 exitcode=66" FEMTO_TEST_QUICK=1
start=$(date +%s)
for run in "parallel" "simd" "contact contact_is_deterministic_across_workers" \
  "determinism engine_threads_in_another_fp_state_give_the_same_bits"; do
  echo "check-tsan: tests $run"
  # shellcheck disable=SC2086 # suite and test name
  build-tsan/tests/femto_tests $run >build-tsan/last.log 2>&1 || { tail -n 60 build-tsan/last.log >&2; exit 1; }
  grep -q " passed, 0 failed" build-tsan/last.log || { cat build-tsan/last.log >&2; exit 1; }
done
echo "check-tsan: examples/job_system.c"
build-tsan/examples/job_system data/house2.node data/house2.ele >build-tsan/last.log 2>&1 ||
  { tail -n 60 build-tsan/last.log >&2; exit 1; }
echo "check-tsan: $(($(date +%s) - start)) s of tests"
echo "check-tsan: no data race"
