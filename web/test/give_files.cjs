// The files web/femto_web.c reads (fw_file_path: the menu's scenes/*.json and the house's mesh),
// read from the repository and given to a WebAssembly build (fw_set_file), as the page gives the
// ones it fetches from web/dist/ and compare_native.c gives them to the native build.
'use strict';
const fs = require('fs');
const path = require('path');

const root = path.join(__dirname, '../..');

// Copy @p bytes into the module's memory (fw_alloc; the caller frees it with fw_free).
function copyIn(M, bytes) {
  const pointer = M._fw_alloc(Math.max(1, bytes.length));
  M.HEAPU8.set(bytes, pointer);
  return pointer;
}

function giveFiles(M) {
  for (let k = 0; k < M._fw_file_count(); ++k) {
    const file = M.UTF8ToString(M._fw_file_path(k));
    const text = fs.readFileSync(path.join(root, file));
    const namePointer = copyIn(M, Buffer.from(file + '\0')), textPointer = copyIn(M, text);
    const r = M._fw_set_file(namePointer, textPointer, text.length);
    M._fw_free(namePointer);
    M._fw_free(textPointer);
    if (r !== 0) throw new Error(M.UTF8ToString(M._fw_error()));
  }
}

module.exports = { copyIn, giveFiles };
