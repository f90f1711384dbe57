#!/usr/bin/env bash
# Every command README.md and docs/*.md show in their ```sh blocks, run as written, so that none
# of them can break silently (scripts/test.sh runs this after the suites have built build/).
#
# The commands are read from the documents themselves (comments after a `#` dropped, lines
# ending in `\` joined) and each must have a way to run in the table below: a command the docs
# show that the table lacks fails this check, and so does a table entry the docs no longer show.
# Each runs in a scratch folder under build-commands/ that holds what the docs assume is there
# (scenes/ and data/ as in the tree, a cube.msh, a bunny.stl/.off: a 0.1 m ball, the bunny.geo
# the docs print), with build/cli first on PATH for `femto`. What differs from the text, and why:
#   - scripts/demo.sh: a 4.5 s run into build-commands/ (FEMTO_DEMO_OUT, FEMTO_DEMO_SECONDS);
#   - `femto view` (interactive): under xvfb-run with --script viewer/tests/drag.txt --frames 90
#     --screenshot appended: a drag, a jump and a slider, then it quits;
#   - `scripts/web.sh --serve` (a server): under a timeout on a free PORT, until the page answers;
#   - the build, install and consumer lines: in a copy of the tree (build/ and docs/ of the
#     checkout are the suite's), the install prefix /opt/femto replaced by a scratch prefix;
#     each ```cmake block becomes a game's CMakeLists.txt (after its add_executable), built
#     against that prefix or with the copy as third_party/femto, and run;
#   - docs/performance.md: its build lines in the checkout (build/ is already that build), its
#     `femto bench` in the copy (it writes docs/), with --quick --max-tets 1500 --repeats 1
#     appended (the full run takes an hour); the libFuzzer run of docs/robustness.md: 10 s, not 3600 s;
#   - scripts/test.sh and scripts/check-web.sh: this check is part of the first, which runs the
#     second itself, and the quick paths `ctest --test-dir build -j2` and the short
#     check-fuzz.sh, which test.sh runs in full.
# Under CI=true a missing tool (xvfb-run, gmsh, tetgen, emcc, clang) fails the check; elsewhere
# the commands that need it are reported skipped.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
work=$root/build-commands
jobs=$(nproc 2>/dev/null || echo 2)
rm -rf "$work"
mkdir -p "$work/here" "$work/logs"
start=$(date +%s)

say() { echo "check-commands: $*"; }
fail() { echo "check-commands: FAILED: $*" >&2; exit 1; }
skipped=()
need() { # program: true when it is on PATH; else a failure under CI=true, a skip elsewhere
  command -v "$1" >/dev/null 2>&1 && return 0
  [ "${CI:-}" = true ] && fail "CI=true and $1 is missing: '$current' is not tested"
  skipped+=("$current (no $1)")
  return 1
}
[ -x build/cli/femto ] || fail "build/cli/femto is not built (scripts/test.sh builds it first)"

# --- the commands the documents show ----------------------------------------------------------
shown=$work/shown.txt
for doc in README.md docs/*.md; do
  awk -v doc="$doc" '
    /^```(sh|bash)[[:space:]]*$/ { inside = 1; next }
    /^```/ { inside = 0; next }
    inside {
      line = $0
      sub(/[[:space:]]+#.*$/, "", line); sub(/^#.*$/, "", line)
      sub(/^[[:space:]]+/, "", line); sub(/[[:space:]]+$/, "", line)
      if (line == "") next
      if (line ~ /\\$/) { sub(/[[:space:]]*\\$/, " ", line); pending = pending line; next }
      print doc "\t" pending line; pending = ""
    }' "$doc"
done >"$shown"

# --- the scratch folder: what the commands expect to find --------------------------------------
here=$work/here
ln -s "$root/scenes" "$here/scenes"
ln -s "$root/data" "$here/data"
cp tests/data/mesh/cube_gmsh41.msh "$here/cube.msh"
# The bunny: a ball of radius 0.1 m (an icosahedron subdivided twice, 320 triangles) as STL and OFF.
awk 'BEGIN {
  t = (1 + sqrt(5)) / 2; n = 0
  split("-1 t 0 1 t 0 -1 -t 0 1 -t 0 0 -1 t 0 1 t 0 -1 -t 0 1 -t t 0 -1 t 0 1 -t 0 -1 -t 0 1", c, " ")
  for (i = 0; i < 12; ++i) for (k = 0; k < 3; ++k) { v = c[3 * i + k + 1]; P[i, k] = v == "t" ? t : v == "-t" ? -t : v + 0 }
  nv = 12
  split("0 11 5 0 5 1 0 1 7 0 7 10 0 10 11 1 5 9 5 11 4 11 10 2 10 7 6 7 1 8 3 9 4 3 4 2 3 2 6 3 6 8 3 8 9 4 9 5 2 4 11 6 2 10 8 6 7 9 8 1", f, " ")
  nf = 20; for (i = 0; i < 60; ++i) F[int(i / 3), i % 3] = f[i + 1]
  for (level = 0; level < 2; ++level) {
    delete mid; m = 0
    for (i = 0; i < nf; ++i) {
      for (e = 0; e < 3; ++e) {
        a = F[i, e]; b = F[i, (e + 1) % 3]; key = a < b ? a " " b : b " " a
        if (!(key in mid)) { for (k = 0; k < 3; ++k) P[nv, k] = (P[a, k] + P[b, k]) / 2; mid[key] = nv++ }
        E[e] = mid[key]
      }
      a = F[i, 0]; b = F[i, 1]; c2 = F[i, 2]
      G[m, 0] = a; G[m, 1] = E[0]; G[m, 2] = E[2]; ++m
      G[m, 0] = b; G[m, 1] = E[1]; G[m, 2] = E[0]; ++m
      G[m, 0] = c2; G[m, 1] = E[2]; G[m, 2] = E[1]; ++m
      G[m, 0] = E[0]; G[m, 1] = E[1]; G[m, 2] = E[2]; ++m
    }
    nf = m; for (i = 0; i < nf; ++i) for (k = 0; k < 3; ++k) F[i, k] = G[i, k]
  }
  for (i = 0; i < nv; ++i) { r = sqrt(P[i, 0] ^ 2 + P[i, 1] ^ 2 + P[i, 2] ^ 2); for (k = 0; k < 3; ++k) P[i, k] *= 0.1 / r }
  off = "bunny.off"; stl = "bunny.stl"
  printf "OFF\n%d %d 0\n", nv, nf > off
  for (i = 0; i < nv; ++i) printf "%.9f %.9f %.9f\n", P[i, 0], P[i, 1], P[i, 2] > off
  for (i = 0; i < nf; ++i) printf "3 %d %d %d\n", F[i, 0], F[i, 1], F[i, 2] > off
  print "solid bunny" > stl
  for (i = 0; i < nf; ++i) {
    print "facet normal 0 0 0\nouter loop" > stl
    for (k = 0; k < 3; ++k) printf "vertex %.9f %.9f %.9f\n", P[F[i, k], 0], P[F[i, k], 1], P[F[i, k], 2] > stl
    print "endloop\nendfacet" > stl
  }
  print "endsolid bunny" > stl
}' </dev/null
mv bunny.off bunny.stl "$here/"
# bunny.geo: the Gmsh script docs/meshes.md prints (its first plain block that merges bunny.stl).
awk '/^```/ { if (inside && keep) exit; inside = !inside; next }
     inside && /Merge "bunny.stl"/ { keep = 1 }
     inside && keep { print }' docs/meshes.md >"$here/bunny.geo"
grep -q 'Merge "bunny.stl"' "$here/bunny.geo" || fail "docs/meshes.md no longer shows the bunny.geo script"

# --- how each command runs ----------------------------------------------------------------------
current=""
run_here() { # the command as written, in the scratch folder, femto from build/cli
  (cd "$here" && PATH="$root/build/cli:$PATH" bash -c "$current") >"$work/logs/last.log" 2>&1 ||
    { tail -n 30 "$work/logs/last.log" >&2; fail "'$current' exited with $?"; }
}
expect_file() { compgen -G "$here/$1" >/dev/null || fail "'$current' did not write $1"; }
expect_file_in_copy() { compgen -G "$copy/$1" >/dev/null || fail "'$current' did not write $1 (in the copy)"; }

run_view() { # an interactive viewer: a scripted drag, jump and slider under a virtual display
  need xvfb-run || return 0
  local shot=$work/view_$RANDOM.png cmd=$current
  current="$cmd --script $root/viewer/tests/drag.txt --frames 90 --screenshot $shot"
  (cd "$here" && PATH="$root/build/cli:$PATH" xvfb-run -a -s "-screen 0 1280x800x24" \
    bash -c "$current") >"$work/logs/last.log" 2>&1 ||
    { tail -n 30 "$work/logs/last.log" >&2; fail "'$current' exited with $?"; }
  [ -s "$shot" ] || fail "'$current' saved no screenshot"
  current=$cmd
}

run_demo() {
  FEMTO_DEMO_OUT=$work/demo FEMTO_DEMO_SECONDS=4.5 bash scripts/demo.sh >"$work/logs/demo.log" 2>&1 ||
    { tail -n 30 "$work/logs/demo.log" >&2; fail "bash scripts/demo.sh exited with $?"; }
  [ -s "$work/demo/house.pvd" ] || fail "scripts/demo.sh wrote no $work/demo/house.pvd"
  [ -s "$work/demo/house_000150.vtu" ] || fail "scripts/demo.sh wrote fewer than 150 frames"
  grep -q "open $work/demo/house.pvd in ParaView" "$work/logs/demo.log" ||
    fail "scripts/demo.sh did not say where the series is"
}

run_view_demo() { # README: build-demo/cli/femto view, from the tree's root after demo.sh
  [ -x build-demo/cli/femto ] || fail "'$current': scripts/demo.sh built no build-demo/cli/femto"
  need xvfb-run || return 0
  local shot=$work/view_demo.png
  xvfb-run -a -s "-screen 0 1280x800x24" bash -c \
    "$current --script viewer/tests/drag.txt --frames 90 --screenshot $shot" \
    >"$work/logs/last.log" 2>&1 || { tail -n 30 "$work/logs/last.log" >&2; fail "'$current' failed"; }
  [ -s "$shot" ] || fail "'$current' saved no screenshot"
}

run_serve() { # web.sh --serve: builds, then serves until killed; the page must answer
  need emcc || return 0
  local port
  port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
  PORT=$port timeout 900 bash -c "$current" >"$work/logs/serve.log" 2>&1 &
  local server=$! answered=false
  for _ in $(seq 1800); do
    if python3 -c "import urllib.request, sys; r = urllib.request.urlopen('http://127.0.0.1:$port/index.html', timeout=2); sys.exit(0 if b'femto' in r.read() else 1)" 2>/dev/null; then
      answered=true
      break
    fi
    kill -0 "$server" 2>/dev/null || break
    sleep 0.5
  done
  kill "$server" 2>/dev/null || true
  pkill -f "http.server $port" 2>/dev/null || true
  wait "$server" 2>/dev/null || true
  $answered || { tail -n 30 "$work/logs/serve.log" >&2; fail "'$current' never served the page on port $port"; }
}

copy=$work/tree
make_copy() { # the checkout's files (committed or not, not ignored), without its build folders
  [ -d "$copy" ] && return 0
  mkdir -p "$copy"
  git ls-files -co --exclude-standard -z | tar --null -T - -cf - | tar -xf - -C "$copy"
}
run_in_copy() {
  make_copy
  (cd "$copy" && bash -c "$current") >"$work/logs/last.log" 2>&1 ||
    { tail -n 30 "$work/logs/last.log" >&2; fail "'$current' (in a copy of the tree) exited with $?"; }
}
run_install() { # the README's install line, into a scratch prefix instead of /opt/femto
  make_copy
  local cmd=${current//\/opt\/femto/$work/prefix}
  [ -f "$copy/build/CMakeCache.txt" ] || fail "'$current' runs after the README's build line"
  (cd "$copy" && bash -c "$cmd") >"$work/logs/last.log" 2>&1 || fail "'$cmd' exited with $?"
  [ -f "$work/prefix/include/femto/femto.h" ] && [ -f "$work/prefix/lib/pkgconfig/femto.pc" ] ||
    fail "'$cmd' installed no headers or femto.pc"
}
run_consumer() { # cc game.c $(pkg-config ...): the consumer test's program as game.c
  need pkg-config || return 0
  mkdir -p "$work/game"
  cp tests/consumers/consumer.c "$work/game/game.c"
  (cd "$work/game" && PKG_CONFIG_PATH=$work/prefix/lib/pkgconfig bash -c "$current" &&
    LD_LIBRARY_PATH=$work/prefix/lib ./a.out) >"$work/logs/last.log" 2>&1 ||
    { tail -n 30 "$work/logs/last.log" >&2; fail "'$current' did not build a program that runs"; }
}
run_bench_docs() { # docs/performance.md's bench, sized down, in the copy (it writes docs/)
  make_copy
  (cd "$copy" && bash -c "$current --quick --max-tets 1500 --repeats 1") >"$work/logs/last.log" 2>&1 ||
    { tail -n 30 "$work/logs/last.log" >&2; fail "'$current' exited with $?"; }
  grep -q "^house2,1389,explicit" "$copy/docs/bench-2core.csv" || fail "'$current' wrote no house row"
}
run_fuzz_build() { need clang || return 0; run_here_root; }
run_here_root() {
  bash -c "$current" >"$work/logs/last.log" 2>&1 ||
    { tail -n 30 "$work/logs/last.log" >&2; fail "'$current' exited with $?"; }
}
run_fuzz_long() { # docs/robustness.md's hour-long run, for 10 s
  need clang || return 0
  [ -x build-fuzz/fuzz/fuzz_simulate ] || fail "'$current': build-fuzz/fuzz/fuzz_simulate was not built"
  local cmd=${current//-max_total_time=3600/-max_total_time=10}
  bash -c "$cmd" >"$work/logs/fuzz.log" 2>&1 || { tail -n 30 "$work/logs/fuzz.log" >&2; fail "'$cmd' failed"; }
}
run_tool() { need "$1" || return 1; run_here; } # 1: skipped (what follows with && is not checked)
run_tool_emcc() { need emcc || return 0; run_here_root; }
self() { :; } # the command that runs this check (or that it runs itself)

declare -A how=(
  # README.md
  ["bash scripts/demo.sh"]=run_demo
  ["bash scripts/test.sh"]=self
  ["build-demo/cli/femto view"]=run_view_demo
  ["bash scripts/web.sh --serve"]=run_serve
  ["cmake -S . -B build -DCMAKE_BUILD_TYPE=Release && cmake --build build -j"]=run_in_copy
  ["cmake --install build --prefix /opt/femto"]=run_install
  ['cc game.c $(pkg-config --cflags --libs femto)']=run_consumer
  ["ctest --test-dir build -j2"]=self # scripts/test.sh runs it (with --output-on-failure)
  ["ctest --test-dir build -R '^material\$'"]=run_here_root
  ["ctest --test-dir build -L viewer -j2"]=run_here_root
  ["FEMTO_FUZZ_SECONDS=5 FEMTO_FUZZ_FORMAT_SECONDS=5 bash scripts/check-fuzz.sh"]=self # run in full by test.sh
  ["femto run"]=run_here
  ["femto run scenes/house.json --seconds 5 --out out/house --obj"]="run_here; expect_file out/house/house.pvd; expect_file 'out/house/house_*.obj'"
  ["femto run --impulse-at 2 --export-node final.node"]="run_here; expect_file final.node"
  ["femto info data/house2.node"]=run_here
  ["femto convert cube.msh cube.vtu"]="run_here; expect_file cube.vtu"
  ["femto mesh bunny.stl bunny.node"]="run_tool tetgen && expect_file bunny.node"
  ["femto static scenes/cantilever.json --export-node bent.node"]="run_here; expect_file bent.node"
  ["femto bench --quick"]=run_here
  ["femto run scenes/two_houses.json --audit"]="run_here"
  ["femto run --seconds 4 --gif house.gif"]="run_here; expect_file house.gif"
  ["femto view scenes/drop.json"]=run_view
  # README.md's Python section and docs/python.md: in the copy, after its Release build line
  # (the tests compare with the copy's build/cli/femto)
  ["/usr/bin/python3 -m venv --system-site-packages .venv && .venv/bin/pip install --no-build-isolation ./python"]=run_in_copy
  [".venv/bin/python -m pytest python/tests"]=run_in_copy
  [".venv/bin/python python/examples/bouncy_house.py"]=run_in_copy
  [".venv/bin/python python/examples/material_sweep.py"]=run_in_copy
  [".venv/bin/python python/examples/gmsh_energy.py"]="run_in_copy; expect_file_in_copy energy.png"
  [".venv/bin/python python/bench/overhead.py"]=run_in_copy
  [".venv/bin/python python/sweep/drop_sweep.py --quick"]=run_in_copy
  # docs/cli.md
  ["femto run scenes/house.json --seconds 10 --out out/house --obj"]="run_here; expect_file out/house/house.pvd"
  ["femto mesh bunny.stl bunny.node --max-volume 1e-6"]="run_tool tetgen && expect_file bunny.ele"
  ["femto view scenes/house.json"]=run_view
  # docs/meshes.md
  ["tetgen -pq1.4a0.001 bunny.off"]="run_tool tetgen && expect_file bunny.1.ele"
  ["tetgen -pq1.2/12a0.001 bunny.off"]="run_tool tetgen && expect_file bunny.1.ele"
  ["tetgen -pYq1.4 bunny.off"]="run_tool tetgen && expect_file bunny.1.ele"
  ["femto info bunny.1.node"]="run_tool tetgen"
  ["gmsh -3 -format msh41 -o bunny.msh bunny.geo"]="run_tool gmsh && expect_file bunny.msh"
  ["femto info bunny.msh"]="run_tool gmsh"
  # docs/performance.md
  ["bash scripts/install-deps.sh"]=run_here_root
  ["cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo"]=run_here_root
  ["cmake --build build -j2"]=run_here_root
  ["uptime"]=run_here
  ["build/cli/femto bench --workers 2 --repeats 3 --csv docs/bench-2core.csv"]=run_bench_docs
  # docs/robustness.md
  ['CC=clang cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=Debug -DCMAKE_C_FLAGS_DEBUG="-O1 -g" -DFEMTO_SANITIZE=ON -DFEMTO_BUILD_FUZZERS=ON -DFEMTO_BUILD_TESTS=OFF']=run_fuzz_build
  ["cmake --build build-fuzz -j"]=run_fuzz_build
  ["mkdir -p build-fuzz/corpus-simulate build-fuzz/crashes"]=run_here_root
  ["build-fuzz/fuzz/fuzz_simulate build-fuzz/corpus-simulate fuzz/corpus/simulate -max_total_time=3600 -max_len=4096 -rss_limit_mb=2048 -timeout=10 -artifact_prefix=build-fuzz/crashes/simulate-"]=run_fuzz_long
  # docs/viewer.md
  ["femto view"]=run_view
  ["femto run scenes/cantilever.json --png frames --size 1280x720 --draw surfaces,floor,stress"]="run_here; expect_file frames/frame_0000.png"
  # docs/web.md
  ["bash scripts/web.sh"]=run_tool_emcc
  ["bash scripts/check-web.sh"]=self
)

# Every command shown has a way to run, and every way to run is still shown.
declare -A seen=()
while IFS=$'\t' read -r doc command; do
  [ -n "${how[$command]+x}" ] || fail "$doc shows '$command', which this check does not run (add it to scripts/check-commands.sh)"
  seen[$command]=1
done <"$shown"
for command in "${!how[@]}"; do
  [ -n "${seen[$command]+x}" ] || fail "'$command' is in the table but no document shows it any more"
done

# Run them in the documents' order (a command once, where it is first shown).
declare -A done_=()
count=0
while IFS=$'\t' read -r doc command; do
  [ -n "${done_[$command]+x}" ] && continue
  done_[$command]=1
  current=$command
  t0=$(date +%s)
  # A failure exits through fail(); a handler's status 1 means skipped (a tool is missing).
  eval "${how[$command]}" || true
  count=$((count + 1))
  say "ok ($(($(date +%s) - t0)) s) $doc: $command"
done <"$shown"
# The ```cmake blocks (README.md's consumer lines): each, as written, is the body of a game's
# CMakeLists.txt (after add_executable(game game.c), with the consumer test's program as game.c),
# configured against the scratch prefix (find_package) or with the tree's copy as
# third_party/femto (add_subdirectory), built and run.
blocks=0
for doc in README.md docs/*.md; do
  awk -v out="$work/cmake_block" '
    /^```cmake[[:space:]]*$/ { inside = 1; ++n; next }
    /^```/ { inside = 0; next }
    inside { print > (out "_" n ".txt") }' "$doc"
  for block in "$work"/cmake_block_*.txt; do
    [ -e "$block" ] || continue
    blocks=$((blocks + 1))
    game=$work/cmake_game_$blocks
    mkdir -p "$game/third_party"
    cp tests/consumers/consumer.c "$game/game.c"
    { echo "cmake_minimum_required(VERSION 3.22)"; echo "project(game LANGUAGES C)"
      echo "add_executable(game game.c)"; cat "$block"; } >"$game/CMakeLists.txt"
    make_copy
    ln -s "$copy" "$game/third_party/femto"
    current="$doc's cmake block: $(grep -v '^[[:space:]]*$' "$block" | head -n 1 | sed 's/[[:space:]]*#.*//')"
    t0=$(date +%s)
    (cmake -S "$game" -B "$game/build" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release &&
      cmake --build "$game/build" -j"$jobs" && "$game/build/game") >"$work/logs/last.log" 2>&1 ||
      { tail -n 30 "$work/logs/last.log" >&2; fail "$current: the game did not build or run"; }
    say "ok ($(($(date +%s) - t0)) s) $current"
    rm -f "$block"
  done
done
[ "$blocks" -gt 0 ] || fail "README.md shows no cmake block any more (the consumer lines)"

if [ ${#skipped[@]} -gt 0 ]; then
  printf 'check-commands: SKIPPED (tool missing): %s\n' "${skipped[@]}"
fi
say "$count commands of README.md and docs/ run as written in $(($(date +%s) - start)) s"
