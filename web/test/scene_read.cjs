// The scene reader in WebAssembly against the tool's (docs/web.md, scripts/check-web.sh): the
// page reads scenes/*.json with the tool's own schema code (cli/scene.c), its JSON tree filled by
// JSON.parse instead of cJSON. This checks that
//   0. before the glue is given its files (fw_set_file), a menu scene and a scene of
//      "builtin:house2" are refused with a message that names the missing file;
//   1. every scene of the page's menu is the file of scenes/ it names (fw_scene_file) and that
//      file loads through fw_load_scene_text;
//   2. the wasm's message for each scene file given is the tool's (`femto run FILE`, first line,
//      when FEMTO names the built tool): the same "file:line:column: path: message"; a syntax error
//      the same location and words up to the JavaScript engine's own reason, which it adds;
//   4. the menu is scenes/*.json less what the page cannot show: every scene file not in it is
//      refused by fw_load_scene_text ("the web page does not show ..." or a file it cannot
//      read), and every menu scene's topic (fw_scene_topic, the picker's group) is its file's;
//   3. malformed texts (cut short, nested 2000 deep, a second value, empty, binary noise) are
//      refused with a located message, and the page's scene stays loaded.
//
//   FEMTO=build/cli/femto node web/test/scene_read.cjs [SCENE.json ...]
// Exit status 0 when all agree, 1 when not.
'use strict';
const fs = require('fs');
const path = require('path');
const { spawnSync } = require('child_process');

const createFemto = require(path.join(__dirname, '../../build-web/node/femto_wasm.js'));
const { copyIn, giveFiles } = require('./give_files.cjs');
const root = path.join(__dirname, '../..');
let failures = 0;

function check(ok, what) {
  if (!ok) {
    failures += 1;
    console.log(`scene_read: FAILED: ${what}`);
  }
}

// Load @p text named @p name; the glue's result code and message.
function load(M, name, text) {
  const bytes = Buffer.from(text, 'utf8');
  const namePointer = copyIn(M, Buffer.from(name + '\0', 'utf8'));
  const textPointer = copyIn(M, bytes);
  const r = M._fw_load_scene_text(namePointer, textPointer, bytes.length, 1);
  M._fw_free(namePointer);
  M._fw_free(textPointer);
  return { r, message: M.UTF8ToString(M._fw_error()) };
}

function checkNotGiven(M) {
  check(M._fw_load_scene(0, 1) !== 0 &&
    M.UTF8ToString(M._fw_error()) === 'scenes/house.json was not given yet (fw_set_file)',
  `menu scene 0 before its file was given: ${M.UTF8ToString(M._fw_error())}`);
  const house = fs.readFileSync(path.join(root, 'scenes/house.json'), 'utf8');
  const { r, message } = load(M, 'scenes/house.json', house);
  check(r !== 0 && message.startsWith('scenes/house.json: "builtin:house2" needs data/house2.node'),
    `the house before its mesh was given: ${message}`);
  console.log('scene_read: before the files are given, the scenes are refused with a message');
}

function checkMenu(M) {
  for (let i = 0; i < M._fw_scene_count(); ++i) {
    const file = M.UTF8ToString(M._fw_scene_file(i));
    const text = fs.readFileSync(path.join(root, file), 'utf8');
    const { r, message } = load(M, file, text);
    check(r === 0, `${file} (menu entry ${i}) does not load: ${message}`);
    check(M._fw_body_count() >= 1, `${file}: no bodies`);
  }
  console.log(`scene_read: the ${M._fw_scene_count()} menu scenes load from scenes/`);
}

// The tool's first message line for @p file.
function nativeMessage(file) {
  const run = spawnSync(process.env.FEMTO, ['run', file, '--frames', '1', '--quiet']);
  return String(run.stderr).split('\n')[0];
}

function checkMessages(M, files) {
  if (!process.env.FEMTO || files.length === 0) {
    console.log('scene_read: (no FEMTO: the messages not compared with the tool\'s)');
    return;
  }
  for (const file of files) {
    const { r, message } = load(M, file, fs.readFileSync(file, 'utf8'));
    const native = nativeMessage(file);
    const syntax = / JSON syntax error at /.test(native);
    const same = syntax ? message.startsWith(native + ' (') : message === native;
    check(r !== 0 && same, `${file}: wasm says\n  ${message}\nthe tool says\n  ${native}`);
  }
  console.log(`scene_read: ${files.length} scene files give the tool's messages`);
}

function checkMenuIsScenes(M) {
  const menu = [];
  for (let i = 0; i < M._fw_scene_count(); ++i) {
    const file = M.UTF8ToString(M._fw_scene_file(i));
    menu.push(file);
    const topic = JSON.parse(fs.readFileSync(path.join(root, file), 'utf8')).topic;
    const shown = M.UTF8ToString(M._fw_scene_topic(i));
    check(typeof topic === 'string' && shown === topic,
      `${file}: the picker groups it under "${shown}", its file says ${JSON.stringify(topic)}`);
  }
  const left = fs.readdirSync(path.join(root, 'scenes')).filter((f) => f.endsWith('.json'))
    .map((f) => `scenes/${f}`).filter((f) => !menu.includes(f));
  for (const file of left) {
    const { r, message } = load(M, file, fs.readFileSync(path.join(root, file), 'utf8'));
    check(r !== 0, `${file} loads in the page but is not in its menu (web/femto_web.c's FW_SCENES)`);
    console.log(`scene_read: not in the menu: ${message}`);
  }
  console.log(`scene_read: the menu is scenes/*.json (${menu.length}) less the ${left.length} ` +
    'the page cannot show, each under its file\'s topic');
}

function checkMalformed(M) {
  const good = fs.readFileSync(path.join(root, 'scenes/house.json'), 'utf8');
  check(load(M, 'scenes/house.json', good).r === 0, 'scenes/house.json does not load');
  const vertices = M._fw_vertex_count(0);
  const cases = {
    'cut.json': good.slice(0, good.length / 2),
    'deep.json': '{"bodies": ' + '['.repeat(2000) + ']'.repeat(2000) + '}',
    'second.json': good + '\n{}',
    'empty.json': '',
    'noise.json': '{"dt": 0.003,\n "bodies": [\u0001\u0007\u00ff]}',
    'key.json': '{\n  "bodies": [{"mesh": "builtin:house2"}],\n  "colour": 1\n}',
  };
  for (const [name, text] of Object.entries(cases)) {
    const { r, message } = load(M, name, text);
    check(r !== 0 && new RegExp(`^${name.replace('.', '\\.')}:[0-9]+:[0-9]+: `).test(message),
      `${name}: expected a located message, got ${r}: ${message}`);
  }
  check(M._fw_vertex_count(0) === vertices, 'a refused scene did not leave the house');
  console.log(`scene_read: ${Object.keys(cases).length} malformed texts refused with their lines`);
}

createFemto().then((M) => {
  checkNotGiven(M);
  giveFiles(M);
  checkMenu(M);
  checkMenuIsScenes(M);
  checkMessages(M, process.argv.slice(2));
  checkMalformed(M);
  process.exit(failures === 0 ? 0 : 1);
});
