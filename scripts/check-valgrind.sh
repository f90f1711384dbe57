#!/usr/bin/env bash
# Valgrind memcheck over the bouncy-house demo (a short run, embedded mesh, VTK output) and
# over the fast test suites: no invalid reads or writes, no uninitialised values, no leaks.
# Uses the RelWithDebInfo build in build/ (scripts/test.sh builds it first).
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v valgrind >/dev/null; then
  echo "check-valgrind: valgrind not found (scripts/install-deps.sh installs it)" >&2
  exit 1
fi
# Fail now, not after minutes under valgrind, when build/ lacks a binary (e.g. configured with
# the tests off): scripts/test.sh configures it with everything on.
for binary in build/cli/femto build/tests/femto_tests; do
  if [ ! -x "$binary" ]; then
    echo "check-valgrind: $binary is missing; build build/ with the tests on (bash scripts/test.sh)" >&2
    exit 1
  fi
done
vg=(valgrind --quiet --error-exitcode=99 --leak-check=full --show-leak-kinds=definite,indirect
    --errors-for-leak-kinds=definite,indirect --track-origins=yes)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "check-valgrind: femto run (demo, 20 frames, VTK output)"
"${vg[@]}" build/cli/femto run --frames 20 --out "$out/house" --quiet
for suite in mesh_io mesh svd material fem fuzz_regressions; do
  echo "check-valgrind: tests $suite"
  "${vg[@]}" build/tests/femto_tests "$suite" >/dev/null
done
echo "check-valgrind: clean"
