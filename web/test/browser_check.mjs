// The page under headless Chromium (docs/web.md, scripts/check-web.sh), through the DevTools
// protocol with Node's own WebSocket (else the ws module: Debian's node-ws, found through
// NODE_PATH=/usr/share/nodejs) and zlib (no network):
//   1. open the page, wait for 40 simulated frames: no console error or exception, no failed step;
//   2. the canvas is not blank: enough pixels of the house's colour;
//   3. the house's pixels move between two screenshots 30 frames apart;
//   4. a scripted mouse drag from the house's centre upward lifts the house in the picture and
//      draws the drag's spring in the grab's pink (gone after the release); a finger (touch
//      events) drags it too; the Play/Pause label matches the state after a
//      pause, a reset and a scene change; the profile graph draws its stages' lines, the
//      contacts view draws the contacts' lines, a pile that has come to rest is dimmed, and the
//      house's wall corner is drawn sharp (normals split at creases: each face uniform beside it);
//   5. the page's measured step cost (ms a frame, wall clock around fw_step, and the library's);
//   6. a TetGen .node/.ele pair and a Gmsh .msh given to the page's file input (the drop's path)
//      load (and the pair steps);
//   7. the build without WebAssembly SIMD (?nosimd=1) loads and steps.
//
//   node --experimental-websocket web/test/browser_check.mjs URL [SCREENSHOT.png]
// (Node 22 and later have WebSocket without the flag.) CHROMIUM names the browser (default
// chromium). Exit status 0 when every check passes, 1 otherwise.
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { inflateSync } from 'node:zlib';

// Node 22 has WebSocket; 20.10 behind --experimental-websocket; older ones take the ws module,
// whose WebSocket has the same addEventListener and event.data.
const WebSocketClient = typeof WebSocket === 'function' ? WebSocket
  : createRequire(import.meta.url)('ws');
const url = process.argv[2];
const screenshotOut = process.argv[3];
const WIDTH = 1024, HEIGHT = 768;
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
let failures = 0;

function check(ok, what) {
  console.log(`browser: ${ok ? 'ok' : 'FAILED'}: ${what}`);
  if (!ok) failures += 1;
}

// ---- a minimal PNG reader: 8-bit RGB or RGBA, not interlaced (what Chromium writes) ----------
function decodePng(buffer) {
  let offset = 8;
  let width = 0, height = 0, channels = 0;
  const idat = [];
  while (offset < buffer.length) {
    const length = buffer.readUInt32BE(offset);
    const type = buffer.toString('ascii', offset + 4, offset + 8);
    const data = buffer.subarray(offset + 8, offset + 8 + length);
    if (type === 'IHDR') {
      width = data.readUInt32BE(0);
      height = data.readUInt32BE(4);
      if (data[8] !== 8 || data[12] !== 0) throw new Error('PNG: only 8-bit, non-interlaced');
      channels = { 2: 3, 6: 4 }[data[9]];
      if (!channels) throw new Error(`PNG: colour type ${data[9]} not read`);
    } else if (type === 'IDAT') idat.push(data);
    offset += 12 + length;
  }
  const raw = inflateSync(Buffer.concat(idat));
  const stride = width * channels;
  const pixels = new Uint8Array(width * height * 4);
  let previous = new Uint8Array(stride);
  for (let y = 0; y < height; ++y) {
    const filter = raw[y * (stride + 1)];
    const line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    const out = new Uint8Array(stride);
    for (let i = 0; i < stride; ++i) {
      const a = i >= channels ? out[i - channels] : 0;
      const b = previous[i];
      const c = i >= channels ? previous[i - channels] : 0;
      let predictor = 0;
      if (filter === 1) predictor = a;
      else if (filter === 2) predictor = b;
      else if (filter === 3) predictor = (a + b) >> 1;
      else if (filter === 4) {
        const p = a + b - c, pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
        predictor = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      out[i] = (line[i] + predictor) & 255;
    }
    for (let x = 0; x < width; ++x) {
      for (let k = 0; k < 3; ++k) pixels[4 * (y * width + x) + k] = out[x * channels + k];
      pixels[4 * (y * width + x) + 3] = 255;
    }
    previous = out;
  }
  return { width, height, pixels };
}

// The house's pixels: its orange (renderer.js's first palette colour, lit), far from the grey
// floor, the blue-grey sky and the white panel.
function houseMask(image) {
  const mask = new Uint8Array(image.width * image.height);
  let count = 0, sumY = 0, top = image.height;
  for (let i = 0; i < mask.length; ++i) {
    const r = image.pixels[4 * i], g = image.pixels[4 * i + 1], b = image.pixels[4 * i + 2];
    if (r > g + 25 && g > b + 10 && r > 60) {
      mask[i] = 1;
      count += 1;
      const y = Math.floor(i / image.width);
      sumY += y;
      top = Math.min(top, y);
    }
  }
  return { mask, count, centroidY: count ? sumY / count : NaN, top };
}

// Pixels of @p image within @p tolerance of @p rgb, in the rectangle @p r (CSS pixels, the
// screenshot's scale is 1): their count and how many distinct columns they span.
function colourIn(image, r, rgb, tolerance) {
  let count = 0;
  const columns = new Set();
  for (let y = Math.max(0, Math.floor(r.top)); y < Math.min(image.height, r.bottom); ++y)
    for (let x = Math.max(0, Math.floor(r.left)); x < Math.min(image.width, r.right); ++x) {
      const i = 4 * (y * image.width + x);
      if (Math.abs(image.pixels[i] - rgb[0]) <= tolerance &&
          Math.abs(image.pixels[i + 1] - rgb[1]) <= tolerance &&
          Math.abs(image.pixels[i + 2] - rgb[2]) <= tolerance) {
        count += 1;
        columns.add(x);
      }
    }
  return { count, columns: columns.size };
}

// How coloured the pixels around (x, y) are: the mean spread between their largest and smallest
// channel over a 9x9 patch (0 for greys; a sleeping body is dimmed toward grey).
function saturationAt(image, x, y) {
  let sum = 0, n = 0;
  for (let v = Math.round(y) - 4; v <= Math.round(y) + 4; ++v)
    for (let u = Math.round(x) - 4; u <= Math.round(x) + 4; ++u) {
      if (u < 0 || v < 0 || u >= image.width || v >= image.height) continue;
      const i = 4 * (v * image.width + u);
      const px = [image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]];
      sum += Math.max(...px) - Math.min(...px);
      n += 1;
    }
  return n ? sum / n : 0;
}

function maskDifference(a, b) {
  let d = 0;
  for (let i = 0; i < a.mask.length; ++i) d += a.mask[i] !== b.mask[i];
  return d;
}

// ---- the browser -------------------------------------------------------------------------------
async function launch() {
  const profile = mkdtempSync(join(tmpdir(), 'femto-chromium-'));
  const browser = spawn(process.env.CHROMIUM || 'chromium', [
    '--headless=new', '--no-sandbox', '--no-first-run', '--no-default-browser-check',
    '--disable-extensions', '--disable-background-networking', '--use-angle=swiftshader',
    '--enable-unsafe-swiftshader', `--window-size=${WIDTH},${HEIGHT}`,
    '--remote-debugging-port=0', `--user-data-dir=${profile}`, 'about:blank',
  ], { stdio: ['ignore', 'ignore', 'pipe'] });
  const endpoint = await new Promise((resolve, reject) => {
    let text = '';
    const timer = setTimeout(() => reject(new Error('Chromium did not start in 30 s')), 30000);
    browser.stderr.on('data', (chunk) => {
      text += chunk;
      const match = text.match(/DevTools listening on (ws:\/\/\S+)/);
      if (match) {
        clearTimeout(timer);
        resolve(match[1]);
      }
    });
    browser.on('exit', (code) => reject(new Error(`Chromium exited (${code}): ${text.slice(-500)}`)));
  });
  return { browser, endpoint, profile };
}

class Session {
  constructor(socket) {
    this.socket = socket;
    this.next = 1;
    this.pending = new Map();
    this.listeners = [];
    socket.addEventListener('message', (event) => {
      const message = JSON.parse(event.data);
      if (message.id && this.pending.has(message.id)) {
        const { resolve, reject } = this.pending.get(message.id);
        this.pending.delete(message.id);
        if (message.error) reject(new Error(JSON.stringify(message.error)));
        else resolve(message.result);
      } else if (message.method) for (const listener of this.listeners) listener(message);
    });
  }

  static async open(wsUrl) {
    const socket = new WebSocketClient(wsUrl);
    await new Promise((resolve, reject) => {
      socket.addEventListener('open', resolve);
      socket.addEventListener('error', () => reject(new Error(`cannot connect to ${wsUrl}`)));
    });
    return new Session(socket);
  }

  send(method, params = {}, sessionId) {
    const id = this.next++;
    this.socket.send(JSON.stringify({ id, method, params, sessionId }));
    return new Promise((resolve, reject) => this.pending.set(id, { resolve, reject }));
  }
}

const rectOf = (evaluate, id) => evaluate(`(() => { const r = document.getElementById("${id}")` +
  '.getBoundingClientRect(); return { left: r.left, top: r.top, right: r.right, ' +
  'bottom: r.bottom }; })()');

// The profile graph (Box2D's profile) holds the last frames and draws the forces' band across
// the graph (the legend's word alone spans a few dozen columns); the contacts view draws the library's
// contact lines in its yellow over the canvas (not the panel), none with the view off.
async function checkProfileAndContacts(evaluate, screenshot) {
  // Waits are long: on a loaded machine the page may run a few frames a second.
  await waitFor(evaluate, 'femto.profileFrames >= 200', 120);
  const graph = await rectOf(evaluate, 'profile');
  const frames = await evaluate('femto.profileFrames');
  const image = decodePng(await screenshot());
  const forces = colourIn(image, graph, [0x1f, 0x77, 0xb4], 40);
  check(frames >= 200 && forces.columns > 100 && graph.bottom <= image.height,
    `the profile graph holds ${frames} frames (200 or more needed) and its forces band spans ` +
    `${forces.columns} columns of the graph (more than 100 needed; ${forces.count} pixels)`);
  const panel = await rectOf(evaluate, 'panel');
  const canvasOnly = { left: panel.right + 1, top: 0, right: image.width, bottom: image.height };
  const yellowBefore = colourIn(image, canvasOnly, [255, 0xd0, 0], 40).count;
  await evaluate('document.getElementById("contacts").click()');
  await waitFor(evaluate, 'femto.contactLines > 0', 30);
  await sleep(700);
  const lines = await evaluate('femto.contactLines');
  const yellowAfter = colourIn(decodePng(await screenshot()), canvasOnly, [255, 0xd0, 0], 40).count;
  await evaluate('document.getElementById("contacts").click()');
  check(lines > 0 && yellowAfter > 40 && yellowAfter > 4 * yellowBefore + 10,
    `the contacts view draws the contacts' lines: ${lines} lines, ${yellowAfter} pixels of their ` +
    `yellow (more than 40 needed), ${yellowBefore} with the view off`);
}

// A pile at rest falls asleep (pile.json's "contact": {"sleep": true}) and is drawn dimmed: the
// top box's pixels are less coloured than when it was dropped, seen paused both times.
async function checkSleepDimmed(evaluate, screenshot) {
  await evaluate('(() => { const s = document.getElementById("scene"); ' +
    'const o = [...s.options].find((x) => x.text.startsWith("pile")); s.value = o.value; ' +
    's.dispatchEvent(new Event("change")); document.getElementById("pause").click(); })()');
  await sleep(400);
  const seen = async () => {
    const p = await evaluate('femto.bodyCenterOnCanvas(2)');
    return saturationAt(decodePng(await screenshot()), p.x, p.y);
  };
  const awake = await seen();
  await evaluate('document.getElementById("pause").click()');
  const slept = await waitFor(evaluate, 'femto.asleep === femto.bodyCount', 120);
  await evaluate('document.getElementById("pause").click()');
  await sleep(400);
  const asleep = await seen();
  await evaluate('document.getElementById("pause").click()');
  check(slept && asleep < 0.75 * awake, `the pile at rest sleeps (${slept ? 'all' : 'not all'} ` +
    `of its bodies within 120 s of wall time) and is dimmed: its top box's colour spread ${asleep.toFixed(0)} ` +
    `against ${awake.toFixed(0)} awake (less than 75% needed)`);
  await evaluate('(() => { const s = document.getElementById("scene"); ' +
    's.value = s.options[0].value; s.dispatchEvent(new Event("change")); })()');
}

// The house's hard edges are drawn sharp (normals split at creases, renderer.js): the house as
// loaded, paused before its first step, seen from the page's default camera; along the row through
// the corner where its walls meet nearest the camera (femto.wallCornerOnCanvas), within 40 pixels
// of it, at the strongest step of luminance, the 8 pixels either side (3 to 10 off the edge) are
// each uniform (within 5 levels) and the two faces differ by 12 levels or more, as femto view's
// test (viewer/tests/check_images.c, "crease"). Normals smoothed across the edge spread the change
// over the faces beside it (a streak).
const luminance = (image, x, y) => {
  const i = 4 * (y * image.width + x);
  return 0.299 * image.pixels[i] + 0.587 * image.pixels[i + 1] + 0.114 * image.pixels[i + 2];
};

async function checkCrease(evaluate, screenshot) {
  await evaluate('(() => { const s = document.getElementById("scene"); ' +
    's.value = s.options[0].value; s.dispatchEvent(new Event("change")); ' +
    'if (!femto.paused) document.getElementById("pause").click(); })()');
  await sleep(400);
  const corner = await evaluate('femto.wallCornerOnCanvas(0)');
  const image = decodePng(await screenshot());
  await evaluate('document.getElementById("pause").click()');
  const mask = houseMask(image).mask;
  const row = Math.round(corner.y), x0 = Math.round(corner.x) - 40, x1 = Math.round(corner.x) + 40;
  let edge = -1, best = -1, onHouse = 0;
  for (let x = x0; x <= x1; ++x) onHouse += mask[row * image.width + x];
  for (let x = x0 + 11; x <= x1 - 11; ++x) {
    if (!mask[row * image.width + x - 10] || !mask[row * image.width + x + 10]) continue;
    const step = Math.abs(luminance(image, x + 1, row) - luminance(image, x - 1, row));
    if (step > best) best = step, edge = x;
  }
  if (edge < 0) {
    check(false, `the house's wall corner is drawn sharp: no house pixels about (${x0} to ${x1}, ` +
      `${row}) (${onHouse} of ${x1 - x0 + 1})`);
    return;
  }
  const span = (a, b) => {
    const values = [];
    for (let x = a; x <= b; ++x) values.push(luminance(image, x, row));
    return { mean: values.reduce((p, q) => p + q) / values.length,
      spread: Math.max(...values) - Math.min(...values) };
  };
  const left = span(edge - 10, edge - 3), right = span(edge + 3, edge + 10);
  check(left.spread <= 5 && right.spread <= 5 && Math.abs(left.mean - right.mean) >= 12,
    `the house's wall corner is drawn sharp: along row ${row}, the crease at column ${edge}; ` +
    `each face beside it uniform (${left.spread.toFixed(1)} and ${right.spread.toFixed(1)} ` +
    `levels, at most 5) and the two apart (${left.mean.toFixed(1)} and ${right.mean.toFixed(1)}, ` +
    '12 or more needed)');
}

async function waitFor(evaluate, expression, seconds) {
  for (let t = 0; t < seconds * 10; ++t) {
    if (await evaluate(expression)) return true;
    await sleep(100);
  }
  return false;
}

async function main() {
  const { browser, endpoint, profile } = await launch();
  const cdp = await Session.open(endpoint);
  try {
    const { targetId } = await cdp.send('Target.createTarget', { url: 'about:blank' });
    const { sessionId } = await cdp.send('Target.attachToTarget', { targetId, flatten: true });
    const page = (method, params) => cdp.send(method, params, sessionId);
    const errors = [];
    cdp.listeners.push((m) => {
      if (m.sessionId !== sessionId) return;
      if (m.method === 'Runtime.consoleAPICalled' && (m.params.type === 'error' ||
          m.params.type === 'assert'))
        errors.push(m.params.args.map((a) => a.value ?? a.description).join(' '));
      else if (m.method === 'Runtime.exceptionThrown')
        errors.push(m.params.exceptionDetails.exception?.description ??
          m.params.exceptionDetails.text);
      else if (m.method === 'Log.entryAdded' && m.params.entry.level === 'error')
        errors.push(`${m.params.entry.text} ${m.params.entry.url ?? ''}`);
    });
    await page('Runtime.enable');
    await page('Log.enable');
    await page('Page.enable');
    await page('Emulation.setDeviceMetricsOverride', { width: WIDTH, height: HEIGHT,
      deviceScaleFactor: 1, mobile: false });
    await page('Page.navigate', { url });
    const evaluate = async (expression) => (await page('Runtime.evaluate',
      { expression, returnByValue: true, awaitPromise: true })).result.value;
    const waitFor = async (expression, seconds) => {
      for (let t = 0; t < seconds * 10; ++t) {
        if (await evaluate(expression)) return true;
        await sleep(100);
      }
      return false;
    };
    const screenshot = async () => Buffer.from((await page('Page.captureScreenshot',
      { format: 'png' })).data, 'base64');

    const started = await waitFor('window.femto && window.femto.ready', 20);
    check(started, 'the page loaded femto\'s WebAssembly');
    if (!started) return;
    // 40 frames: 1.2 s of the house's simulated time, landed and bouncing.
    check(await waitFor('window.femto.frames >= 40', 20), 'the page stepped 40 frames');
    // The second picture is taken 30 frames (0.5 s of the page's time at 60 fps) after the
    // first: counted in frames, not wall time, so a slow host does not shorten the motion.
    const framesA = await evaluate('window.femto.frames');
    const a = await screenshot();
    const advanced = await waitFor(`window.femto.frames >= ${framesA + 30}`, 30);
    const b = await screenshot();
    const imageA = decodePng(a), imageB = decodePng(b);
    const maskA = houseMask(imageA), maskB = houseMask(imageB);
    const pixels = imageA.width * imageA.height;
    check(maskA.count > 0.02 * pixels,
      `the canvas is not blank: ${(100 * maskA.count / pixels).toFixed(1)}% of the pixels are ` +
      'the house\'s (more than 2% needed)');
    const moved = maskDifference(maskA, maskB);
    check(advanced && moved > 0.002 * pixels,
      `the house's pixels move between two screenshots 30 frames apart: ${moved} pixels changed ` +
      `(more than ${Math.round(0.002 * pixels)} needed)`);

    // Let it settle a little, then drag from its centre 200 px up, in steps, and hold.
    await waitFor('window.femto.frames >= 150', 20);
    const before = houseMask(decodePng(await screenshot()));
    const center = await evaluate('window.femto.bodyCenterOnCanvas(0)');
    const mouse = (type, x, y, extra = {}) => page('Input.dispatchMouseEvent',
      { type, x, y, button: 'left', buttons: type === 'mouseReleased' ? 0 : 1, ...extra });
    await mouse('mousePressed', center.x, center.y, { clickCount: 1 });
    const dragging = await evaluate('window.femto.dragging');
    for (let k = 1; k <= 20; ++k) {
      await mouse('mouseMoved', center.x, center.y - 10 * k);
      await sleep(50);
    }
    await sleep(700);
    const duringImage = decodePng(await screenshot());
    const during = houseMask(duringImage);
    const spring = await evaluate('window.femto.grabLine');
    await mouse('mouseReleased', center.x, center.y - 200, { clickCount: 1 });
    await sleep(300);
    const pink = (image) => colourIn(image, { left: 0, top: 0, right: image.width,
      bottom: image.height }, [255, 0x40, 0xc0], 40).count;
    const pinkDuring = pink(duringImage), pinkAfter = pink(decodePng(await screenshot()));
    check(spring && pinkDuring > 100 && pinkAfter < 10,
      `the drag's spring is drawn in the grab's pink while it holds (${pinkDuring} pixels, more ` +
      `than 100 needed) and gone after the release (${pinkAfter}, fewer than 10 needed)`);
    check(dragging, 'a press on the house picked it (ray cast) and started a drag');
    check(before.top - during.top > 30,
      `the drag lifted the house in the picture: its top went from row ${before.top} to ` +
      `${during.top} (more than 30 px up needed)`);

    // A finger: a touch on the house drags it too (pointer events), and lifting it lets go.
    await sleep(1000);
    await page('Emulation.setTouchEmulationEnabled', { enabled: true, maxTouchPoints: 2 });
    const finger = await evaluate('window.femto.bodyCenterOnCanvas(0)');
    const touch = (type, points) => page('Input.dispatchTouchEvent', { type, touchPoints: points });
    await touch('touchStart', [{ x: finger.x, y: finger.y }]);
    const touchDrags = await evaluate('window.femto.dragging');
    for (let k = 1; k <= 5; ++k) {
      await touch('touchMove', [{ x: finger.x + 10 * k, y: finger.y - 10 * k }]);
      await sleep(50);
    }
    await touch('touchEnd', []);
    await sleep(100);
    const touchReleased = !(await evaluate('window.femto.dragging'));
    check(touchDrags && touchReleased, 'a finger on the house drags it and lifting it lets go');
    await page('Emulation.setTouchEmulationEnabled', { enabled: false });

    // A thrown body stays in view: drop.json's cube, 3 s after its throw, is on the canvas (the
    // camera follows the bodies when they leave the middle of the view).
    await evaluate('(() => { const s = document.getElementById("scene"); ' +
      'const o = [...s.options].find((x) => x.text.startsWith("drop")); s.value = o.value; ' +
      's.dispatchEvent(new Event("change")); })()');
    await sleep(3000);
    const thrown = await evaluate('(() => { const p = window.femto.bodyCenterOnCanvas(0); ' +
      'const r = document.getElementById("view").getBoundingClientRect(); ' +
      'return p && p.x > 0 && p.y > 0 && p.x < r.width && p.y < r.height; })()');
    check(thrown, 'drop.json\'s thrown cube is still in view after 3 s (the camera follows)');

    // The scene picker shows its longest name whole (it was cut at 140 px).
    const picker = await evaluate('(() => { const s = document.getElementById("scene"); ' +
      'const c = document.createElement("canvas").getContext("2d"); c.font = getComputedStyle(s).font; ' +
      'let w = 0; for (const o of s.options) w = Math.max(w, c.measureText(o.text).width); ' +
      'return [w, s.clientWidth]; })()');
    check(picker[1] >= picker[0] + 20, `the scene picker (${picker[1]} px) holds its longest name ` +
      `(${picker[0].toFixed(0)} px and the arrow)`);

    // The picker groups the scenes by their files' topics (optgroups, in the format's order),
    // none left outside a group or under "other" (scene_read.cjs checks each group is its file's).
    const groups = await evaluate('(() => { const s = document.getElementById("scene"); ' +
      'return { labels: [...s.querySelectorAll("optgroup")].map((g) => g.label), ' +
      'grouped: s.querySelectorAll("optgroup option").length, all: s.options.length }; })()');
    const topics = ['materials', 'integrators', 'contact', 'colliders', 'loads', 'render meshes'];
    const ordered = groups.labels.every((l, k) => topics.includes(l) &&
      (k === 0 || topics.indexOf(l) > topics.indexOf(groups.labels[k - 1])));
    check(groups.labels.length >= 3 && ordered && groups.grouped === groups.all,
      `the scene picker is grouped by topic: ${groups.labels.join(', ')} (${groups.grouped} of ` +
      `${groups.all} scenes in a group)`);

    // The Play/Pause label says what it will do after every control: paused then reset, and
    // paused then another scene, the page runs again and the button says "Pause".
    const label = () => evaluate('[document.getElementById("pause").textContent, femto.paused]');
    await evaluate('document.getElementById("pause").click()');
    const pausedLabel = await label();
    await evaluate('document.getElementById("reset").click()');
    const afterReset = await label();
    await evaluate('document.getElementById("pause").click()');
    await evaluate('(() => { const s = document.getElementById("scene"); ' +
      's.value = s.options[1].value; s.dispatchEvent(new Event("change")); })()');
    const afterScene = await label();
    await evaluate('(() => { const s = document.getElementById("scene"); ' +
      's.value = s.options[0].value; s.dispatchEvent(new Event("change")); })()');
    check(pausedLabel[0] === 'Play' && pausedLabel[1] &&
      afterReset[0] === 'Pause' && !afterReset[1] && afterScene[0] === 'Pause' && !afterScene[1],
      `the Play/Pause label matches the state: paused "${pausedLabel[0]}", after a reset ` +
      `"${afterReset[0]}" (${afterReset[1] ? 'paused' : 'running'}), after a scene change ` +
      `"${afterScene[0]}" (${afterScene[1] ? 'paused' : 'running'})`);

    await checkProfileAndContacts(evaluate, screenshot);
    await checkSleepDimmed(evaluate, screenshot);
    await checkCrease(evaluate, screenshot);

    await sleep(300);
    const stats = await evaluate('({ fps: femto.fps, stepMs: femto.stepMs, ' +
      'libraryMs: femto.libraryMs, frames: femto.frames, error: femto.error })');
    console.log(`browser: measured in headless Chromium (software WebGL): ${stats.fps.toFixed(0)} ` +
      `fps, ${stats.stepMs.toFixed(2)} ms a frame in fw_step (library ${stats.libraryMs.toFixed(2)}` +
      ` ms), ${stats.frames} frames`);
    check(stats.error === '', `no step failed${stats.error ? `: ${stats.error}` : ''}`);
    check(errors.length === 0, `no console error or exception${errors.length ? ': ' +
      errors.join(' | ') : ''}`);
    if (screenshotOut) writeFileSync(screenshotOut, a);

    // Load a TetGen pair through the page's file input (what a drop does too): data/house2.
    const data = join(dirname(fileURLToPath(import.meta.url)), '../../data');
    const { root } = await page('DOM.getDocument');
    const { nodeId } = await page('DOM.querySelector', { nodeId: root.nodeId, selector: '#files' });
    await page('DOM.setFileInputFiles', { nodeId,
      files: [join(data, 'house2.node'), join(data, 'house2.ele')] });
    const loaded = await waitFor('window.femto.scene === -1 && window.femto.bodyCount === 1 && ' +
      'document.getElementById("status").textContent.startsWith("loaded house2")', 10);
    const framesAtLoad = await evaluate('window.femto.frames');
    await sleep(500);
    const stepping = (await evaluate('window.femto.frames')) > framesAtLoad;
    check(loaded && stepping, 'a TetGen .node and .ele pair given to the page loads and steps');
    await page('DOM.setFileInputFiles', { nodeId,
      files: [join(data, '../tests/data/mesh/cube_gmsh41.msh')] });
    const gmsh = await waitFor('window.femto.bodyCount === 1 && document.getElementById("status")' +
      '.textContent.startsWith("loaded cube_gmsh41.msh")', 10);
    check(gmsh, 'a Gmsh .msh file given to the page loads: ' +
      `"${await evaluate('document.getElementById("status").textContent')}"`);

    // The build without WebAssembly SIMD, which browsers without it get, runs too.
    const plain = url + (url.includes('?') ? '&' : '?') + 'nosimd=1';
    await page('Page.navigate', { url: plain });
    await sleep(300);
    const plainRuns = await waitFor('window.femto && window.femto.ready && ' +
      '!window.femto.simd && window.femto.frames >= 20', 20);
    check(plainRuns && errors.length === 0, 'the build without SIMD (?nosimd=1) loads and steps ' +
      `with no console error${errors.length ? ': ' + errors.join(' | ') : ''}`);
  } finally {
    cdp.socket.close();
    const exited = new Promise((resolve) => browser.on('exit', resolve));
    browser.kill();
    await Promise.race([exited, sleep(5000)]);
    try {
      rmSync(profile, { recursive: true, force: true, maxRetries: 5 });
    } catch {
      // a helper process still writing: the profile is in the temporary folder anyway
    }
  }
}

main().then(() => {
  console.log(failures ? `browser: ${failures} check(s) FAILED` : 'browser: all checks passed');
  process.exit(failures ? 1 : 0);
}, (error) => {
  console.log(`browser: FAILED: ${error.message}`);
  process.exit(1);
});
