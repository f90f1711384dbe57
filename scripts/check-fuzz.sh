#!/usr/bin/env bash
# Build the libFuzzer targets with clang + ASan + UBSan and run each (fuzz_tetgen, fuzz_face,
# fuzz_obj, fuzz_gmsh, fuzz_vtk, fuzz_vtu, fuzz_medit, fuzz_scene, fuzz_simulate, fuzz_api:
# every build-fuzz/fuzz/fuzz_*) for a bounded time on its committed seed corpus
# (fuzz/corpus/<name>). New crashes fail the check; the crashing input is kept in
# build-fuzz/crashes/ to be turned into a regression test (tests/data/fuzz/).
# The targets run one a core at a time (two at once on 2 cores), each for its whole time.
# FEMTO_FUZZ_SECONDS (default 20) sets the time per target; the five surface and mesh format
# readers (fuzz_obj, fuzz_gmsh, fuzz_vtk, fuzz_vtu, fuzz_medit) run FEMTO_FUZZ_FORMAT_SECONDS
# each (default 15).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${FEMTO_FUZZ_SECONDS:-20}
format_seconds=${FEMTO_FUZZ_FORMAT_SECONDS:-15}
if ! command -v clang >/dev/null; then
  echo "check-fuzz: clang not found (scripts/install-deps.sh installs it)" >&2
  exit 1
fi
CC=clang cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=Debug -DCMAKE_C_FLAGS_DEBUG="-O1 -g" \
  -DFEMTO_SANITIZE=ON -DFEMTO_BUILD_FUZZERS=ON -DFEMTO_BUILD_TESTS=OFF -DFEMTO_BUILD_VIEWER=OFF \
  >/dev/null
cmake --build build-fuzz -j"$(nproc 2>/dev/null || echo 2)" >/dev/null
mkdir -p build-fuzz/crashes
rm -f build-fuzz/*.failed
# fuzz_one NAME TARGET: one fuzzer for its time; a failure leaves build-fuzz/NAME.failed.
fuzz_one() {
  local name=$1 target=$2 work="build-fuzz/corpus-$1" max_len=65536 time=$seconds
  mkdir -p "$work"
  # The parsers read files; the simulation and API fuzzers decode a few hundred bytes.
  case "$name" in simulate | api) max_len=4096 ;; esac
  case "$name" in obj | gmsh | vtk | vtu | medit) time=$format_seconds ;; esac
  echo "check-fuzz: $name for ${time}s"
  # The seed corpus is read-only input; new inputs go to the scratch corpus in build-fuzz/.
  if ! "$target" "$work" "fuzz/corpus/$name" -max_total_time="$time" -max_len="$max_len" \
    -rss_limit_mb=2048 -timeout=10 -artifact_prefix=build-fuzz/crashes/"$name"- \
    -print_final_stats=1 2>"build-fuzz/$name.log"; then
    touch "build-fuzz/$name.failed"
    return
  fi
  echo "check-fuzz: $name: $(grep -E "stat::number_of_executed_units" "build-fuzz/$name.log" | tail -n 1 | tr -s ' ')"
}
# One fuzzer a core at a time: each gets its whole time on a core of its own.
slots=$(nproc 2>/dev/null || echo 2)
running=0
for target in build-fuzz/fuzz/fuzz_*; do
  [ -x "$target" ] || continue
  if [ "$running" -ge "$slots" ]; then
    wait -n || true
    running=$((running - 1))
  fi
  fuzz_one "$(basename "$target" | sed 's/^fuzz_//')" "$target" &
  running=$((running + 1))
done
wait
for failed in build-fuzz/*.failed; do
  [ -e "$failed" ] || continue
  name=$(basename "$failed" .failed)
  tail -n 40 "build-fuzz/$name.log" >&2
  echo "check-fuzz: $name FAILED; input in build-fuzz/crashes/" >&2
  exit 1
done
# The README states how many fuzzers run for how long: those counts are these.
long=0 short=0
for target in build-fuzz/fuzz/fuzz_*; do
  [ -x "$target" ] || continue
  case "$(basename "$target")" in
    fuzz_obj | fuzz_gmsh | fuzz_vtk | fuzz_vtu | fuzz_medit) short=$((short + 1)) ;;
    *) long=$((long + 1)) ;;
  esac
done
stated=$(sed -n 's/.*the fuzzers (\([0-9]*\) targets \([0-9]*\) s each.*/\1 \2/p' README.md | head -n 1)
stated_short=$(sed -n 's/.*the \([0-9]*\) surface and mesh format readers \([0-9]*\) s each.*/\1 \2/p' README.md | head -n 1)
if [ "$stated" != "$long ${FEMTO_FUZZ_SECONDS:-20}" ] || [ "$stated_short" != "$short ${FEMTO_FUZZ_FORMAT_SECONDS:-15}" ]; then
  echo "check-fuzz: ran $long targets for ${FEMTO_FUZZ_SECONDS:-20} s and $short for ${FEMTO_FUZZ_FORMAT_SECONDS:-15} s; README.md says '${stated:-?}' and '${stated_short:-?}' (update it)" >&2
  [ -z "${FEMTO_FUZZ_SECONDS:-}${FEMTO_FUZZ_FORMAT_SECONDS:-}" ] && exit 1
fi
echo "check-fuzz: all fuzzers clean"
