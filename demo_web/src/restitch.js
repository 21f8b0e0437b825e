// restitch.js - loads the restitch WebAssembly module (dist/restitch_web.mjs) in a page, a module Web Worker or node.
//
//   import { loadRestitch } from './restitch.js';
//   const restitch = await loadRestitch();      // resolves once the module is ready
//   const session = new restitch.Session();
//   session.loadGltf(bytes);                     // {ok, ...} or {ok: false, code, message}
//   session.delete();                            // embind objects are freed by hand
//
// The same ES6 artefact serves all three environments. Under node the loader
// wants `require` and `__dirname` as globals and cannot fetch a file: URL, so
// this sets them and hands it the .wasm bytes (docs/building.md).
// Cost: fetching and compiling about 0.5 MB of WebAssembly, once.

const moduleUrl = new URL('../dist/restitch_web.mjs', import.meta.url);
const wasmUrl = new URL('../dist/restitch_web.wasm', import.meta.url);

export async function loadRestitch(options = {}) {
  const isNode = typeof process !== 'undefined' && !!(process.versions && process.versions.node);
  const opts = { ...options };
  if (isNode) {
    const { createRequire } = await import('node:module');
    const { fileURLToPath } = await import('node:url');
    const path = await import('node:path');
    const fs = await import('node:fs');
    if (!globalThis.require) globalThis.require = createRequire(import.meta.url);
    if (!globalThis.__dirname) globalThis.__dirname = path.dirname(fileURLToPath(moduleUrl));
    if (!opts.wasmBinary) opts.wasmBinary = fs.readFileSync(fileURLToPath(wasmUrl));
  }
  const { default: createRestitch } = await import(moduleUrl.href);
  return createRestitch(opts);
}
