#!/usr/bin/env bash
# Build femto for the browser (docs/web.md): libfemto's sources and web/femto_web.c compiled to
# WebAssembly with Debian's emscripten (installed here when missing), into web/dist/ (the page's
# modules: femto_wasm.js + .wasm with WebAssembly SIMD, femto_wasm_nosimd.js + .wasm without,
# and the files the page fetches: the menu's scenes/*.json and the house's data/house2.node and
# .ele) and build-web/node/ (both for Node.js, for the comparison test). Prints the .wasm
# sizes and fails when one reaches 512 KiB.
#
#   bash scripts/web.sh            # build
#   bash scripts/web.sh --serve    # build, then serve web/ on http://localhost:8000 (PORT=...)
set -euo pipefail
cd "$(dirname "$0")/.."

serve=false
for arg in "$@"; do
  case "$arg" in
    --serve) serve=true ;;
    -h | --help) sed -n '2,10p' "$0"; exit 0 ;;
    *) echo "web.sh: unknown option $arg (use --serve)" >&2; exit 2 ;;
  esac
done

# --- emscripten ------------------------------------------------------------------------------
if ! command -v emcc >/dev/null; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    echo "web.sh: installing emscripten (apt-get)"
    DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends emscripten >/dev/null \
      || { DEBIAN_FRONTEND=noninteractive apt-get update >/dev/null &&
           DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends emscripten >/dev/null; }
  fi
  if ! command -v emcc >/dev/null; then
    echo "web.sh: emcc not found and cannot be installed (apt-get install emscripten)" >&2
    exit 1
  fi
fi
# Debian's emcc 3.1.6 finds its acorn module only there when Node.js is not Debian's own.
export NODE_PATH="/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}"

out=build-web
obj=$out/obj
dist=web/dist
mkdir -p "$obj" "$dist" "$out/node"

# --- compile ---------------------------------------------------------------------------------
# As the native build: C11, warnings are errors, no FMA contraction (docs/determinism.md), never
# -ffast-math. -O2: measured 2.5 to 7 times faster than -Os (the house 0.5 against 1.3 ms a
# frame, its Mooney-Rivlin twin 1.2 against 8.6 ms) for 25 KiB more; the kernels -O3 as natively.
warnings=(-Wall -Wextra -Werror -Wshadow -Wstrict-prototypes -Wvla)
cflags=(-std=c11 -flto -Iinclude -Isrc -Icli -ffp-contract=off "${warnings[@]}")

# The files the page fetches and gives the glue (fw_set_file), at their repository paths under
# web/dist/: the menu's scenes, the scenes/*.json files that web/femto_web.c's FW_SCENES lists,
# and the mesh of "builtin:house2" (its FW_HOUSE_NODE and FW_HOUSE_ELE).
rm -rf "$dist/scenes" "$dist/data"
mkdir -p "$dist/scenes" "$dist/data"
for scene in $(sed -n 's/^\s*X("[^"]*", \([a-z0-9_]*\)).*/\1/p' web/femto_web.c); do
  cp "scenes/$scene.json" "$dist/scenes/"
done
for file in $(sed -n 's/^#define FW_HOUSE_[A-Z]* "\(data\/[^"]*\)"$/\1/p' web/femto_web.c); do
  cp "$file" "$dist/data/"
done

# newest FILE... prints the most recently modified file (a loop, no pipe: under pipefail a
# reader that leaves early would end the script with SIGPIPE).
newest() {
  local best=$1 file
  for file in "$@"; do
    if [ "$file" -nt "$best" ]; then best=$file; fi
  done
  echo "$best"
}

# Each object is rebuilt when its source or any header is newer (a tiny make).
newest_header=$(newest include/femto/*.h src/*/*.h src/*/*/*.h cli/*.h)
jobs=()
compile() { # source object flags...
  local source=$1 object=$2
  shift 2
  if [ ! -f "$object" ] || [ "$source" -nt "$object" ] || [ "$newest_header" -nt "$object" ] ||
     [ "$0" -nt "$object" ]; then
    echo "emcc $source"
    emcc -c "${cflags[@]}" "$@" "$source" -o "$object" &
    jobs+=($!)
    if [ "${#jobs[@]}" -ge "$(nproc 2>/dev/null || echo 2)" ]; then
      wait "${jobs[0]}"
      jobs=("${jobs[@]:1}")
    fi
  fi
}
objects=()
# The scene schema is the tool's (cli/): its JSON tree (filled by JSON.parse here), checking kit
# and schema, and the helpers they call (objects named cli_*).
scene_sources=(cli/json_tree.c cli/json_check.c cli/json_locate.c cli/scene.c cli/scene_body.c
  cli/util.c)
for source in src/*/*.c "${scene_sources[@]}" web/femto_web.c; do
  name=$(basename "$source" .c)
  posix=()
  case "$source" in cli/*) name=cli_$name posix=(-D_POSIX_C_SOURCE=200809L) ;; esac
  # The mesh readers and checks, the contact audit, the snapshots and the world's and bodies'
  # settings and defs run once a load or a call, not once a step: -Oz. The glue, the frame's
  # orchestration and the two integrators' stages (their per-element work is in the kernels),
  # the islands, the core's diagnostics, the debug draw, the contact stage's orchestration, its
  # buffers, bookkeeping and mid phase (body_sweep, contact_detect) and the stability limit run
  # once a frame, substep or body, never per element, and the solvers and loads the page's
  # scenes do not run per element (multigrid, static solves, VBD, loads, the collider broad
  # phase, targets) and the SVD-frame projection (material_stretch: since the tangents without
  # an SVD, only corotated and Mooney-Rivlin implicit bodies use it per element): -Os (the .wasm
  # line: 524,059 bytes of 524,288 on 2026-12-07, with issue 33's attachments; then issue 34's
  # anisotropic materials, material_aniso -Oz (no page scene uses them), the link's -Os below,
  # and the Newton iterations' orchestration, the energy ledger, the snapshots' stream and
  # checksum, the friction anchors and penalty contacts (per contact or iteration, never per
  # element) -Os: 521,421 bytes, the page's frames unchanged in Node.js; then the plasticity
  # (material_plastic -Oz, the body's flow -Os: no page scene is plastic) and the snapshots' body
  # record (-Oz) with emmalloc below: 517,480; the nodal pressure -Oz (no page scene uses it);
  # then fracture (fracture, tear_topology -Oz: no page scene tears): 519,382, against 524,130
  # with them at -O2;
  # for some files,
  # e.g. query.c, schedule.c, grab.c, render_mesh.c, contact_events.c, embedded.c, -Os gives
  # more code, so they stay -O2).
  case "$name" in
    mesh | mesh_* | reorder | text_reader | scanner | surface_mesh | audit | snapshot | \
      body_def | world | material_aniso | material_plastic | snapshot_body | nodal_pressure | \
      fracture | tear_topology) level=-Oz ;;
    island | body | step | core | draw | body_sweep | contact_detect | \
      contact_state | stability | contact | contact_ledger | femto_web | multigrid | static | \
      vbd | loads | broad_phase | targets | material_stretch | implicit | explicit | newton | \
      energy_ledger | snapshot_stream | checksum | friction_anchor | penalty | plasticity) level=-Os ;;
    cli_*) level=-Oz ;;
    *) level=-O2 ;;
  esac
  compile "$source" "$obj/$name.o" "$level" "${posix[@]}"
  objects+=("$obj/$name.o")
done
# The element and sparse-row kernels, as natively (CMakeLists.txt), in the vector variant and the
# plain-C one (fmWorldDef.simd = fm_simdScalar) -- twice: with WebAssembly SIMD (-msimd128: the
# 16-lane vectors become v128 instructions, 2.4 times faster on the house; every current desktop
# browser has them) and without, for browsers without SIMD (the page picks). Without SIMD the
# vector variant is the plain-C one under its name (-DFM_SIMD_SCALAR): its 16-lane vectors
# lowered to scalars took 104 KiB of the .wasm's code against the plain-C kernel's 40, and the
# variants agree bit for bit (check-web.sh compares the builds' coordinates). Only the kernels
# pay for SIMD (measured: the rest built with -msimd128 is no faster), so the rest is built once.
for variant in simd plain; do
  flags=(-msimd128)
  [ "$variant" = plain ] && flags=(-DFM_SIMD_SCALAR)
  for kernel in fem/kernels/tet_kernel fem/kernels/vertex_kernel solver/kernels/bsr_kernel; do
    name=$(basename "$kernel")
    compile "src/$kernel.c" "$obj/${name}_baseline_$variant.o" -O3 -Wno-psabi \
      -fno-math-errno "${flags[@]}" -DFM_KERNEL_VARIANT=baseline
    compile "src/$kernel.c" "$obj/${name}_scalar_$variant.o" -O3 -fno-math-errno \
      "${flags[@]}" -DFM_KERNEL_VARIANT=scalar -DFM_SIMD_SCALAR
  done
done
for job in "${jobs[@]}"; do wait "$job"; done
simd_objects=("${objects[@]}")
plain_objects=("${objects[@]}")
for kernel in tet_kernel vertex_kernel bsr_kernel; do
  simd_objects+=("$obj/${kernel}_baseline_simd.o" "$obj/${kernel}_scalar_simd.o")
  plain_objects+=("$obj/${kernel}_baseline_plain.o" "$obj/${kernel}_scalar_plain.o")
done

# --- link ------------------------------------------------------------------------------------
# Only what the page calls is exported; no file system, no exceptions, memory that grows. The
# link's binaryen pass at -Os (the objects keep their own levels above): 10.5 KB smaller than -O2
# with issue 34's anisotropic materials in (520,290 against 530,850 bytes), the page's first
# two scenes' frames in Node.js the same within the host's noise (best of three runs' medians,
# -O2 then -Os: 0.585, 0.568 ms explicit, 7.4, 7.7 ms implicit); -Oz saves 4.6 KB more but
# measured 5-15% slower frames. emmalloc for malloc (-sMALLOC=emmalloc): about 8 KB smaller than
# dlmalloc with issue 34's plasticity in (517,480 against 525,443 bytes); femto allocates nothing
# in a frame at rest (the house, 60 frames, both integrators), and the page's first two scenes'
# frames in Node.js, best of six interleaved runs, dlmalloc then emmalloc: explicit 0.539, 0.538
# and 0.477, 0.489 ms, implicit 6.91, 7.17 and 3.43, 3.73 ms (0-9%, within the host's spread of
# 0.54-0.95 ms a run). Link-time optimisation (-flto, compile and link: the objects are LLVM
# bitcode, each function keeps its file's level, the link optimises across files and drops
# what the page cannot reach): 504,152 bytes against 526,341 with issue 34's nodal pressure in
# (which took the plain build past 512 KiB), the page's house explicit and implicit in Node.js,
# medians of 120 and 60 frames, three interleaved runs each, without then with: explicit 0.614,
# 0.787, 0.972 and 0.607, 0.809, 0.535 ms, implicit 2.67, 3.29, 3.29 and 3.13, 3.69, 2.54 ms
# (within the host's spread); check-web's comparisons still ask for native's bits.
exports=$(grep -o 'FW_EXPORT [^(]*(' web/femto_web.c | grep -o 'fw_[a-z_]*' | sed 's/^/_/' |
  sort -u | paste -sd, -)
link=(-Os -flto --no-entry -sMODULARIZE=1 -sFILESYSTEM=0 -sALLOW_MEMORY_GROWTH=1 -sMALLOC=emmalloc
      -sDISABLE_EXCEPTION_CATCHING=1 -sEXPORTED_FUNCTIONS="$exports"
      -sEXPORTED_RUNTIME_METHODS=UTF8ToString,HEAPU8,HEAP32,HEAPF32,HEAPF64)
web=(-sEXPORT_ES6=1 -sENVIRONMENT=web -sEXPORT_NAME=createFemto)
# The same objects for Node.js (a CommonJS module) for the comparison test (web/test/). One file,
# the .wasm inside: emscripten 3.1.6's glue would fetch() a .wasm path under Node 18 and later.
node=(-sENVIRONMENT=node -sEXPORT_NAME=createFemto -sSINGLE_FILE=1)
# The links (each optimises the whole page: some 14 s) run unless every output is newer than
# every object and this script: the tiny make's last step.
linked=("$dist/femto_wasm.js" "$dist/femto_wasm.wasm" "$dist/femto_wasm_nosimd.js"
        "$dist/femto_wasm_nosimd.wasm" "$out/node/femto_wasm.js" "$out/node/femto_wasm_nosimd.js")
newest_object=$(newest "${simd_objects[@]}" "${plain_objects[@]}")
stale=false
for file in "${linked[@]}"; do
  if [ ! -f "$file" ] || [ "$newest_object" -nt "$file" ] || [ "$0" -nt "$file" ]; then
    stale=true
  fi
done
if $stale; then
  emcc "${simd_objects[@]}" "${link[@]}" "${web[@]}" -o "$dist/femto_wasm.js"
  emcc "${plain_objects[@]}" "${link[@]}" "${web[@]}" -o "$dist/femto_wasm_nosimd.js"
  emcc "${simd_objects[@]}" "${link[@]}" "${node[@]}" -o "$out/node/femto_wasm.js"
  emcc "${plain_objects[@]}" "${link[@]}" "${node[@]}" -o "$out/node/femto_wasm_nosimd.js"
else
  echo "web.sh: the modules are newer than every object: not linked again"
fi

for wasm in "$dist/femto_wasm.wasm" "$dist/femto_wasm_nosimd.wasm"; do
  size=$(stat -c %s "$wasm")
  echo "web.sh: $wasm is $size bytes ($((size / 1024)) KiB, limit 512 KiB)"
  if [ "$size" -ge $((512 * 1024)) ]; then
    echo "web.sh: $wasm is over 512 KiB" >&2
    exit 1
  fi
done

if $serve; then
  port=${PORT:-8000}
  echo "web.sh: serving web/ on http://localhost:$port/ (Ctrl-C stops)"
  exec python3 -m http.server "$port" --directory web
fi
