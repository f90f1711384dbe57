#!/usr/bin/env bash
# The determinism suite (tests/test_determinism.c) away from the normal build's x86-64, gcc and
# glibc (docs/determinism.md): the test runner with that suite and the library's sources,
# compiled with the project's flags (C11, -ffp-contract=off, warnings as errors; the element and
# sparse-row kernels once per instruction set, as CMakeLists.txt does; FM_ASSERT on) for
#   clang        x86-64, clang, glibc (the kernels' scalar, SSE2, AVX2 and AVX-512 variants)
#   musl         x86-64, gcc, musl (musl-gcc, static)
#   aarch64      AArch64, gcc, glibc (aarch64-linux-gnu-gcc, static), run under qemu-user; the
#                kernels' vectors are NEON there (simd.h's generic vectors, 4 lanes)
#   wasm         WebAssembly (emcc), run under Node.js, the kernels with WebAssembly SIMD
#   wasm-nosimd  the same, the kernels without SIMD (the page's build for browsers without it)
# and run there. Every test must pass, among them the golden hashes (golden_hash_explicit,
# golden_hash_implicit: a box thrown at the floor with crossPlatformDeterminism;
# golden_hash_mixed_scene: four bodies of four materials, body-body contact, a collider of each
# shape, a pin, a load and a target; each explicit and implicit, on one and two workers),
# constants recorded on x86-64 with gcc and glibc: passing them is the same bits as there. The
# simd suite (every instruction set the same bits) runs beside it everywhere, the parallel one
# (every worker count) on x86-64 (150 s under qemu). Then every target's printed hashes are
# compared, and two controls show the comparison can fail: the suite's own (the box one frame
# shorter hashes differently), and
#   fma-control  the aarch64 build with -ffp-contract=fast (GCC's default for GNU C on AArch64)
#                must fail the box's golden hashes: the check sees fused multiply-adds.
# Measured on 2 busy cores: 140 s from scratch, 55 s when only the tests run again.
#
# A missing tool fails the check under CI=true, naming it; elsewhere its targets are SKIPPED with
# the reason and the install command (scripts/install-deps.sh installs every one). Builds in
# build-xplat/<target>/; an object is rebuilt when its source, a header or this script is newer.
#
#   bash scripts/check-determinism.sh [TARGET...]   # default: every target above
set -euo pipefail
cd "$(dirname "$0")/.."
export NODE_PATH="/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}" # Debian's emcc 3.1.6 finds acorn there

all_targets=(clang musl aarch64 fma-control wasm wasm-nosimd)
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=("${all_targets[@]}")
for target in "${targets[@]}"; do
  case " ${all_targets[*]} " in
    *" $target "*) ;;
    *) echo "check-determinism: unknown target $target (${all_targets[*]})" >&2; exit 2 ;;
  esac
done

out=build-xplat
mkdir -p "$out"
start=$(date +%s)
jobs=$(nproc 2>/dev/null || echo 2)
warnings=(-Wall -Wextra -Werror -Wshadow -Wstrict-prototypes -Wvla)
test_flags=(-O2 -Isrc -Itests -DFEMTO_MESH_DIR="\"$PWD/data\"" -DFEMTO_TEST_DATA="\"$PWD/tests/data\"")
newest_header=""
for header in include/femto/*.h src/*/*.h src/*/*/*.h tests/*.h; do
  if [ -z "$newest_header" ] || [ "$header" -nt "$newest_header" ]; then
    newest_header=$header
  fi
done

# --- the targets' tools --------------------------------------------------------------------------
missing() { # target: "tool package" of the first tool it lacks, or nothing
  local pair pairs=()
  case "$1" in
    clang) pairs=(clang:clang) ;;
    musl) pairs=(musl-gcc:musl-tools) ;;
    aarch64 | fma-control)
      pairs=(aarch64-linux-gnu-gcc:gcc-aarch64-linux-gnu qemu-aarch64:qemu-user) ;;
    wasm | wasm-nosimd) pairs=(emcc:emscripten node:nodejs) ;;
  esac
  for pair in "${pairs[@]}"; do
    command -v "${pair%%:*}" >/dev/null || { echo "${pair%%:*} ${pair#*:}"; return; }
  done
  case "$1" in
    aarch64 | fma-control)
      [ -e /usr/aarch64-linux-gnu/lib/libc.a ] ||
        echo "/usr/aarch64-linux-gnu/lib/libc.a libc6-dev-arm64-cross" ;;
  esac
}

# configure target: how it builds and runs. cc: the compiler; contract: -ffp-contract's value;
# variants: the kernels' (every x86-64 build has AVX2 and AVX-512 besides, as in
# CMakeLists.txt); lib: the library's optimisation (GCC's -fpeel-loops as in CMakeLists.txt);
# suites: what runs; runner: what runs the executable $exe.
configure() {
  contract=off variants=(scalar baseline) lib=(-O2) kernel_flags=() suites=(determinism simd)
  runner=() exe=$out/$1/femto_tests
  case "$1" in
    clang)
      cc=clang variants+=(avx2 avx512) suites+=(parallel) link=(-lm -lpthread) ;;
    musl)
      cc=musl-gcc variants+=(avx2 avx512) lib+=(-fpeel-loops) suites+=(parallel)
      link=(-static -lm -lpthread) ;;
    aarch64 | fma-control)
      cc=aarch64-linux-gnu-gcc lib+=(-fpeel-loops) runner=(qemu-aarch64)
      link=(-static -lm -lpthread)
      if [ "$1" = fma-control ]; then contract=fast suites=(determinism); fi ;;
    wasm | wasm-nosimd)
      cc=emcc runner=(node) exe=$out/$1/femto_tests.js
      if [ "$1" = wasm ]; then kernel_flags=(-msimd128); fi
      link=(-sENVIRONMENT=node -sNODERAWFS=1 -sSINGLE_FILE=1 -sALLOW_MEMORY_GROWTH=1) ;;
  esac
}

# --- a tiny make ---------------------------------------------------------------------------------
pids=()
compile() { # source object flags...: with $cc in the background, at most $jobs at once
  local source=$1 object=$2
  shift 2
  if [ -f "$object" ] && [ "$object" -nt "$source" ] && [ "$object" -nt "$newest_header" ] &&
     [ "$object" -nt "$0" ]; then
    return 0
  fi
  "$cc" -c -std=c11 -ffp-contract="$contract" "${warnings[@]}" -Iinclude -Isrc "$@" "$source" \
    -o "$object" &
  pids+=($!)
  if [ "${#pids[@]}" -ge "$jobs" ]; then
    wait "${pids[0]}"
    pids=("${pids[@]:1}")
  fi
}

# build target: $exe, the test runner with $suites, the library's sources and its kernels.
build() {
  local dir=$out/$1 libdir=$out/$1 objects=() source name variant flags pid
  # WebAssembly's two builds differ in their kernels only: the rest is compiled once.
  [ "$1" = wasm-nosimd ] && libdir=$out/wasm
  mkdir -p "$dir" "$libdir"
  for source in src/*/*.c; do
    name=$(basename "$source" .c)
    compile "$source" "$libdir/$name.o" "${lib[@]}"
    objects+=("$libdir/$name.o")
  done
  for variant in "${variants[@]}"; do
    flags=(-O3 -Wno-psabi -fno-math-errno -DFM_KERNEL_VARIANT="$variant" "${kernel_flags[@]}")
    case "$variant" in
      scalar) flags+=(-DFM_SIMD_SCALAR) ;;
      avx2) flags+=(-mavx2) ;;
      avx512) flags+=(-mavx512f) ;;
    esac
    for kernel in fem/kernels/tet_kernel fem/kernels/vertex_kernel solver/kernels/bsr_kernel; do
      name=$(basename "$kernel")
      compile "src/$kernel.c" "$dir/${name}_$variant.o" "${flags[@]}"
      objects+=("$dir/${name}_$variant.o")
    done
  done
  for source in tests/main.c tests/support.c "${suites[@]/#/tests/test_}"; do
    source=${source%.c}.c
    name=$(basename "$source" .c)
    compile "$source" "$dir/test_$name.o" "${test_flags[@]}"
    objects+=("$dir/test_$name.o")
  done
  for pid in "${pids[@]}"; do wait "$pid"; done
  pids=()
  "$cc" "${objects[@]}" "${link[@]}" -o "$exe"
}

# run target: every suite of $suites must pass every test; prints the golden hashes.
run() {
  local dir=$out/$1 suite status
  for suite in "${suites[@]}"; do
    status=0
    "${runner[@]}" "$exe" "$suite" >"$dir/$suite.txt" 2>&1 || status=$?
    if [ "$status" -ne 0 ] || ! grep -q '^[1-9][0-9]* passed, 0 failed$' "$dir/$suite.txt"; then
      grep -v '^ok ' "$dir/$suite.txt" | tail -n 40
      echo "check-determinism: $1: the $suite suite failed (exit $status; $dir/$suite.txt)" >&2
      exit 1
    fi
    echo "check-determinism: $1: $suite: $(tail -n 1 "$dir/$suite.txt")"
  done
  grep '^  golden ' "$dir/determinism.txt" | sed "s/^  /check-determinism: $1: /"
}

# control: the contracted build must fail both golden hashes, each with a hash (not a crash).
control() {
  local dir=$out/$1 test status
  for test in golden_hash_explicit golden_hash_implicit; do
    status=0
    "${runner[@]}" "$exe" determinism "$test" >"$dir/$test.txt" 2>&1 || status=$?
    if [ "$status" -ne 1 ] || ! grep -qE "^FAIL determinism.$test \([0-9.]+ s\)$" "$dir/$test.txt" ||
       ! grep -q 'hashes to 0x[0-9a-f]*ull, expected' "$dir/$test.txt"; then
      cat "$dir/$test.txt"
      echo "check-determinism: $1: with FMA contraction $test did not fail on its hash" \
        "(exit $status): the golden hashes would not see contraction" >&2
      exit 1
    fi
    grep '^  golden ' "$dir/$test.txt" | sed "s/^  /check-determinism: $1: (other bits, as it must) /"
  done
}

# --- build and run each -------------------------------------------------------------------------
ran=() skipped=()
for target in "${targets[@]}"; do
  lacks=$(missing "$target")
  if [ -n "$lacks" ]; then
    if [ "${CI:-}" = true ]; then
      echo "check-determinism: $target: ${lacks% *} not found (Debian package ${lacks#* });" \
        "under CI=true every target must run (bash scripts/install-deps.sh)" >&2
      exit 1
    fi
    echo "check-determinism: $target SKIPPED: ${lacks% *} not found (apt-get install" \
      "${lacks#* }; bash scripts/install-deps.sh installs every target's tools)"
    skipped+=("$target")
    continue
  fi
  target_start=$(date +%s)
  configure "$target"
  build "$target"
  if [ "$target" = fma-control ]; then
    control "$target"
  else
    run "$target"
    ran+=("$target")
  fi
  echo "check-determinism: $target passed ($(($(date +%s) - target_start)) s)"
done

# Every target passed the golden hashes and the suite's control, so their printed hashes (8: two
# scenes, two integrators, one and two workers) are equal; checked again here, so that a suite
# that stopped checking or printing them is seen too.
reference=""
for target in "${ran[@]}"; do
  for test in golden_hash_explicit golden_hash_implicit golden_hash_mixed_scene \
    golden_hash_tells_a_changed_run_apart; do
    if ! grep -qE "^ok   determinism.$test \([0-9.]+ s\)$" "$out/$target/determinism.txt"; then
      echo "check-determinism: $target: determinism.$test did not run and pass" >&2
      exit 1
    fi
  done
  hashes=$(grep '^  golden .*: 0x[0-9a-f]\{16\}$' "$out/$target/determinism.txt" || true)
  count=$(printf '%s\n' "$hashes" | grep -c 0x || true)
  if [ "$count" -ne 8 ]; then
    echo "check-determinism: $target printed $count golden hashes, not 8" >&2
    exit 1
  fi
  if [ -z "$reference" ]; then
    reference=$hashes
  elif [ "$hashes" != "$reference" ]; then
    echo "check-determinism: $target's hashes differ from ${ran[0]}'s" >&2
    exit 1
  fi
done
took=$(($(date +%s) - start))
if [ ${#ran[@]} -eq 0 ]; then
  echo "check-determinism: SKIPPED: ${skipped[*]}; nothing compared ($took s)"
elif [ ${#skipped[@]} -gt 0 ]; then
  echo "check-determinism: the same bits on ${ran[*]}; SKIPPED: ${skipped[*]} ($took s)"
else
  echo "check-determinism: the same bits on ${ran[*]} ($took s)"
fi
