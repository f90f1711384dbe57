// The WebAssembly side of the Node.js comparison (docs/web.md, scripts/check-web.sh): runs the
// scene script of compare_native.c on build-web/node/femto_wasm.js and compares the final
// positions with the native program's output, bit for bit, or within a tolerance (m).
//
//   node web/test/compare_node.cjs SCENE FRAMES DETERMINISTIC INTEGRATOR
//        NATIVE_OUTPUT TOLERANCE [femto_wasm | femto_wasm_nosimd]
// TOLERANCE 0 asks for identical bits. Exit status 0 when they agree, 1 when not.
'use strict';
const fs = require('fs');
const path = require('path');

const [scene, frames, deterministic, integrator] = process.argv.slice(2, 6).map(Number);
const nativeFile = process.argv[6];
const tolerance = Number(process.argv[7]);
const build = process.argv[8] || 'femto_wasm'; // or femto_wasm_nosimd: the build without SIMD
const createFemto = require(path.join(__dirname, '../../build-web/node', build + '.js'));
const { giveFiles } = require('./give_files.cjs');

function run(M) {
  giveFiles(M);
  if (M._fw_load_scene(scene, deterministic) !== 0)
    throw new Error(M.UTF8ToString(M._fw_error()));
  M._fw_set_integrator(integrator);
  const start = performance.now();
  for (let f = 0; f < frames; ++f) {
    if (f === Math.floor(frames / 3)) M._fw_jump();
    if (f === Math.floor(frames / 2)) {
      const x = M._fw_positions_double(0) / 8;
      M._fw_drag_start(0, M.HEAPF64[x + 15], M.HEAPF64[x + 16], M.HEAPF64[x + 17]);
      M._fw_drag_move(M.HEAPF64[x + 15], M.HEAPF64[x + 16] + 0.2, M.HEAPF64[x + 17]);
    }
    if (f === Math.floor((2 * frames) / 3)) M._fw_drag_end();
    if (M._fw_step() !== 0) throw new Error(`frame ${f}: ${M.UTF8ToString(M._fw_error())}`);
  }
  const ms = (performance.now() - start) / frames;
  const lines = [];
  for (let b = 0; b < M._fw_body_count(); ++b) {
    const n = M._fw_vertex_count(b);
    const x = M._fw_positions_double(b) / 8;
    const bits = new BigUint64Array(Float64Array.from(M.HEAPF64.subarray(x, x + 3 * n)).buffer);
    for (let i = 0; i < n; ++i) {
      const hex = [0, 1, 2].map((k) => bits[3 * i + k].toString(16).padStart(16, '0'));
      lines.push(`${b} ${i} ${hex.join(' ')}`);
    }
  }
  return { lines, ms };
}

function toDouble(hex) {
  const view = new DataView(new ArrayBuffer(8));
  view.setBigUint64(0, BigInt('0x' + hex));
  return view.getFloat64(0);
}

createFemto().then((M) => {
  const { lines, ms } = run(M);
  const native = fs.readFileSync(nativeFile, 'utf8').trim().split('\n');
  const label = `${build}: scene ${scene}, ${frames} frames, deterministic ${deterministic}, ` +
    `integrator ${integrator}`;
  if (native.length !== lines.length) {
    console.log(`compare: ${label}: ${native.length} native lines, ${lines.length} wasm lines`);
    process.exit(1);
  }
  let differing = 0;
  let maxDiff = 0;
  let first = '';
  for (let k = 0; k < lines.length; ++k) {
    if (lines[k] === native[k]) continue;
    const a = lines[k].split(' ');
    const b = native[k].split(' ');
    for (let c = 2; c < 5; ++c) {
      if (a[c] === b[c]) continue;
      differing += 1;
      const diff = Math.abs(toDouble(a[c]) - toDouble(b[c]));
      maxDiff = Math.max(maxDiff, Number.isNaN(diff) ? Infinity : diff);
      if (!first) first = `body ${a[0]} vertex ${a[1]}: wasm ${toDouble(a[c])}, native ${toDouble(b[c])}`;
    }
  }
  const coordinates = 3 * lines.length;
  const verdict = tolerance === 0 ? differing === 0 : maxDiff <= tolerance;
  console.log(`compare: ${label}: ${coordinates - differing}/${coordinates} coordinates ` +
    `bit-identical, largest difference ${maxDiff.toExponential(3)} m ` +
    `(${tolerance === 0 ? 'bit-identical required' : `tolerance ${tolerance} m`}); ` +
    `wasm ${ms.toFixed(3)} ms a frame: ${verdict ? 'ok' : 'FAILED'}` +
    (first ? `; first difference: ${first}` : ''));
  process.exit(verdict ? 0 : 1);
});
