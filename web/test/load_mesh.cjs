// Dropped meshes under Node.js (docs/web.md, scripts/check-web.sh): fw_load_tetgen, the page's
// path for a dropped .node/.ele pair, loads data/house2 (400 vertices, 1389 tets, and it steps),
// and refuses a corrupted .ele with the reader's located diagnostic, and a tet with a repeated
// node with the body check's, keeping the scene it had; fw_load_mesh loads Gmsh's cube as binary
// .msh 4.1, .vtk and Medit .mesh (tests/data/mesh/) and refuses a broken .msh and an .obj; a mesh
// dropped before the glue was given its files (fw_set_file) is refused with a message.
'use strict';
const fs = require('fs');
const path = require('path');
const createFemto = require(path.join(__dirname, '../../build-web/node/femto_wasm.js'));
const { copyIn, giveFiles } = require('./give_files.cjs');

let failures = 0;
function check(ok, what) {
  console.log(`load_mesh: ${ok ? 'ok' : 'FAILED'}: ${what}`);
  if (!ok) failures += 1;
}

function load(M, node, ele) {
  const a = copyIn(M, node), b = copyIn(M, ele);
  const r = M._fw_load_tetgen(a, node.length, b, ele.length);
  M._fw_free(a);
  M._fw_free(b);
  return r;
}

function loadNamed(M, name, data) {
  const n = copyIn(M, Buffer.from(name + '\0')), d = copyIn(M, data);
  const r = M._fw_load_mesh(n, d, data.length);
  M._fw_free(n);
  M._fw_free(d);
  return r;
}

createFemto().then((M) => {
  let r;
  const data = path.join(__dirname, '../../data');
  const node = fs.readFileSync(path.join(data, 'house2.node'));
  const ele = fs.readFileSync(path.join(data, 'house2.ele'));
  r = load(M, node, ele);
  check(r !== 0 && /scenes\/house\.json was not given/.test(M.UTF8ToString(M._fw_error())),
    `a mesh dropped before the files were given is refused: "${M.UTF8ToString(M._fw_error())}"`);
  giveFiles(M);
  check(M._fw_load_scene(6, 0) === 0, 'the thrown cube loads');
  const cubeVertices = M._fw_vertex_count(0);
  const lines = ele.toString().split('\n');
  lines[3] = lines[3].replace(/\d+\s*$/, 'abc'); // a node index that is not a number
  r = load(M, node, Buffer.from(lines.join('\n')));
  const error = M.UTF8ToString(M._fw_error());
  check(r !== 0 && /ele:\d+/.test(error),
    `a corrupted .ele is refused with its line: "${error.slice(0, 120)}"`);
  check(M._fw_body_count() === 1 && M._fw_vertex_count(0) === cubeVertices,
    'the scene before the refused mesh is kept');
  const flat = ele.toString().split('\n');
  flat[5] = flat[5].replace(/^(\s*\d+\s+)(\d+)(\s+)\d+/, '$1$2$3$2'); // a tet with a node twice
  r = load(M, node, Buffer.from(flat.join('\n')));
  const flatError = M.UTF8ToString(M._fw_error());
  check(r !== 0 && M._fw_vertex_count(0) === cubeVertices,
    `a tet with a repeated node is refused, the scene kept: "${flatError.slice(0, 120)}"`);
  r = load(M, node, ele);
  check(r === 0 && M._fw_vertex_count(0) === 400 && M._fw_tet_count(0) === 1389,
    `data/house2 loads: ${M._fw_vertex_count(0)} vertices, ${M._fw_tet_count(0)} tets`);
  let steps = 0;
  while (steps < 60 && M._fw_step() === 0) steps += 1;
  check(steps === 60, `the dropped mesh steps 60 frames (${steps})`);

  // One-file formats through fmLoadMeshFromMemory: Gmsh's own cube, binary .msh 4.1 and .vtk.
  const meshes = path.join(__dirname, '../../tests/data/mesh');
  for (const name of ['cube_gmsh41_bin.msh', 'cube_gmsh.vtk', 'cube_gmsh.mesh']) {
    r = loadNamed(M, name, fs.readFileSync(path.join(meshes, name)));
    const tets = M._fw_tet_count(0);
    steps = 0;
    while (r === 0 && steps < 30 && M._fw_step() === 0) steps += 1;
    check(r === 0 && tets > 0 && steps === 30, `${name} loads (${tets} tets; ` +
      `"${M.UTF8ToString(M._fw_warning())}") and steps 30 frames`);
  }
  const broken = fs.readFileSync(path.join(meshes, 'cube_gmsh41.msh')).toString()
    .replace('$Elements', '$Elementz');
  r = loadNamed(M, 'broken.msh', Buffer.from(broken));
  check(r !== 0 && /broken\.msh/.test(M.UTF8ToString(M._fw_error())),
    `a broken .msh is refused: "${M.UTF8ToString(M._fw_error()).slice(0, 120)}"`);
  r = loadNamed(M, 'house.obj', Buffer.from('v 0 0 0'));
  check(r !== 0, `a file of another kind is refused: "${M.UTF8ToString(M._fw_error())}"`);
  process.exit(failures ? 1 : 0);
});
