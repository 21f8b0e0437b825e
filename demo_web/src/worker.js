// worker.js - the module Web Worker that runs restitch for the page, so the page never freezes.
//
// Protocol (every request carries an `id`; every answer echoes it):
//   page -> worker                                     worker -> page
//   {type: 'catalog'}                                  {type: 'catalog', samples, policies, version}
//   {type: 'load', file: {name, bytes}}                {type: 'loaded', info, mesh, glb}
//   {type: 'load', sample: {name, params}}             (same)
//   {type: 'analyze', descriptor, matcher, detector,   {type: 'progress', stage, fraction} ..., then
//    prepare?: {labelSpace, seamEnergy}}               {type: 'analyzed', analysis, extras, ms}; then, with
//                                                      `prepare`, the worker builds the retargeter those
//                                                      policies need before the next request
//   {type: 'promote', ..., prepare?}                    (the same after a promotion)
//   {type: 'promote', offsets: [[x, y, z], ...]}       {type: 'promoted', offsets, analysis, extras, ms}
//     (model units, at most three: they become the first principal offsets, in order; [] goes back to the
//     detected ones; later retargets step along the new principal offsets. Refused: analysis unchanged.)
//   {type: 'retarget', steps: [a, b, c], labelSpace, pivot?}   {type: 'retargeted', steps, result, mesh, ms}
//   {type: 'retarget', size: [x, y, z], labelSpace, pivot?}    (the same: the nearest whole repeats to that box
//     size, model units, 0 keeps an axis, scaled about the pivot to it exactly; result.report.steps_principal
//     says which repeats)
//   {type: 'save', which: 'result' | 'input'}          {type: 'saved', bytes}
//   any failure                                        {type: 'error', request, code, message}
// `analysis` holds the fields of `restitch analyze --json`, `result.report` those
// of `restitch resize --json` (see ../bindings.cpp); `steps` are steps along the
// principal offsets v1, v2, v3. `mesh` is {positions, normals?, uvs?, colors?,
// indices, groups} (typed arrays transferred, not copied); `glb` is the model as
// .glb bytes, from which the page takes the materials and textures. Requests run one at a time in order;
// analysis cannot be interrupted, so the page replaces the worker to cancel it.
//
// A trap in the module (WebAssembly has no C++ exceptions here, so a failed allocation aborts the call, as
// would a bug) leaves the module's state unusable: the answer is {type: 'error', code: 'out_of_memory'} (an
// uncaught C++ exception: the library throws nothing else) or 'internal' (any other trap), the module
// instance is dropped with the model loaded in it, and the next request gets a fresh one (a trap while
// preparing the first resize, after the analysis was answered, is the answer to the next request). The worker's URL
// may carry ?memory=MB, the most memory the module may grow to (default and upper bound 2048 MB, the
// module's link-time maximum; lower bound 64 MB).
import { loadRestitch } from '../npm/index.js';  // the npm package's loader: the page is its first client
import { trapAnswer, memoryLimitPages } from './trap.js';

const maxPages = memoryLimitPages(self.location ? new URL(self.location.href).searchParams.get('memory') : null);
const instantiate = () => loadRestitch(maxPages ? { wasmMemory: new WebAssembly.Memory({ initial: 512, maximum: maxPages }) } : {});
const limitMb = maxPages ? maxPages / 16 : 2048;
let ready = instantiate();
let session = null;
let closed = null;  // {code, message} when a trap closed the model outside a request (see prepare)

function buffersOf(obj, out = []) {
  if (!obj || typeof obj !== 'object') return out;
  if (ArrayBuffer.isView(obj)) {
    if (!out.includes(obj.buffer)) out.push(obj.buffer);
    return out;
  }
  for (const v of Array.isArray(obj) ? obj : Object.values(obj)) buffersOf(v, out);
  return out;
}

function post(message) {
  self.postMessage(message, buffersOf(message));
}

function fail(msg, r) {
  post({ type: 'error', id: msg.id, request: msg.type, code: r.code, message: r.message });
}

// After an analysis or a promotion has been answered: builds the retargeter the first resize will need
// ({labelSpace, seamEnergy} of the page, when given), while the user looks at the analysis. A resize asked
// meanwhile waits for it (requests run in order) and then pays only for itself. A refusal here is not
// reported: the resize that needs it reports it.
function prepare(policies) {
  if (!policies || !policies.labelSpace || !session) return;
  try {
    session.prepare(policies.labelSpace, policies.seamEnergy || 'descriptor');
  } catch (e) {  // a trap after the answer went out: the next request (a resize, a save) is told why
    closed = trapAnswer(e, 'prepare', limitMb);
    ready = instantiate();
    session = null;
  }
}

function handle(restitch, msg) {
  switch (msg.type) {
    case 'catalog':
      post({ type: 'catalog', id: msg.id, samples: restitch.samples(), policies: restitch.policies(),
             version: restitch.version() });
      return;
    case 'load': {
      const r = msg.file ? session.loadGltf(new Uint8Array(msg.file.bytes))
                         : session.loadSample(msg.sample.name, msg.sample.params || {});
      if (!r.ok) return fail(msg, r);
      const glb = session.saveGlb('input');
      post({ type: 'loaded', id: msg.id, info: r, mesh: session.mesh('input'), glb: glb.ok ? glb.bytes : null });
      return;
    }
    case 'analyze': {
      const t0 = performance.now();
      const r = session.analyze(msg.descriptor, msg.matcher, msg.detector || 'histogram', (stage, fraction) =>
        self.postMessage({ type: 'progress', id: msg.id, stage, fraction }));
      if (!r.ok) return fail(msg, r);
      post({ type: 'analyzed', id: msg.id, analysis: r.analysis, extras: r.extras, ms: performance.now() - t0 });
      prepare(msg.prepare);
      return;
    }
    case 'promote': {
      const t0 = performance.now();
      const r = session.promote(msg.offsets);
      if (!r.ok) return fail(msg, r);
      post({ type: 'promoted', id: msg.id, offsets: msg.offsets, analysis: r.analysis, extras: r.extras,
             ms: performance.now() - t0 });
      prepare(msg.prepare);
      return;
    }
    case 'retarget': {
      const t0 = performance.now();
      const pivot = msg.pivot || 'origin', energy = msg.seamEnergy || 'descriptor';
      const r = msg.size ? session.retargetToSize(msg.size[0], msg.size[1], msg.size[2], true, msg.labelSpace, pivot, energy)
                         : session.retarget(msg.steps[0], msg.steps[1], msg.steps[2], msg.labelSpace, pivot, energy);
      if (!r.ok) return fail(msg, r);
      const mesh = session.mesh('result');
      post({ type: 'retargeted', id: msg.id, steps: msg.steps, labelSpace: msg.labelSpace, pivot: msg.pivot, result: r, mesh,
             ms: performance.now() - t0 });
      return;
    }
    case 'save': {
      const r = session.saveGlb(msg.which || 'result');
      if (!r.ok) return fail(msg, r);
      post({ type: 'saved', id: msg.id, bytes: r.bytes });
      return;
    }
    default:
      fail(msg, { code: 'invalid_argument', message: `unknown request '${msg.type}'` });
  }
}

self.onmessage = async (event) => {
  let restitch;
  try {
    restitch = await ready;
  } catch (e) {
    post({ type: 'error', id: event.data.id, request: event.data.type, code: 'internal',
           message: `the WebAssembly module did not load: ${e && e.message ? e.message : e}` });
    return;
  }
  if (!session) session = new restitch.Session();
  if (closed && event.data.type !== 'load' && event.data.type !== 'catalog') {
    post({ type: 'error', id: event.data.id, request: event.data.type, ...closed });
    closed = null;
    return;
  }
  closed = null;
  try {
    handle(restitch, event.data);
  } catch (e) {  // the bindings return {ok: false} for every refusal; a trap (out of memory, a bug) lands here
    ready = instantiate();  // the old instance is unusable: the next request gets a new one
    session = null;
    post({ type: 'error', id: event.data.id, request: event.data.type, ...trapAnswer(e, event.data.type, limitMb) });
  }
};
