#!/usr/bin/env bash
# Install the Debian packages femto's tools and tests need (the core library needs none): the
# CLI's cJSON, the viewer's renderer and window (EGL, epoxy, GL, giflib, libspng, GLFW, Dear
# ImGui, Mesa's software driver) and xvfb for its window tests (docs/viewer.md), then
# the optional ones `femto bench` and the mesh format tests use when they are there: tetgen (the
# TetGen beams, meshing a cube), gmsh (meshing a cube in every format it writes; about 40 s and
# 170 MB with its OpenCASCADE libraries, --no-install-recommends), python3-meshio (.vtu and .vtk
# files as Python tools write them; about 30 s with numpy), gnuplot-nox (the PNG plot) and
# libbullet-dev (bench/peers/, Bullet's deformable world side by side). zlib1g-dev lets the
# library read compressed .vtu files. The build and the tests never need the optional packages
# (tests that use them say they skipped); failing to install them is a warning, and
# FEMTO_BENCH_DEPS=0 leaves them out.
set -euo pipefail
packages=(build-essential cmake pkg-config libcjson-dev zlib1g-dev clang libclang-rt-14-dev valgrind
  libepoxy-dev libegl-dev libgl-dev libgif-dev libspng-dev libglfw3-dev libimgui-dev
  libegl-mesa0 libgl1-mesa-dri xvfb xauth)
optional=(tetgen gmsh python3-meshio gnuplot-nox libbullet-dev)
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
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends \
    "${missing_optional[@]}" ||
    echo "install-deps.sh: warning: the optional bench packages (${missing_optional[*]}) did not install; femto bench skips what needs them" >&2
fi
