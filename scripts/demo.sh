#!/usr/bin/env bash
# Build femto and run the bouncy house demo: 10 s of the GAMES103 house falling on the floor,
# with a jump at 4 s. The VTK series lands in out/house (open house.pvd in ParaView).
# Extra arguments go to `femto run` (e.g. --obj, --frames 100, scenes/drop.json).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
# A build folder of its own: the demo's options (Release, no tests) never meet the test build's
# cache in build/ (scripts/test.sh), whichever runs first.
cmake -S . -B build-demo -DCMAKE_BUILD_TYPE=Release -DFEMTO_BUILD_TESTS=OFF
cmake --build build-demo -j"$(nproc 2>/dev/null || echo 2)" --target femto
out=out/house
# femto removes the frames an earlier, longer run of the same series left in $out.
build-demo/cli/femto run --seconds 10 --impulse-at 4 --out "$out" "$@"
echo
for pvd in "$out"/*.pvd; do
  echo "femto demo: the VTK series is in $(pwd)/$out; open $pvd in ParaView"
done
echo "(File > Open, Apply, then press play; colour by 'velocity')."
