#!/usr/bin/env bash
# Build femto and run the bouncy house demo; the VTK series lands in out/house (open house.pvd
# in ParaView). Extra arguments go to `femto run`.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DFEMTO_BUILD_TESTS=OFF
cmake --build build -j"$(nproc 2>/dev/null || echo 2)" --target femto
build/cli/femto run --seconds 10 --out out/house "$@"
