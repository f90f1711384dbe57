#!/usr/bin/env bash
# Build femto and run every test: a normal build, then the whole suite under
# AddressSanitizer + UndefinedBehaviorSanitizer (FEMTO_TEST_QUICK=1: the slow tests with their
# small counts), then every scripts/check-*.sh: the README's and docs' commands as written, the
# consumer projects, the determinism suite on other targets, the fuzzers, ThreadSanitizer,
# valgrind and the browser build.
#
# A skipped test is never a pass: ctest's skipped tests (a tool such as gmsh missing) are listed
# at the end and, under CI=true, fail the run; so does a check-*.sh that could not test something
# (each says what). The README's test counts are checked against what ctest ran.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
jobs=$(nproc 2>/dev/null || echo 2)
start=$(date +%s)
ci=${CI:-}
skipped_all=()

# run_suite DIR NAME README_PATTERN: ctest in DIR; its skipped tests are collected (a failure
# under CI=true), and its count must be the one the README states (README_PATTERN captures it).
run_suite() {
  local dir=$1 name=$2 pattern=$3 log=$1/ctest.log status=0
  # The README's quick path, `ctest --test-dir build -j2`, with what CI needs added.
  ctest --test-dir "$dir" --no-tests=error --output-on-failure -j"$jobs" 2>&1 | tee "$log" || status=$?
  [ "$status" = 0 ] || { echo "test.sh: the $name suite failed" >&2; exit 1; }
  local skipped total stated
  skipped=$(grep -E '^[[:space:]]*[0-9]+ - .*\((Skipped|Not Run|Disabled)\)' "$log" | sed 's/^[[:space:]]*//' || true)
  if [ -n "$skipped" ]; then
    while IFS= read -r line; do skipped_all+=("$name: $line"); done <<<"$skipped"
  fi
  total=$(sed -n 's/.*tests failed out of \([0-9][0-9]*\).*/\1/p' "$log" | tail -n 1)
  stated=$(sed -n "s/.*$pattern.*/\\1/p" README.md | head -n 1)
  if [ "$total" != "$stated" ]; then
    echo "test.sh: the $name suite ran $total tests; README.md says ${stated:-nothing} (update it)" >&2
    [ "$ci" = true ] && exit 1
  fi
}

# Every option that decides what gets built is given, so a cache left by an earlier configure
# (a demo or a hand-made build with the tests off) cannot shrink the suite; and a ctest that
# finds no tests fails (--no-tests=error) instead of passing.
suite=(-DFEMTO_BUILD_TESTS=ON -DFEMTO_BUILD_CLI=ON -DFEMTO_BUILD_FUZZERS=OFF)
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFEMTO_SANITIZE=OFF "${suite[@]}"
cmake --build build -j"$jobs"
echo "test.sh: the dependencies and the normal build took $(($(date +%s) - start)) s"
run_suite build normal 'normal suite (\([0-9]*\) cases)'

cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_C_FLAGS_DEBUG="-O1 -g" -DFEMTO_SANITIZE=ON \
  "${suite[@]}"
cmake --build build-asan -j"$jobs"
export ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 FEMTO_TEST_QUICK=1
run_suite build-asan ASan+UBSan 'ASan+UBSan suite (\([0-9]*\)[;)]'
unset ASAN_OPTIONS UBSAN_OPTIONS FEMTO_TEST_QUICK

for extra in scripts/check-*.sh; do
  log=build/$(basename "$extra" .sh).log
  echo "test.sh: $extra"
  began=$(date +%s)
  bash "$extra" 2>&1 | tee "$log"
  echo "test.sh: $extra took $(($(date +%s) - began)) s"
  while IFS= read -r line; do skipped_all+=("$line"); done < <(grep 'SKIPPED' "$log" || true)
done

if [ ${#skipped_all[@]} -gt 0 ]; then
  echo "test.sh: NOT TESTED here (a tool was missing; scripts/install-deps.sh installs it):" >&2
  printf '  %s\n' "${skipped_all[@]}" >&2
  [ "$ci" = true ] && { echo "test.sh: under CI=true every test must run" >&2; exit 1; }
  echo "femto tests passed in $(($(date +%s) - start)) s, except the ${#skipped_all[@]} not tested above"
  exit 0
fi
echo "all femto tests passed in $(($(date +%s) - start)) s"
