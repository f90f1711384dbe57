// The page (docs/web.md): libfemto in WebAssembly (dist/femto_wasm.js, built by scripts/web.sh
// from the same C as the native library) stepped at 60 ticks a second, drawn with WebGL2
// (renderer.js), played with the mouse, a finger and the keyboard. Everything the simulation
// does goes through web/femto_web.c's fw_* functions.
import { OrbitCamera, vec3 } from './camera.js';
import { Renderer } from './renderer.js';

const TICK_MS = 1000 / 60;        // one scene frame per tick, as femto view (docs/viewer.md)
const MAX_TICKS_PER_FRAME = 4;    // a slow machine slows down rather than falls behind
const MODELS = ['linear', 'corotated', 'StVK', 'Neo-Hookean', 'Mooney-Rivlin'];

const $ = (id) => document.getElementById(id);
const params = new URLSearchParams(location.search);

// Whether the browser runs WebAssembly SIMD: a module of one function returning v128.const 0.
const SIMD_PROBE = new Uint8Array([0, 0x61, 0x73, 0x6d, 1, 0, 0, 0, 1, 5, 1, 0x60, 0, 1, 0x7b,
  3, 2, 1, 0, 10, 22, 1, 20, 0, 0xfd, 0x0c, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x0b]);
const simd = WebAssembly.validate(SIMD_PROBE) && !params.has('nosimd');

// What a test or an embedding page can read (scripts/check-web.sh reads it).
const state = {
  ready: false, simd, dragging: false, frames: 0, fps: 0, stepMs: 0, libraryMs: 0, error: '', paused: false,
  normalsMs: 0, // a frame's normals split at creases and their positions, all bodies (renderer.js)
  scene: 0, bodyCount: 0, profileFrames: 0, contactLines: 0, grabLine: false, asleep: 0,
};
window.femto = state;

let M;            // the WebAssembly module
let renderer;
const camera = new OrbitCamera();
let sceneSubsteps = 10;
let sceneIntegrator = 0;

function message(text, isError) {
  const line = $('status');
  line.textContent = text;
  line.className = isError ? 'error' : '';
  if (isError) state.error = text;
}

function lastError() {
  return M.UTF8ToString(M._fw_error());
}

// Positions of body b as a Float32Array view of the module's memory (valid until it grows).
function positions(b) {
  const pointer = M._fw_positions(b);
  return M.HEAPF32.subarray(pointer >> 2, (pointer >> 2) + 3 * M._fw_vertex_count(b));
}

function bounds() {
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let b = 0; b < M._fw_body_count(); ++b) {
    const x = positions(b);
    for (let i = 0; i < x.length; i += 3)
      for (let k = 0; k < 3; ++k) {
        lo[k] = Math.min(lo[k], x[i + k]);
        hi[k] = Math.max(hi[k], x[i + k]);
      }
  }
  return { lo, hi };
}

// After a scene is loaded: GPU meshes, sliders from the scene, the camera on the bodies.
function sceneLoaded() {
  const bodies = [];
  let vertices = 0, tets = 0;
  for (let b = 0; b < M._fw_body_count(); ++b) {
    const pointer = M._fw_surface(b) >> 2;
    const triangles = Uint32Array.from(M.HEAP32.subarray(pointer, pointer + 3 * M._fw_surface_count(b)));
    bodies.push({ triangles, vertexCount: M._fw_vertex_count(b), positions: positions(b) });
    vertices += M._fw_vertex_count(b);
    tets += M._fw_tet_count(b);
  }
  renderer.setBodies(bodies);
  state.bodyCount = bodies.length;
  $('counts').textContent = `${bodies.length} ${bodies.length === 1 ? 'body' : 'bodies'}, ` +
    `${vertices} vertices, ${tets} tets`;
  $('model').value = M._fw_get_param(0);
  $('youngs').value = Math.log10(M._fw_get_param(1));
  $('poisson').value = M._fw_get_param(2);
  $('damping').value = M._fw_get_param(3);
  sceneSubsteps = M._fw_get_param(4);
  $('substeps').value = sceneSubsteps;
  sceneIntegrator = M._fw_get_param(5);
  $('integrator').value = sceneIntegrator;
  showValues();
  const { lo, hi } = bounds();
  lo[1] = Math.min(lo[1], M._fw_floor_height());
  const center = vec3.scale(0.5, vec3.add(lo, hi));
  placeCamera(center, 0.5 * Math.hypot(...vec3.sub(hi, lo)));
  setPaused(false);
  state.error = '';
  message('');
  profile.length = 0;
  state.profileFrames = 0;
}

// The scene's "camera" preset (fw_camera; docs/scene-format.md) over the framing of the bodies:
// its yaw and pitch first, the framing, then its target and distance.
function placeCamera(center, radius) {
  const preset = [0, 1, 2, 3, 4, 5].map((k) => M._fw_camera(k));
  if (!Number.isNaN(preset[4])) camera.yaw = (preset[4] * Math.PI) / 180;
  if (!Number.isNaN(preset[5])) camera.pitch = (preset[5] * Math.PI) / 180;
  camera.frame(center, radius);
  if (!Number.isNaN(preset[0])) camera.target = preset.slice(0, 3);
  if (!Number.isNaN(preset[3])) camera.distance = preset[3];
}

// The picker's scenes grouped by their files' "topic" (fw_scene_topic), in the format's order of
// topics, as femto view's list; each keeps its number (fw_load_scene's index, the URL's scene=N).
const TOPICS = ['materials', 'integrators', 'contact', 'colliders', 'loads', 'render meshes'];
function fillScenePicker(select) {
  const groups = new Map();
  for (let i = 0; i < M._fw_scene_count(); ++i) {
    const topic = M.UTF8ToString(M._fw_scene_topic(i)) || 'other';
    if (!groups.has(topic)) groups.set(topic, []);
    groups.get(topic).push(new Option(M.UTF8ToString(M._fw_scene_name(i)), String(i)));
  }
  const order = (t) => (TOPICS.includes(t) ? TOPICS.indexOf(t) : TOPICS.length);
  for (const topic of [...groups.keys()].sort((a, b) => order(a) - order(b))) {
    const group = document.createElement('optgroup');
    group.label = topic;
    for (const option of groups.get(topic)) group.appendChild(option);
    select.appendChild(group);
  }
}

// The camera follows the bodies when they leave the middle of the view (a thrown body, drop.json,
// flew out of the frame): its target eases toward their centre, the angles and distance kept,
// until they are back inside. Not while a drag is held (the drag moves what it looks at).
function followBodies() {
  if (state.dragging || state.bodyCount === 0) return;
  const { lo, hi } = bounds();
  const center = vec3.scale(0.5, vec3.add(lo, hi));
  const r = canvas.getBoundingClientRect();
  const p = camera.project(center, r.width, r.height);
  const inside = p && Math.abs(p[0] / r.width - 0.5) < 0.35 && Math.abs(p[1] / r.height - 0.5) < 0.35;
  if (inside) return;
  camera.target = vec3.add(camera.target, vec3.scale(0.08, vec3.sub(center, camera.target)));
}

function loadScene(index) {
  if (M._fw_load_scene(index, 0) !== 0) {
    message(`cannot load the scene: ${lastError()}`, true);
    return;
  }
  state.scene = index;
  sceneLoaded();
}

function showValues() {
  $('youngs-value').textContent = formatPascal(10 ** Number($('youngs').value));
  $('poisson-value').textContent = Number($('poisson').value).toFixed(3);
  $('damping-value').textContent = Number($('damping').value).toFixed(4);
  $('substeps-value').textContent = $('substeps').value;
}

function formatPascal(p) {
  if (p >= 1e6) return `${(p / 1e6).toPrecision(3)} MPa`;
  if (p >= 1e3) return `${(p / 1e3).toPrecision(3)} kPa`;
  return `${p.toPrecision(3)} Pa`;
}

function applyMaterial() {
  showValues();
  const r = M._fw_set_material(Number($('model').value), 10 ** Number($('youngs').value),
    Number($('poisson').value));
  if (r !== 0) message(lastError(), true);
  else if (!state.paused) message('');
}

function applyIntegrator() {
  const implicit = Number($('integrator').value);
  M._fw_set_integrator(implicit);
  // Backward Euler is stable at the whole frame: one step a frame. Explicit: the scene's substeps
  // when it is explicit, else substeps of at most the seeds' 3 ms.
  const explicitSubsteps = sceneIntegrator === 0 ? sceneSubsteps :
    Math.ceil(M._fw_get_param(6) / 0.003 - 1e-9);
  $('substeps').value = implicit ? 1 : explicitSubsteps;
  applySubsteps();
}

function applySubsteps() {
  showValues();
  M._fw_set_substeps(Number($('substeps').value));
}

// ---- input ------------------------------------------------------------------------------------
const canvas = $('view');
const pointers = new Map(); // active pointers: id -> {x, y}
let gesture = null;         // {kind: 'drag' | 'orbit' | 'pan' | 'pinch', ...}

function canvasPoint(event) {
  const r = canvas.getBoundingClientRect();
  return { x: event.clientX - r.left, y: event.clientY - r.top, width: r.width, height: r.height };
}

// Where the ray through a canvas point meets the plane through p facing the camera.
function onDragPlane(point, p) {
  const { origin, direction } = camera.ray(point.x, point.y, point.width, point.height);
  const normal = camera.axes().forward;
  const denominator = vec3.dot(direction, normal);
  if (Math.abs(denominator) < 1e-6) return null;
  const t = vec3.dot(vec3.sub(p, origin), normal) / denominator;
  return vec3.add(origin, vec3.scale(t, direction));
}

function startGesture(event) {
  const point = canvasPoint(event);
  if (pointers.size === 2) {
    endDrag();
    const [a, b] = [...pointers.values()];
    gesture = { kind: 'pinch', distance: Math.hypot(a.x - b.x, a.y - b.y),
      middle: [(a.x + b.x) / 2, (a.y + b.y) / 2] };
    return;
  }
  if (event.button === 1 || event.button === 2 || event.shiftKey) {
    gesture = { kind: 'pan', last: point };
    return;
  }
  const { origin, direction } = camera.ray(point.x, point.y, point.width, point.height);
  const range = 4 * camera.distance + 50;
  const body = M._fw_pick(...origin, ...vec3.scale(range, direction));
  if (body >= 0) {
    const hit = [M._fw_hit(1), M._fw_hit(2), M._fw_hit(3)];
    if (M._fw_drag_start(body, ...hit) === 0) {
      gesture = { kind: 'drag', anchor: hit };
      state.dragging = true;
      return;
    }
  }
  gesture = { kind: 'orbit', last: point };
}

function endDrag() {
  if (gesture && gesture.kind === 'drag') M._fw_drag_end();
  state.dragging = false;
  gesture = null;
}

canvas.addEventListener('pointerdown', (event) => {
  canvas.setPointerCapture(event.pointerId);
  const point = canvasPoint(event);
  pointers.set(event.pointerId, point);
  if (pointers.size <= 2) startGesture(event);
  event.preventDefault();
});

canvas.addEventListener('pointermove', (event) => {
  if (!pointers.has(event.pointerId)) return;
  const point = canvasPoint(event);
  pointers.set(event.pointerId, point);
  if (!gesture) return;
  if (gesture.kind === 'drag') {
    const target = onDragPlane(point, gesture.anchor);
    if (target) M._fw_drag_move(...target);
  } else if (gesture.kind === 'orbit') {
    camera.orbit(point.x - gesture.last.x, point.y - gesture.last.y);
    gesture.last = point;
  } else if (gesture.kind === 'pan') {
    camera.pan(point.x - gesture.last.x, point.y - gesture.last.y, point.height);
    gesture.last = point;
  } else if (gesture.kind === 'pinch' && pointers.size === 2) {
    const [a, b] = [...pointers.values()];
    const distance = Math.hypot(a.x - b.x, a.y - b.y);
    const middle = [(a.x + b.x) / 2, (a.y + b.y) / 2];
    if (distance > 0) camera.zoom(gesture.distance / distance);
    camera.pan(middle[0] - gesture.middle[0], middle[1] - gesture.middle[1], point.height);
    gesture.distance = distance;
    gesture.middle = middle;
  }
});

function pointerEnd(event) {
  if (!pointers.delete(event.pointerId)) return;
  endDrag();
}
canvas.addEventListener('pointerup', pointerEnd);
canvas.addEventListener('pointercancel', pointerEnd);
canvas.addEventListener('contextmenu', (event) => event.preventDefault());
canvas.addEventListener('wheel', (event) => {
  camera.zoom(event.deltaY > 0 ? 1.1 : 1 / 1.1);
  event.preventDefault();
}, { passive: false });

function jump() {
  M._fw_jump();
}

// The one place the pause state changes: the button's label always says what it will do.
function setPaused(paused)
{
	state.paused = paused;
	$('pause').textContent = paused ? 'Play' : 'Pause';
}

function togglePause() {
	setPaused(!state.paused);
}

window.addEventListener('keydown', (event) => {
  if (!M || event.target.tagName === 'SELECT' || event.target.tagName === 'INPUT' &&
      event.target.type !== 'range') return;
  if (event.code === 'Space') {
    jump();
    event.preventDefault();
  } else if (event.key === 'p' || event.key === 'P') togglePause();
  else if (event.key === 'r' || event.key === 'R') reset();
  else if (event.key === 'i' || event.key === 'I') {
    $('integrator').value = 1 - Number($('integrator').value);
    applyIntegrator();
  } else if (event.key === 'm' || event.key === 'M') {
    $('model').value = (Number($('model').value) + 1) % MODELS.length;
    applyMaterial();
  }
});

function reset() {
  if (state.scene >= 0) loadScene(state.scene);
  else if (droppedMesh) loadMesh(droppedMesh);
  $('scene').value = state.scene;
}

// ---- dropped meshes: a TetGen .node and .ele pair (fmLoadTetGenFromMemory), or one Gmsh .msh,
// VTK .vtk / .vtu or Medit .mesh file (fmLoadMeshFromMemory), read by the C readers ----------
let droppedMesh = null;
const pendingFiles = {};
const ONE_FILE_FORMATS = ['msh', 'vtk', 'vtu', 'mesh'];

function copyIn(bytes) {
  const pointer = M._fw_alloc(Math.max(1, bytes.length));
  M.HEAPU8.set(bytes, pointer);
  return pointer;
}

// Load @p mesh: {node, ele} (TetGen) or {name, data} (one file); shows the reader's message.
function loadMesh(mesh) {
  let r;
  if (mesh.node) {
    const nodePointer = copyIn(mesh.node), elePointer = copyIn(mesh.ele);
    r = M._fw_load_tetgen(nodePointer, mesh.node.length, elePointer, mesh.ele.length);
    M._fw_free(nodePointer);
    M._fw_free(elePointer);
  } else {
    const name = new TextEncoder().encode(mesh.name + '\0');
    const namePointer = copyIn(name), dataPointer = copyIn(mesh.data);
    r = M._fw_load_mesh(namePointer, dataPointer, mesh.data.length);
    M._fw_free(namePointer);
    M._fw_free(dataPointer);
  }
  if (r !== 0) {
    message(lastError(), true);
    return false;
  }
  droppedMesh = mesh;
  state.scene = -1;
  let option = $('scene').querySelector('option[value="-1"]');
  if (!option) {
    option = new Option('dropped mesh', '-1');
    $('scene').add(option);
  }
  $('scene').value = '-1';
  sceneLoaded();
  const warning = M.UTF8ToString(M._fw_warning());
  message(`loaded ${mesh.label}${warning ? ` (${warning})` : ''}`);
  return true;
}

async function takeFiles(files) {
  for (const file of files) {
    const extension = file.name.split('.').pop().toLowerCase();
    const data = new Uint8Array(await file.arrayBuffer());
    if (ONE_FILE_FORMATS.includes(extension)) {
      loadMesh({ name: file.name, data, label: file.name });
      return;
    }
    if (extension !== 'node' && extension !== 'ele') {
      message(`${file.name}: expected a .msh, .vtk, .vtu or .mesh file, or a TetGen .node and ` +
        '.ele pair', true);
      return;
    }
    pendingFiles[extension] = data;
    pendingFiles[extension + 'Name'] = file.name;
  }
  if (pendingFiles.node && pendingFiles.ele) {
    loadMesh({ node: pendingFiles.node, ele: pendingFiles.ele,
      label: `${pendingFiles.nodeName} + ${pendingFiles.eleName}` });
    delete pendingFiles.node;
    delete pendingFiles.ele;
  } else {
    message(`got the .${pendingFiles.node ? 'node' : 'ele'}; drop the ` +
      `.${pendingFiles.node ? 'ele' : 'node'} too`);
  }
}

window.addEventListener('dragover', (event) => {
  event.preventDefault();
  document.body.classList.add('dropping');
});
window.addEventListener('dragleave', () => document.body.classList.remove('dropping'));
window.addEventListener('drop', (event) => {
  event.preventDefault();
  document.body.classList.remove('dropping');
  if (M) takeFiles([...event.dataTransfer.files]);
});

// ---- the profile graph: Box2D's profile, each stage's time a frame over the last 5 s ----------
// fw_profile's stages (the last fmWorld_Step's fmProfile, ms; they do not overlap), stacked as
// bands from the bottom, the whole step as a line over them (what is left is the step's own
// overhead): which, name, colour. No colour is the house's orange (the browser test finds the
// house by it).
const PROFILE_FRAMES = 300;
const STEP_SHARE_MS = 8.3; // the physics' share of a 60 Hz frame (femto view's "over budget")
const PROFILE_STAGES = [
  [[1, 'forces', '#1f77b4'], [2, 'integrate', '#2ca02c'], [6, 'contact', '#9467bd'],
    [5, 'check', '#17becf']],
  [[3, 'solve', '#1f77b4'], [4, 'finish', '#2ca02c'], [6, 'contact', '#9467bd'],
    [5, 'check', '#17becf']],
];
const profile = []; // one Float64Array of fw_profile's 9 stages a frame, the newest last

function recordProfile() {
  const sample = new Float64Array(9);
  for (let k = 0; k < 9; ++k) sample[k] = M._fw_profile(k);
  profile.push(sample);
  if (profile.length > PROFILE_FRAMES) profile.shift();
  state.profileFrames = profile.length;
}

function drawProfile() {
  const graph = $('profile');
  const c = graph.getContext('2d');
  const w = graph.width, h = graph.height, plotTop = 24, plotBottom = h - 1;
  c.clearRect(0, 0, w, h);
  const stages = PROFILE_STAGES[Number($('integrator').value)];
  // The top follows the steps shown (their 95th percentile: a first step's warm-up of 20 ms or a
  // garbage collection would flatten the rest; higher steps are cut at the top).
  const steps = profile.map((sample) => sample[0]).sort((a, b) => a - b);
  const top = Math.max(0.1, 1.25 * (steps[Math.floor(0.95 * (steps.length - 1))] || 0));
  const y = (ms) => plotBottom - (plotBottom - plotTop) * Math.min(ms / top, 1);
  const x = (k) => (w * (k + PROFILE_FRAMES - profile.length)) / (PROFILE_FRAMES - 1);
  const below = new Float64Array(profile.length);
  for (const [which, , colour] of stages) {
    c.fillStyle = colour;
    c.beginPath();
    profile.forEach((sample, k) => c.lineTo(x(k), y(below[k] + sample[which])));
    for (let k = profile.length - 1; k >= 0; --k) c.lineTo(x(k), y(below[k]));
    c.fill();
    profile.forEach((sample, k) => { below[k] += sample[which]; });
  }
  c.strokeStyle = '#222';
  c.beginPath();
  profile.forEach((sample, k) => c.lineTo(x(k), y(sample[0])));
  c.stroke();
  if (top > STEP_SHARE_MS) {
    c.strokeStyle = '#d33'; // the physics' share of a 60 Hz frame
    c.beginPath();
    c.moveTo(0, y(STEP_SHARE_MS));
    c.lineTo(w, y(STEP_SHARE_MS));
    c.stroke();
  }
  c.font = '10px system-ui, sans-serif';
  c.fillStyle = '#444';
  const last = profile.length ? profile[profile.length - 1][0] : 0;
  c.fillText(`step ${last.toFixed(2)} ms (line), last 5 s, top ${top.toPrecision(2)} ms`, 2, 10);
  let legend = 2;
  for (const [, name, colour] of stages) {
    c.fillStyle = colour;
    c.fillText(name, legend, 21);
    legend += c.measureText(name).width + 6;
  }
}

// The contacts debug view: the library's contact lines (fw_contact_lines, fm_drawContacts).
function updateContactLines() {
  if (!$('contacts').checked) {
    renderer.setContactLines(new Float32Array(0));
    state.contactLines = 0;
    return;
  }
  const pointer = M._fw_contact_lines() >> 2;
  state.contactLines = M._fw_contact_line_count();
  renderer.setContactLines(M.HEAPF32.slice(pointer, pointer + 6 * state.contactLines));
}

// The drag's spring (fw_grab_line), drawn while a drag holds a body.
function updateGrabLine() {
  const pointer = M._fw_grab_line() >> 2;
  state.grabLine = pointer !== 0;
  renderer.setGrabLine(pointer !== 0 ? M.HEAPF32.slice(pointer, pointer + 6) : null);
}

// ---- the loop ---------------------------------------------------------------------------------
let last = performance.now();
let accumulator = 0;
let fpsFrames = 0, fpsStart = last, stepSum = 0, librarySum = 0, stepCount = 0, normalsStart = 0;

function frame(now) {
  accumulator += Math.min(now - last, 250);
  last = now;
  let ticks = 0;
  while (!state.paused && accumulator >= TICK_MS && ticks < MAX_TICKS_PER_FRAME) {
    accumulator -= TICK_MS;
    ticks += 1;
    const start = performance.now();
    const r = M._fw_step();
    stepSum += performance.now() - start;
    librarySum += M._fw_step_ms();
    recordProfile();
    stepCount += 1;
    state.frames += 1;
    if (r !== 0) {
		setPaused(true);
		message(`${lastError()} — paused; R or Reset starts again`, true);
    }
  }
  if (ticks === MAX_TICKS_PER_FRAME || state.paused) accumulator = 0;
  state.asleep = 0;
  for (let b = 0; b < M._fw_body_count(); ++b) {
    const asleep = M._fw_awake(b) === 0;
    state.asleep += asleep;
    renderer.updateBody(b, positions(b), asleep);
  }
  if (ticks > 0 || profile.length === 0) drawProfile();
  updateContactLines();
  updateGrabLine();
  followBodies();
  renderer.draw(camera, M._fw_floor_height());
  fpsFrames += 1;
  if (now - fpsStart >= 500) {
    state.fps = (1000 * fpsFrames) / (now - fpsStart);
    state.normalsMs = (renderer.normalsMs - normalsStart) / fpsFrames;
    normalsStart = renderer.normalsMs;
    if (stepCount > 0) {
      state.stepMs = stepSum / stepCount;
      state.libraryMs = librarySum / stepCount;
    }
    $('hud').textContent = `${state.fps.toFixed(0)} fps · step ${state.stepMs.toFixed(2)} ms ` +
      `(library ${state.libraryMs.toFixed(2)} ms)${simd ? '' : ' · no SIMD'}`;
    fpsFrames = 0;
    fpsStart = now;
    stepSum = librarySum = stepCount = 0;
  }
  requestAnimationFrame(frame);
}

// ---- start ------------------------------------------------------------------------------------
// The files the glue reads (fw_file_path: the menu's scenes/*.json and the house's mesh), fetched
// from dist/ beside this module, where scripts/web.sh copies them, and given to it (fw_set_file).
async function giveFiles() {
  const paths = [];
  for (let k = 0; k < M._fw_file_count(); ++k) paths.push(M.UTF8ToString(M._fw_file_path(k)));
  const texts = await Promise.all(paths.map(async (path) => {
    const response = await fetch(new URL(`dist/${path}`, import.meta.url));
    if (!response.ok)
      throw new Error(`cannot fetch dist/${path} (${response.status} ${response.statusText})`);
    return new Uint8Array(await response.arrayBuffer());
  }));
  paths.forEach((path, k) => {
    const namePointer = copyIn(new TextEncoder().encode(path + '\0'));
    const textPointer = copyIn(texts[k]);
    const r = M._fw_set_file(namePointer, textPointer, texts[k].length);
    M._fw_free(namePointer);
    M._fw_free(textPointer);
    if (r !== 0) throw new Error(lastError());
  });
}

async function main() {
  try {
    renderer = new Renderer(canvas);
  } catch (error) {
    message(`${error.message}: the page needs WebGL2`, true);
    return;
  }
  const { default: createFemto } = await import(simd ? './dist/femto_wasm.js' :
    './dist/femto_wasm_nosimd.js');
  M = await createFemto();
  await giveFiles();
  const select = $('scene');
  fillScenePicker(select);
  MODELS.forEach((name, i) => $('model').add(new Option(name, String(i))));
  select.addEventListener('change', () => {
    const index = Number(select.value);
    if (index >= 0) loadScene(index);
    else if (droppedMesh) loadMesh(droppedMesh);
  });
  $('model').addEventListener('change', applyMaterial);
  $('youngs').addEventListener('input', applyMaterial);
  $('poisson').addEventListener('input', applyMaterial);
  $('damping').addEventListener('input', showValues);
  $('damping').addEventListener('change', () => {
    if (M._fw_set_damping(Number($('damping').value)) !== 0) message(lastError(), true);
  });
  $('substeps').addEventListener('input', applySubsteps);
  $('integrator').addEventListener('change', applyIntegrator);
  $('jump').addEventListener('click', jump);
  $('pause').addEventListener('click', togglePause);
  $('reset').addEventListener('click', reset);
  $('files').addEventListener('change', (event) => takeFiles([...event.target.files]));
  // A clicked button gives the keyboard back, so that Space then jumps instead of clicking it.
  for (const button of document.querySelectorAll('button'))
    button.addEventListener('click', () => button.blur());
  if (params.has('embed')) document.body.classList.add('embed');
  const first = Number(params.get('scene') || 0);
  select.value = String(first);
  loadScene(first);
  if (params.has('paused')) togglePause();
  state.ready = true;
  requestAnimationFrame(frame);
}

// For tests and embedding pages: where a body's centre is on the canvas (CSS pixels).
state.bodyCenterOnCanvas = (b) => {
  const x = positions(b);
  const c = [0, 0, 0];
  for (let i = 0; i < x.length; i += 3) for (let k = 0; k < 3; ++k) c[k] += x[i + k];
  const n = x.length / 3;
  const r = canvas.getBoundingClientRect();
  const p = camera.project(c.map((v) => v / n), r.width, r.height);
  return p && { x: r.left + p[0], y: r.top + p[1] };
};

// For tests: where body @p b's walls meet nearest the camera, on the canvas (CSS pixels): the
// vertical edge of the box around its vertices in its lower @p part (the walls, under a roof that
// may overhang), nearest the eye, at @p height of that box's height.
state.wallCornerOnCanvas = (b, part = 0.6, height = 0.5) => {
  const x = positions(b);
  let bottom = Infinity, top = -Infinity;
  for (let i = 1; i < x.length; i += 3) bottom = Math.min(bottom, x[i]), top = Math.max(top, x[i]);
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < x.length; i += 3) {
    if (x[i + 1] > bottom + part * (top - bottom)) continue;
    for (let k = 0; k < 3; ++k) lo[k] = Math.min(lo[k], x[i + k]), hi[k] = Math.max(hi[k], x[i + k]);
  }
  const eye = camera.eye();
  const corner = [eye[0] > 0.5 * (lo[0] + hi[0]) ? hi[0] : lo[0], lo[1] + height * (hi[1] - lo[1]),
    eye[2] > 0.5 * (lo[2] + hi[2]) ? hi[2] : lo[2]];
  const r = canvas.getBoundingClientRect();
  const p = camera.project(corner, r.width, r.height);
  return p && { x: r.left + p[0], y: r.top + p[1] };
};

main().catch((error) => {
  message(`femto did not start: ${error.message}`, true);
  console.error(error);
});
