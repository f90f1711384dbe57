// Emscripten --pre-js for the test suites compiled to WebAssembly under Node.js
// (scripts/check-web.sh): hands the host's FEMTO_* variables to the program's getenv, which
// otherwise sees only Emscripten's defaults.
Module['preRun'] = Module['preRun'] || [];
Module['preRun'].push(function () {
  for (const name of Object.keys(process.env))
    if (name.startsWith('FEMTO_')) ENV[name] = process.env[name];
});
