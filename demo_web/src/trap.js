// trap.js - what the worker says when the WebAssembly module traps, and its memory limit. No DOM, no module:
// node tests import it directly.
//
//   trapAnswer(e, request, limitMb) -> {code, message}   e: what the module threw; limitMb: its memory limit
//   memoryLimitPages(text) -> pages | 0         the worker's ?memory=MB, in 64 KiB pages (0: the default)
//
// The web module is built without C++ exception catching, so a std::bad_alloc (an allocation the 2 GB
// address space or the ?memory limit cannot hold) ends the call in abort(): a WebAssembly.RuntimeError
// 'Aborted()' (measured with emscripten 3.1.6; an older runtime throws the exception's address, a number).
// Nothing else in this build aborts (NDEBUG: no assertions; the library throws nothing but allocation
// failures), so both are read as out of memory. Any other trap (out of bounds, unreachable) is a bug.

const requestWords = {
  load: 'opening the model', analyze: 'analysing the model', promote: 'promoting the offset',
  retarget: 'resizing', save: 'saving', catalog: 'starting', prepare: 'preparing the first resize',
};

export function trapAnswer(e, request, limitMb = 2048) {
  const during = requestWords[request] || request;
  const text = String(e && e.message ? e.message : e);
  const outOfMemory = typeof e === 'number' || /^Aborted\(|bad_alloc|out of memory|OOM|Cannot enlarge memory/i.test(text);
  if (outOfMemory)
    return { code: 'out_of_memory',
             message: `restitch ran out of memory while ${during} (the page can use at most ${limitMb} MB; the restitch ` +
                      'command-line tool has no such limit). The model was closed; open it or another one again.' };
  return { code: 'internal',
           message: `restitch stopped unexpectedly while ${during} (${e && e.message ? e.message : String(e)}); ` +
                    'this is a bug, please report it. The model was closed; open it or another one again.' };
}

export function memoryLimitPages(text) {
  if (text === null || text === undefined || text === '') return 0;
  const mb = Number(text);
  if (!Number.isFinite(mb)) return 0;
  return Math.round(Math.min(2048, Math.max(64, mb)) * 16);
}
