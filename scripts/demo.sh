#!/usr/bin/env bash
# Build femto and run the bouncy house demo: 10 s of the GAMES103 house falling on the floor,
# with a jump at 4 s. The VTK series lands in out/house (open house.pvd in ParaView).
# Extra arguments go to `femto run` (e.g. --obj, scenes/drop.json). FEMTO_DEMO_OUT (default
# out/house) and FEMTO_DEMO_SECONDS (default 10) change where and how long: scripts/check-commands.sh
# runs this script with a short run into a temporary folder.
set -euo pipefail
cd "$(dirname "$0")/.."
# The demo needs the build and viewer packages only, not the tools the test suite runs beside femto.
FEMTO_BENCH_DEPS=0 bash scripts/install-deps.sh
# A build folder of its own: the demo's options (Release, no tests) never meet the test build's
# cache in build/ (scripts/test.sh), whichever runs first.
cmake -S . -B build-demo -DCMAKE_BUILD_TYPE=Release -DFEMTO_BUILD_TESTS=OFF
cmake --build build-demo -j"$(nproc 2>/dev/null || echo 2)" --target femto_cli
out=${FEMTO_DEMO_OUT:-out/house}
seconds=${FEMTO_DEMO_SECONDS:-10}
# femto removes the frames an earlier, longer run of the same series left in $out.
build-demo/cli/femto run --seconds "$seconds" --impulse-at 4 --out "$out" "$@"
echo
for pvd in "$out"/*.pvd; do
  echo "femto demo: the VTK series is in $out; open $pvd in ParaView"
done
echo "(File > Open, Apply, then press play; colour by 'velocity')."
