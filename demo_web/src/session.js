// session.js - the demo's state machine: start, load a model, analyse it, resize it; no DOM, no three.js.
//
//   const session = new Session(client, { hooks, policy: () => ({ descriptor, matcher, detector, labelSpace, seamEnergy }) });
//   (labelSpace and seamEnergy, when given, go with each analysis and promotion so the worker prepares the
//   first resize's retargeter while the user looks at the result)
//   await session.start();                     // the catalog: {samples, policies, version}, or null on failure
//   await session.load({ sample: { name, params } });   // or { file: { name, bytes } }; analyses it too
//   await session.resize([a, b, c], labelSpace, pivot);  // resolves once hooks.result has shown it (pivot: 'origin' if not given)
//   await session.resize({ size: [x, y, z] }, labelSpace, pivot);  // the nearest whole repeats to a box size (model
//                                              units, 0 keeps an axis), scaled about the pivot to that size exactly
//   await session.promote([[x, y, z], ...]);            // these offsets principal first; [] = the detected ones
//   session.reanalyze()        the policy changed      session.save() -> .glb bytes (the result, else the input)
//   session.present() -> mesh  what the view shows     session.fail(message): the error state, from the app
//
// `client` is a WorkerClient (./worker-client.js) or a fake with the same request(type, payload, options) and
// restart(). Status goes 'loading' -> 'analyzing' -> 'ready', or 'error' with `state.error` in words.
//
// Generations: every load and every re-analysis starts a new generation; an answer that arrives for an older
// one (a model opened or analysed since) is dropped, and a load that finds the worker busy restarts it
// (analysis cannot be interrupted), which cancels the running request.
// Resizes are latest-wins: at most one retarget is in flight; a request made meanwhile waits as the next one
// and a later request replaces it. The promise of a replaced request rejects with an Error whose
// `.superseded` is true (unless the later request asks for the same steps: it then shares its result). A
// failed resize rejects its promise with the worker's message and sets the error state; a new load or
// analysis rejects the promises still pending.
// Promotions (offsets made principal, model units, the analysis refitted in the worker) are latest-wins the
// same way, in a queue of their own: one in flight, a later request replaces the waiting one (whose promise
// rejects with `.superseded`). While one is in flight no resize is sent; once its answer is in, the new
// analysis replaces the old one (hooks.analysis: the sliders follow the new principal offsets), the input is
// shown again, and the resizes asked for meanwhile are dropped (their steps referred to the old offsets). A
// refused promotion rejects with the worker's message and sets the error state, and changes nothing else:
// analysis, result and the offsets promoted before stay, and the waiting resizes run.
//
// hooks (all optional; the app draws from them):
//   status(status)            every status change (also recorded in `statusHistory`)
//   error(message)            the error to show, '' to hide it
//   loading(label)            a load began: label is the file's name or 'sample: NAME'
//   materials(glb) -> promise what `model.materials` holds, from the loaded model's .glb bytes (default [])
//   model(model)              the input model is loaded and shown (no analysis yet)
//   progress(stage, fraction) analysis progress; progress(null) once the analysis has ended
//   analysis(analysis)        the analysis is in (`state.analysis`, `state.extras`), after a load, a
//                             re-analysis or a promotion
//   result(retarget) -> promise   a resize result is in `state.retarget`; resolve once the view shows it
//   timed(retarget)           its time from request to view, `retarget.pageMs`, is known
//   redraw()                  a load or an analysis failed: the view should draw the state as it is now
//
// state: status, error, startFailed (the last start failed: start() tries again), catalog [{name, units, ...}],
//   policies {descriptors, matchers, label_spaces},
//   model {name, units, info, inputMesh, materials} (info: the worker's load answer: bbox_min/max, triangles,
//   warnings, ...), analysis (`restitch analyze --json` fields), extras (raw match offsets for the histogram),
//   analysisMs, promoted [[x, y, z]...] (the offsets made principal on request, [] for the detected ones),
//   retarget {steps, labelSpace, pivot, result, mesh, ms, pageMs} (the result shown, null while the input
//   is shown), shown {vertices, triangles} (of the mesh shown).

const NO_REPETITION = 'No repetition found: restitch found no repeated part in this model, so there is nothing to ' +
                      'resize along. Try a model with repeated parts (shelves, windows, fence pickets).';

// The error shown for an analysis without principal offsets: candidates, when there are, can be promoted.
export function noRepetitionMessage(analysis) {
  const n = (analysis.candidates || []).length;
  if (!n) return NO_REPETITION;
  return `No repeated pattern found, but ${n === 1 ? 'a candidate repeat' : `${n} candidate repeats`} (a pair or a ` +
         'weaker parallel repeat): click one under Candidates to resize along it.';
}

const noop = () => {};
const defaultHooks = {
  status: noop, error: noop, loading: noop, materials: async () => [], model: noop, progress: noop,
  analysis: noop, result: noop, timed: noop, redraw: noop,
};

function countsOf(mesh) {
  return { vertices: mesh.positions.length / 3, triangles: mesh.indices.length / 3 };
}

// Latest-wins: `job` replaces the waiting one, which shares its promises when it asks for the same (`key`) and
// else rejects them with an Error whose .superseded is true.
function replace(waiting, job, what) {
  if (waiting && waiting.key === job.key) job.waiters.unshift(...waiting.waiters);
  else if (waiting) {
    const superseded = () => Object.assign(new Error(`superseded by a later ${what} request`), { superseded: true });
    for (const w of waiting.waiters) w.reject(superseded());
  }
  return job;
}

export class Session {
  state = {
    status: 'loading', error: '', startFailed: false, catalog: [],
    policies: { descriptors: [], matchers: [], label_spaces: [] },
    model: null, analysis: null, extras: null, analysisMs: 0, promoted: [], retarget: null, shown: null,
  };
  statusHistory = [];   // every status change, for automated checks
  resizeTimings = [];   // ms from request to view, per resize shown
  progressReports = 0;  // analysis progress reports shown

  #client;
  #hooks;
  #policy;
  #now;
  #generation = 0;
  #starting = null;     // the catalog request of start(), while it runs
  #deferred = null;     // the model asked for while the start had failed
  #inFlight = null;     // the retarget job running: {steps, labelSpace, key, t0, waiters}
  #next = null;         // the one waiting to run
  #promoting = null;    // the promotion running: {offsets, key, waiters}
  #nextPromotion = null;  // the one waiting to run

  constructor(client, { hooks = {}, policy = () => ({}), now = () => performance.now() } = {}) {
    this.#client = client;
    this.#hooks = { ...defaultHooks, ...hooks };
    this.#policy = policy;
    this.#now = now;
  }

  // Starts the worker and asks for the catalog; null (and the error state) when that fails. A model opened
  // meanwhile waits for it (load), and a worker restarted meanwhile is asked again, so the start never ends
  // as "cancelled". A failed start (state.startFailed) is tried again by calling start() again; a model
  // opened while it had failed is loaded once a start succeeds.
  async start() {
    this.state.startFailed = false;
    this.#clearError();
    this.#setStatus('loading');
    this.#client.restart();
    this.#starting = this.#askCatalog();
    let msg = null;
    try {
      msg = await this.#starting;
    } finally {
      this.#starting = null;
    }
    if (msg && this.#deferred) {
      const what = this.#deferred;
      this.#deferred = null;
      this.load(what);
    }
    return msg;
  }

  async #askCatalog() {
    for (;;) {
      try {
        const msg = await this.#client.request('catalog');
        this.state.catalog = msg.samples;
        this.state.policies = msg.policies;
        return msg;
      } catch (e) {
        if (e.cancelled) continue;  // the worker was restarted under the request: ask the new one
        this.state.startFailed = true;
        this.fail(`restitch could not start: ${e.message}`);
        return null;
      }
    }
  }

  // Whether a model was asked for (by load) since the page started.
  get opened() { return this.#generation > 0; }

  // Loads a model ({file: {name, bytes}} or {sample: {name, params}}) and analyses it. During the start it
  // waits for the catalog first; a later load supersedes it.
  async load(what) {
    const generation = ++this.#generation;
    if (this.#starting) await this.#starting;
    if (generation !== this.#generation) return;  // superseded while the page started
    if (this.state.startFailed) {  // loaded once a start succeeds (start() again: the page's Retry)
      this.#deferred = what;
      return;
    }
    if (this.state.status === 'analyzing' || this.state.status === 'loading') this.#client.restart();
    this.#clearError();
    this.#setStatus('loading');
    Object.assign(this.state, { analysis: null, extras: null, retarget: null, promoted: [] });
    this.#dropResizes('a new model was opened');
    this.#dropPromotions('a new model was opened');
    const label = what.file ? what.file.name : `sample: ${what.sample.name}`;
    this.#hooks.loading(label);
    try {
      const transfer = what.file ? [what.file.bytes] : [];
      const msg = await this.#client.request('load', what, { transfer });
      if (generation !== this.#generation) return;
      const materials = await this.#hooks.materials(msg.glb);
      if (generation !== this.#generation) return;
      const sample = what.sample && this.state.catalog.find((s) => s.name === what.sample.name);
      this.state.model = { name: label, units: (sample && sample.units) || 'm', info: msg.info, inputMesh: msg.mesh,
                           materials };
      for (const w of msg.info.warnings || []) console.info(`restitch: ${w}`);
      this.present();
      this.#hooks.model(this.state.model);
      await this.#analyze(generation);
    } catch (e) {
      if (e.cancelled || generation !== this.#generation) return;
      this.fail(`Could not open ${label}: ${e.message}`);
      this.#hooks.redraw();
    }
  }

  // Analyses the loaded model again (the policy changed): a new generation, so answers about the previous
  // analysis are dropped.
  async reanalyze() {
    const generation = ++this.#generation;
    this.#dropResizes('the model is being analysed again');
    this.#dropPromotions('the model is being analysed again');
    await this.#analyze(generation);
  }

  // Asks for the model resized by `steps` along the principal offsets, or to {size: [x, y, z]} exactly (the
  // nearest whole repeats scaled about the pivot); see the header for the queue. Resolves with {vertices,
  // triangles, steps, ms} once the view shows it (steps: the whole repeats along the principal offsets).
  resize(steps, labelSpace, pivot = 'origin', seamEnergy = 'descriptor') {
    const size = Array.isArray(steps) ? null : steps.size.map(Number);
    const key = `${size ? `size ${size.join(',')}` : steps.join(',')}|${labelSpace}|${pivot}|${seamEnergy}`;
    const job = { steps: size ? null : steps.slice(), size, labelSpace, pivot, seamEnergy, key, t0: this.#now(), waiters: [] };
    const promise = new Promise((resolve, reject) => job.waiters.push({ resolve, reject }));
    this.#next = replace(this.#next, job, 'resize');
    this.#pump();
    return promise;
  }

  // Makes `offsets` (model units, at most three) the first principal offsets, in order ([]: back to the
  // detected ones); see the header for the queue. Resolves with the new analysis once hooks.analysis has
  // shown it.
  promote(offsets) {
    const list = offsets.map((v) => Array.from(v, Number));
    const job = { offsets: list, key: JSON.stringify(list), waiters: [] };
    const promise = new Promise((resolve, reject) => job.waiters.push({ resolve, reject }));
    if (!this.state.analysis || this.state.status === 'analyzing') {
      for (const w of job.waiters) w.reject(new Error('no analysed model yet'));
      return promise;
    }
    this.#nextPromotion = replace(this.#nextPromotion, job, 'promotion');
    this.#pumpPromotion();
    return promise;
  }

  // The .glb bytes of the result shown, else of the input.
  async save() {
    const msg = await this.#client.request('save', { which: this.state.retarget ? 'result' : 'input' });
    return msg.bytes;
  }

  // The mesh the view shows: the resize result if there is one, else the input (null without a model).
  // Records its counts as `state.shown`.
  present() {
    const { model, retarget } = this.state;
    if (!model) return null;
    const mesh = retarget ? retarget.mesh : model.inputMesh;
    this.state.shown = countsOf(mesh);
    return mesh;
  }

  // Shows `message` as the error and enters the error state.
  fail(message) {
    this.state.error = message;
    this.#hooks.error(message);
    this.#setStatus('error');
  }

  #setStatus(s) {
    if (s !== this.state.status || !this.statusHistory.length) this.statusHistory.push(s);
    this.state.status = s;
    this.#hooks.status(s);
  }

  #clearError() {
    this.state.error = '';
    this.#hooks.error('');
  }

  #progress(stage, fraction) {
    ++this.progressReports;
    this.#hooks.progress(stage, fraction);
  }

  async #analyze(generation) {
    this.#setStatus('analyzing');
    this.#clearError();
    Object.assign(this.state, { retarget: null, analysis: null, extras: null, promoted: [] });
    this.#progress('sampling', 0);
    try {
      const { descriptor, matcher, detector, labelSpace, seamEnergy } = this.#policy();
      const prepare = labelSpace ? { labelSpace, seamEnergy } : undefined;  // the first resize's retargeter
      const msg = await this.#client.request('analyze', { descriptor, matcher, detector, ...(prepare && { prepare }) },
                                             { onProgress: (stage, f) => this.#progress(stage, f) });
      if (generation !== this.#generation) return;
      this.#hooks.progress(null);
      Object.assign(this.state, { analysis: msg.analysis, extras: msg.extras, analysisMs: msg.ms });
      this.present();
      this.#hooks.analysis(msg.analysis);
      if (msg.analysis.principal_offsets.length === 0) return this.fail(noRepetitionMessage(msg.analysis));
      this.#setStatus('ready');
    } catch (e) {
      if (e.cancelled || generation !== this.#generation) return;
      this.#hooks.progress(null);
      this.fail(`Analysis failed: ${e.message}`);
      this.#hooks.redraw();
    }
  }

  // Forgets the queued and the running resize (their answers will be stale) and rejects their promises.
  #dropResizes(message) {
    for (const job of [this.#inFlight, this.#next]) if (job) for (const w of job.waiters) w.reject(new Error(message));
    this.#inFlight = this.#next = null;
  }

  #dropPromotions(message) {
    for (const job of [this.#promoting, this.#nextPromotion]) if (job) for (const w of job.waiters) w.reject(new Error(message));
    this.#promoting = this.#nextPromotion = null;
  }

  async #pumpPromotion() {
    if (this.#promoting || !this.#nextPromotion) return;
    const job = this.#nextPromotion;
    this.#nextPromotion = null;
    this.#promoting = job;
    let generation = this.#generation;
    try {
      const { labelSpace, seamEnergy } = this.#policy();
      const prepare = labelSpace ? { labelSpace, seamEnergy } : undefined;
      const msg = await this.#client.request('promote', { offsets: job.offsets, ...(prepare && { prepare }) });
      if (generation !== this.#generation) return;
      this.#promoting = null;
      generation = ++this.#generation;  // a result still on its way to the view is about the old offsets
      this.#dropResizes('the principal offsets changed');
      Object.assign(this.state, { analysis: msg.analysis, extras: msg.extras, promoted: job.offsets, retarget: null });
      this.present();
      this.#hooks.analysis(msg.analysis);
      if (msg.analysis.principal_offsets.length === 0) this.fail(noRepetitionMessage(msg.analysis));
      else {
        this.#clearError();
        this.#setStatus('ready');
      }
      for (const w of job.waiters) w.resolve(msg.analysis);
    } catch (e) {
      if (e.cancelled || generation !== this.#generation) return;
      this.#promoting = null;
      this.fail(`Could not make ${job.offsets.length ? 'those offsets' : 'the detected offsets'} principal: ${e.message}`);
      for (const w of job.waiters) w.reject(new Error(e.message));
    } finally {
      if (generation === this.#generation) {
        this.#pumpPromotion();
        this.#pump();
      }
    }
  }

  async #pump() {
    if (this.#inFlight || this.#promoting || !this.#next || !this.state.analysis) return;
    const job = this.#next;
    this.#next = null;
    this.#inFlight = job;
    const generation = this.#generation;
    try {
      const msg = await this.#client.request('retarget', { steps: job.steps, size: job.size, labelSpace: job.labelSpace,
                                                           pivot: job.pivot, seamEnergy: job.seamEnergy });
      if (generation !== this.#generation) return;
      const steps = job.steps || [0, 1, 2].map((i) => msg.result.report.steps_principal[i] || 0);
      const retarget = { steps, size: job.size, labelSpace: job.labelSpace, pivot: job.pivot, seamEnergy: job.seamEnergy,
                         result: msg.result, mesh: msg.mesh, ms: msg.ms,
                         pageMs: null };
      this.state.retarget = retarget;
      this.present();
      await this.#hooks.result(retarget);
      if (generation !== this.#generation) return;
      retarget.pageMs = this.#now() - job.t0;
      this.resizeTimings.push(retarget.pageMs);
      this.#hooks.timed(retarget);
      if (this.state.status === 'error' && this.state.analysis.principal_offsets.length) {
        this.#clearError();
        this.#setStatus('ready');
      }
      for (const w of job.waiters) w.resolve({ ...this.state.shown, steps, ms: retarget.pageMs });
    } catch (e) {
      if (e.cancelled || generation !== this.#generation) return;
      this.fail(`Resize failed: ${e.message}`);
      for (const w of job.waiters) w.reject(new Error(e.message));
    } finally {
      if (generation === this.#generation) {
        this.#inFlight = null;
        this.#pump();
      }
    }
  }
}
