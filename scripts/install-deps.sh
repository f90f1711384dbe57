#!/usr/bin/env bash
# Install the Debian packages femto's tools and tests need (the core library needs none).
#   packages: the CLI's cJSON, the viewer's renderer and window (EGL, epoxy, GL, giflib, libspng,
#     GLFW, Dear ImGui, Mesa's software driver), xvfb for its window tests (docs/viewer.md), clang
#     and its runtime for the fuzzers, valgrind; zlib1g-dev lets the library read compressed .vtu.
#   test tools: what the suite runs beside femto to check it (each is a test that fails under
#     CI=true when its tool is missing, and says it skipped otherwise): tetgen and gmsh (meshing,
#     `femto bench`'s beams; gmsh is about 170 MB with OpenCASCADE, --no-install-recommends),
#     python3-meshio (.vtu/.vtk as Python tools write them), gnuplot-nox (the bench plot),
#     libbullet-dev (bench/peers/), calculix-ccx (the reference solver the static tests compare
#     with), qemu-user + gcc-aarch64-linux-gnu and musl-tools (the determinism suite on AArch64
#     and against musl), emscripten, nodejs with node-ws (a WebSocket client for Node.js older
#     than 22) and chromium (the browser build and its page), abigail-tools (abidw and abidiff:
#     the public ABI against abi/libfemto.abi), and the Python package's build and tests
#     (python3-venv, -dev, -numpy, -cffi, -setuptools, -wheel, -pytest, -matplotlib, -dask,
#     -distributed: python/).
# Failing to install a test tool is a warning, or an error under CI=true (the suite would fail on
# it anyway, later and less clearly). FEMTO_BENCH_DEPS=0 leaves the test tools out (a quick
# library-and-CLI build; scripts/demo.sh needs none of them).
set -euo pipefail
packages=(build-essential cmake pkg-config libcjson-dev zlib1g-dev clang libclang-rt-14-dev valgrind
  libepoxy-dev libegl-dev libgl-dev libgif-dev libspng-dev libglfw3-dev libimgui-dev
  libegl-mesa0 libgl1-mesa-dri xvfb xauth)
optional=(tetgen gmsh python3-meshio gnuplot-nox libbullet-dev calculix-ccx qemu-user
  gcc-aarch64-linux-gnu libc6-dev-arm64-cross musl-tools emscripten node-ws chromium abigail-tools
  python3-venv python3-dev python3-numpy python3-cffi python3-setuptools python3-wheel
  python3-pytest python3-matplotlib python3-dask python3-distributed)
command -v node >/dev/null || optional+=(nodejs)
[ "${FEMTO_BENCH_DEPS:-1}" = 0 ] && optional=()
missing=()
for p in "${packages[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
missing_optional=()
for p in "${optional[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing_optional+=("$p")
done
SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
if [ ${#missing[@]} -gt 0 ] || [ ${#missing_optional[@]} -gt 0 ]; then
  $SUDO apt-get update -qq
fi
if [ ${#missing[@]} -gt 0 ]; then
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}"
fi
if [ ${#missing_optional[@]} -gt 0 ]; then
  if ! DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends \
    "${missing_optional[@]}"; then
    if [ "${CI:-}" = true ]; then
      echo "install-deps.sh: error: the test tools (${missing_optional[*]}) did not install; under CI=true every test must run" >&2
      exit 1
    fi
    echo "install-deps.sh: warning: the test tools (${missing_optional[*]}) did not install; the tests that need them say they skipped" >&2
  fi
fi
