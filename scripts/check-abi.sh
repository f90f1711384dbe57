#!/usr/bin/env bash
# The public API and ABI against the recorded one (abi/libfemto.abi, written by abidw from the
# public headers and libfemto.so): any change (a function added, removed or changed, a public
# struct or enum changed) fails the check, so that the public surface changes only on purpose.
# On purpose means: `bash scripts/check-abi.sh --update` records the new surface, and
# CHANGELOG.md says what changed in its "Unreleased" section (the check fails when the recorded
# surface changed and CHANGELOG.md did not; both are compared with the last commit).
# The record stands in for the last tagged version until femto has tags: it is the surface of the
# last version that changed it on purpose. Uses build/libfemto.so (scripts/test.sh builds it
# with debug info), else a library-only build in build-abi/. Needs abigail-tools (abidw, abidiff).
set -euo pipefail
cd "$(dirname "$0")/.."
say() { echo "check-abi: $*"; }
fail() { echo "check-abi: FAILED: $*" >&2; exit 1; }
update=false
[ "${1:-}" = --update ] && update=true
if ! command -v abidiff >/dev/null || ! command -v abidw >/dev/null; then
  [ "${CI:-}" = true ] && fail "CI=true and not tested: abidiff is missing (apt-get install abigail-tools)"
  say "SKIPPED: abidiff is missing (apt-get install abigail-tools): the public ABI is not compared"
  exit 0
fi
library=build/libfemto.so
if [ ! -f "$library" ] || ! grep -q '^CMAKE_BUILD_TYPE:STRING=RelWithDebInfo' build/CMakeCache.txt; then
  cmake -S . -B build-abi -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFEMTO_BUILD_CLI=OFF \
    -DFEMTO_BUILD_TESTS=OFF -DFEMTO_BUILD_EXAMPLES=OFF -DFEMTO_BUILD_VIEWER=OFF >/dev/null
  cmake --build build-abi -j"$(nproc 2>/dev/null || echo 2)" --target femto_shared >/dev/null
  library=build-abi/libfemto.so
fi
mkdir -p build-abi
# Machine-independent: no paths, no build folder; only what the public headers declare.
abidw --headers-dir include/femto --drop-private-types --exported-interfaces-only --no-show-locs --no-comp-dir-path \
  --no-corpus-path --out-file build-abi/current.abi "$library"
if $update; then
  cp build-abi/current.abi abi/libfemto.abi
  say "recorded the public ABI of $library in abi/libfemto.abi: say what changed in CHANGELOG.md"
  exit 0
fi

# The control: the comparison tells a renamed function apart (it can fail).
sed "s/'fmCreateWorld'/'fmCreateWorldRenamed'/g" \
  abi/libfemto.abi >build-abi/control.abi
if abidiff build-abi/control.abi abi/libfemto.abi >/dev/null 2>&1; then
  fail "the control (fmCreateWorld renamed in a copy of the record) compared equal"
fi

status=0
# Record against record: both read through the public headers the same way (a struct member
# added at the end of fmBodyStats is reported: abidiff status 4, its size from 640 to 704 bits).
abidiff abi/libfemto.abi build-abi/current.abi >build-abi/report.txt 2>&1 || status=$?
if [ "$status" != 0 ]; then
  cat build-abi/report.txt >&2
  fail "the public API/ABI differs from abi/libfemto.abi (abidiff status $status). If on purpose: bash scripts/check-abi.sh --update, and say what changed in CHANGELOG.md"
fi
# A recorded change comes with its changelog entry.
if git rev-parse --verify -q HEAD~1 >/dev/null && ! git diff --quiet HEAD~1 -- abi/libfemto.abi &&
  git diff --quiet HEAD~1 -- CHANGELOG.md; then
  fail "abi/libfemto.abi changed in the last commit but CHANGELOG.md did not: say what changed"
fi
say "the public API/ABI is the recorded one ($(grep -c '<function-decl' abi/libfemto.abi) functions; control told apart)"
