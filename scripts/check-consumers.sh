#!/usr/bin/env bash
# femto used from outside, the three ways a project takes it (tests/consumers/): installed with
# `cmake --install` to a scratch prefix and found with find_package (static and shared) and with
# pkg-config; and its source tree added with add_subdirectory, where it must build only its
# library. Each consumer builds and runs tests/consumers/consumer.c (a box that must fall). The
# installed tree is checked too: headers, libfemto.a, the versioned libfemto.so, the femto tool
# (when the build has it), the CMake package and femto.pc.
# Installs from build/ when scripts/test.sh has built it (nothing is rebuilt), else from a
# library-only build in build-consumers/femto. About 30 s on 2 cores (the add_subdirectory route
# compiles the static library once more).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
work=$root/build-consumers
jobs=$(nproc 2>/dev/null || echo 2)
rm -rf "$work/prefix" "$work/find_package" "$work/pkg_config" "$work/add_subdirectory"
mkdir -p "$work"

say() { echo "check-consumers: $*"; }
fail() { echo "check-consumers: FAILED: $*" >&2; exit 1; }

# 1. Install.
if [ -f build/CMakeCache.txt ] && grep -q '^FEMTO_INSTALL:BOOL=ON' build/CMakeCache.txt; then
  from=build
  cmake --build build -j"$jobs" >/dev/null
else
  from=$work/femto
  cmake -S . -B "$from" -DCMAKE_BUILD_TYPE=Release -DFEMTO_BUILD_CLI=OFF -DFEMTO_BUILD_TESTS=OFF \
    -DFEMTO_BUILD_EXAMPLES=OFF -DFEMTO_BUILD_VIEWER=OFF -DFEMTO_INSTALL=ON >/dev/null
  cmake --build "$from" -j"$jobs" >/dev/null
fi
prefix=$work/prefix
cmake --install "$from" --prefix "$prefix" >/dev/null
say "installed from $from into $prefix"
for f in include/femto/femto.h include/femto/mesh.h include/femto/types.h include/femto/base.h \
  include/femto/fm_math.h lib/libfemto.a lib/libfemto.so lib/cmake/femto/femtoConfig.cmake \
  lib/cmake/femto/femtoConfigVersion.cmake lib/cmake/femto/femtoTargets.cmake \
  lib/pkgconfig/femto.pc; do
  [ -e "$prefix/$f" ] || fail "cmake --install did not install $f"
done
version=$(sed -n 's/^project(femto VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
soname=$(objdump -p "$prefix/lib/libfemto.so" | awk '/SONAME/ {print $2}')
[ "$soname" = "libfemto.so.${version%.*}" ] || fail "soname $soname, expected libfemto.so.${version%.*}"
[ -e "$prefix/lib/libfemto.so.$version" ] || fail "no libfemto.so.$version"
if grep -q '^FEMTO_BUILD_CLI:BOOL=ON' "$from/CMakeCache.txt"; then
  [ -x "$prefix/bin/femto" ] || fail "the femto tool was built but not installed"
  "$prefix/bin/femto" --version | grep "femto $version" >/dev/null || fail "bin/femto --version"
fi

# 2. find_package, static (femto::femto) and shared (femto::femto_shared).
cmake -S tests/consumers/find_package -B "$work/find_package" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/find_package" -j"$jobs" >/dev/null
"$work/find_package/consumer" || fail "find_package consumer (static)"
"$work/find_package/consumer_shared" || fail "find_package consumer (shared)"
ldd "$work/find_package/consumer_shared" | grep "$prefix/lib/libfemto.so" >/dev/null ||
  fail "consumer_shared does not load the installed libfemto.so"

# 3. pkg-config (shared library, rpath to its libdir).
mkdir -p "$work/pkg_config"
PKG_CONFIG_PATH=$prefix/lib/pkgconfig make -s -C "$work/pkg_config" \
  -f "$root/tests/consumers/pkg_config/Makefile" SRC="$root/tests/consumers/consumer.c"
"$work/pkg_config/consumer" || fail "pkg-config consumer"
PKG_CONFIG_PATH=$prefix/lib/pkgconfig pkg-config --static --libs femto >/dev/null ||
  fail "pkg-config --static --libs femto"

# 4. add_subdirectory: only the library is built (the consumer's CMakeLists fails on a tool,
# test or example target), from a tree without cJSON or the viewer's packages needed.
cmake -S tests/consumers/add_subdirectory -B "$work/add_subdirectory" -DFEMTO_SOURCE_DIR="$root" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/add_subdirectory" -j"$jobs" >/dev/null
"$work/add_subdirectory/consumer" || fail "add_subdirectory consumer"
say "find_package, pkg-config and add_subdirectory consumers built and ran"
