#!/usr/bin/env bash
# Make docs/house.gif, the README's picture: the bouncy house falling onto the floor and the
# seeds' jump at 2 s, drawn headless (EGL, no window or display needed) by `femto run --gif`.
# 320x240, 4 s at 25 pictures a second: about 100 frames. Extra arguments go to `femto run`.
set -euo pipefail
cd "$(dirname "$0")/.."
# The demo's build folder (scripts/demo.sh): Release, no tests.
cmake -S . -B build-demo -DCMAKE_BUILD_TYPE=Release -DFEMTO_BUILD_TESTS=OFF >/dev/null
cmake --build build-demo -j"$(nproc 2>/dev/null || echo 2)" --target femto
build-demo/cli/femto run --seconds 4 --impulse-at 2 --quiet --size 320x240 --fps 25 \
  --camera-yaw 35 --camera-pitch 18 --gif docs/house.gif "$@"
ls -l docs/house.gif
