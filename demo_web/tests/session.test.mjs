// Node tests of the page's state machine (src/session.js) against a fake worker client whose answers the tests
// give by hand, in any order: latest-wins resizing, stale load and analysis answers dropped, worker errors
// shown as the error state. No WebAssembly, no browser.
// Run: node --test demo_web/tests/session.test.mjs (tests/run.sh runs it with the other node tests).
import test from 'node:test';
import assert from 'node:assert/strict';
import { Session } from '../src/session.js';
import { cancelledError } from '../src/worker-client.js';

// Lets the session react to an answer: its promise callbacks and the fake view's (a macrotask, as a frame is).
async function flush() {
  for (let i = 0; i < 10; ++i) await new Promise((resolve) => setImmediate(resolve));
}

// A worker client whose requests wait until the test answers them.
class FakeClient {
  requests = [];   // {type, payload, options, resolve, reject, settled}
  restarts = 0;
  cancelOnRestart = true;  // a real restart cancels what was pending; false: the old answers still arrive

  restart() {
    ++this.restarts;
    if (!this.cancelOnRestart) return;
    for (const r of this.open()) this.#settle(r, 'reject', cancelledError());
  }

  request(type, payload = {}, options = {}) {
    return new Promise((resolve, reject) => {
      this.requests.push({ type, payload, options, resolve, reject, settled: false });
    });
  }

  open(type) { return this.requests.filter((r) => !r.settled && (!type || r.type === type)); }
  sent(type) { return this.requests.filter((r) => r.type === type); }

  // Answers the oldest open request of `type` (or the request given) and lets the session react.
  async answer(which, msg) {
    this.#settle(this.#pick(which), 'resolve', msg);
    await flush();
  }

  async fail(which, message, code = 'internal') {
    this.#settle(this.#pick(which), 'reject', Object.assign(new Error(message), { code }));
    await flush();
  }

  #pick(which) {
    const r = typeof which === 'string' ? this.open(which)[0] : which;
    assert.ok(r && !r.settled, `no open ${typeof which === 'string' ? which : 'such'} request`);
    return r;
  }

  #settle(r, how, value) {
    r.settled = true;
    r[how](value);
  }
}

const meshOf = (triangles) => ({ positions: new Float32Array(9 * triangles), indices: new Uint32Array(3 * triangles),
                                 groups: [] });
const loaded = (triangles = 4) => ({ type: 'loaded', info: { triangles, bbox_min: [0, 0, 0], bbox_max: [1, 1, 1],
                                                             warnings: [] }, mesh: meshOf(triangles), glb: null });
const analysed = (offsets = [[0.4, 0, 0]], candidates = []) => ({
  type: 'analyzed', ms: 12,
  analysis: { principal_offsets: offsets, resizable: [offsets.length > 0, false, false], lattice_cells: [4, 1, 1],
              candidates },
  extras: { match_offsets: new Float32Array(0), dominant_normalized: [] },
});
const promoted = (offsets, principal = offsets) => ({ ...analysed(principal), type: 'promoted', offsets });
// The 2-pin header: no principal offset, its pitch a pair candidate.
const pitch = [2.54, 0, 0];
const pinHeader = () => analysed([], [{ offset: pitch, copies: 2, reason: 'pair', dominant: 0 }]);
const retargeted = (steps, triangles) => ({ type: 'retargeted', steps, ms: 3, mesh: meshOf(triangles),
                                             result: { report: { steps_principal: steps.slice(0, 1) } } });

// A session whose hooks record what they were told, plus its fake client.
function makeSession(policy = { descriptor: 'shot', matcher: 'reduced', detector: 'histogram' }) {
  const client = new FakeClient();
  const calls = [];
  const record = (name) => (...args) => { calls.push([name, ...args]); };
  const hooks = Object.fromEntries(['status', 'error', 'loading', 'model', 'progress', 'analysis', 'timed', 'redraw']
    .map((name) => [name, record(name)]));
  hooks.result = async (retarget) => {
    calls.push(['result', retarget.steps]);
    await new Promise((resolve) => setImmediate(resolve));  // the page waits for a frame here
  };
  let t = 0;
  const session = new Session(client, { hooks, policy: () => ({ ...policy }), now: () => (t += 5) });
  return { session, client, calls, named: (name) => calls.filter((c) => c[0] === name) };
}

// Loads a sample and answers until the session is ready.
async function readySession() {
  const s = makeSession();
  s.session.load({ sample: { name: 'bookshelf', params: {} } });
  await s.client.answer('load', loaded());
  await s.client.answer('analyze', analysed());
  assert.equal(s.session.state.status, 'ready');
  return s;
}

// Watches a promise from the start (so a rejection is handled): {state: 'pending' | 'fulfilled' | 'rejected', value}.
function watch(promise) {
  const w = { state: 'pending', value: undefined };
  promise.then((value) => Object.assign(w, { state: 'fulfilled', value }),
               (value) => Object.assign(w, { state: 'rejected', value }));
  return w;
}

// What a promise has resolved with once the session is idle; fails (rather than hangs) while it is pending.
async function resolved(promise) {
  const w = watch(promise);
  await flush();
  if (w.state === 'rejected') throw w.value;
  assert.equal(w.state, 'fulfilled', 'the promise is still pending');
  return w.value;
}

test('a load goes loading -> analyzing -> ready, with the policy and the progress passed on', async () => {
  const { session, client, named } = makeSession();
  const done = session.load({ sample: { name: 'bookshelf', params: {} } });
  assert.equal(session.state.status, 'loading');
  assert.deepEqual(named('loading'), [['loading', 'sample: bookshelf']]);
  await client.answer('load', loaded(4));
  assert.equal(session.state.status, 'analyzing');
  assert.deepEqual(session.state.shown, { vertices: 12, triangles: 4 });
  const req = client.open('analyze')[0];
  assert.deepEqual(req.payload, { descriptor: 'shot', matcher: 'reduced', detector: 'histogram' });
  req.options.onProgress('matching', 0.5);
  assert.deepEqual(named('progress').at(-1), ['progress', 'matching', 0.5]);
  await client.answer(req, analysed());
  await resolved(done);
  assert.equal(session.state.status, 'ready');
  assert.deepEqual(session.statusHistory, ['loading', 'analyzing', 'ready']);
  assert.equal(session.progressReports, 2, 'the first (sampling, 0) and the one from the worker');
  assert.deepEqual(named('progress').at(-1), ['progress', null], 'the progress bar is hidden at the end');
  assert.equal(session.state.analysisMs, 12);
});

test('with the resize policies known, the analysis asks the worker to prepare the first resize', async () => {
  const { session, client } = makeSession({ descriptor: 'shot', matcher: 'brute_force', detector: 'histogram',
                                            labelSpace: 'lattice', seamEnergy: 'geometry' });
  session.load({ sample: { name: 'bookshelf', params: {} } });
  await client.answer('load', loaded(4));
  const req = client.open('analyze')[0];
  assert.deepEqual(req.payload, { descriptor: 'shot', matcher: 'brute_force', detector: 'histogram',
                                  prepare: { labelSpace: 'lattice', seamEnergy: 'geometry' } });
});

test('latest wins: of three rapid resizes the first runs, the middle is superseded, the last runs', async () => {
  const { session, client, named } = await readySession();
  const first = watch(session.resize([1, 0, 0], 'lattice'));
  const middle = watch(session.resize([2, 0, 0], 'lattice'));
  const last = session.resize([3, 0, 0], 'lattice');
  await flush();
  assert.deepEqual(client.sent('retarget').map((r) => r.payload.steps), [[1, 0, 0]], 'one retarget in flight at a time');
  assert.equal(middle.state, 'rejected', 'the middle one settles as soon as the last replaces it');
  assert.equal(middle.value.superseded, true, middle.value.message);
  assert.equal(first.state, 'pending');

  await client.answer('retarget', retargeted([1, 0, 0], 10));
  assert.equal(first.state, 'fulfilled');
  assert.deepEqual(first.value, { vertices: 30, triangles: 10, steps: [1, 0, 0], ms: first.value.ms });
  assert.ok(first.value.ms > 0);
  assert.deepEqual(client.sent('retarget').map((r) => r.payload.steps), [[1, 0, 0], [3, 0, 0]],
                   'the middle request never reaches the worker; the last follows the first');

  await client.answer('retarget', retargeted([3, 0, 0], 16));
  const shown = await resolved(last);
  assert.deepEqual(shown, { vertices: 48, triangles: 16, steps: [3, 0, 0], ms: shown.ms });
  assert.deepEqual(session.state.retarget.steps, [3, 0, 0]);
  assert.deepEqual(session.state.shown, { vertices: 48, triangles: 16 });
  assert.deepEqual(named('result').map((c) => c[1]), [[1, 0, 0], [3, 0, 0]], 'the view was given the first and the last');
  assert.equal(session.resizeTimings.length, 2);
  assert.equal(client.sent('retarget').length, 2);
  assert.equal(session.state.status, 'ready');
});

test('a repeated request for the queued steps runs once and settles both promises', async () => {
  const { session, client } = await readySession();
  session.resize([1, 0, 0], 'lattice');
  const p1 = session.resize([2, 0, 0], 'lattice');
  const p2 = session.resize([2, 0, 0], 'lattice');
  await client.answer('retarget', retargeted([1, 0, 0], 10));
  await client.answer('retarget', retargeted([2, 0, 0], 12));
  assert.equal((await resolved(p1)).triangles, 12);
  assert.equal((await resolved(p2)).triangles, 12);
  assert.equal(client.sent('retarget').length, 2);
});

test('the pivot goes to the worker with the steps; the same steps about another pivot are a new request', async () => {
  const { session, client } = await readySession();
  const first = session.resize([1, 0, 0], 'lattice');
  await client.answer('retarget', retargeted([1, 0, 0], 10));
  await resolved(first);
  assert.equal(client.sent('retarget')[0].payload.pivot, 'origin', 'the default pivot is the origin');
  assert.equal(session.state.retarget.pivot, 'origin');
  const max = session.resize([1, 0, 0], 'lattice', 'max');
  await client.answer('retarget', retargeted([1, 0, 0], 10));
  await resolved(max);
  assert.deepEqual(client.sent('retarget').map((r) => r.payload.pivot), ['origin', 'max']);
  assert.equal(session.state.retarget.pivot, 'max');
});

test('the seam energy goes to the worker with the steps; another energy is a new request', async () => {
  const { session, client } = await readySession();
  const first = session.resize([1, 0, 0], 'lattice');
  await client.answer('retarget', retargeted([1, 0, 0], 10));
  await resolved(first);
  assert.equal(client.sent('retarget')[0].payload.seamEnergy, 'descriptor', 'the default seam energy');
  const geo = session.resize([1, 0, 0], 'lattice', 'origin', 'geometry');
  await client.answer('retarget', retargeted([1, 0, 0], 10));
  await resolved(geo);
  assert.deepEqual(client.sent('retarget').map((r) => r.payload.seamEnergy), ['descriptor', 'geometry']);
  assert.equal(session.state.retarget.seamEnergy, 'geometry');
});

test('a size goes to the worker instead of steps; the result says which whole repeats it took; a size and steps are different requests', async () => {
  const { session, client } = await readySession();
  const bySize = session.resize({ size: [2.3, 0, 0] }, 'lattice', 'min');
  const bySteps = session.resize([2, 0, 0], 'lattice', 'min');  // the same repeats, but not the same request
  const sent = client.sent('retarget')[0].payload;
  assert.deepEqual(sent.size, [2.3, 0, 0]);
  assert.equal(sent.steps, null);
  assert.equal(sent.pivot, 'min');
  await client.answer('retarget', retargeted([2, 0, 0], 12));
  const r = await resolved(bySize);
  assert.deepEqual(r.steps, [2, 0, 0], 'the steps come from the report');
  assert.deepEqual(session.state.retarget.steps, [2, 0, 0]);
  assert.deepEqual(session.state.retarget.size, [2.3, 0, 0]);
  assert.equal(client.sent('retarget').length, 2, 'the steps request is sent after the size one');
  assert.deepEqual(client.sent('retarget')[1].payload.steps, [2, 0, 0]);
  await client.answer('retarget', retargeted([2, 0, 0], 12));
  await resolved(bySteps);
});

test('a stale load answer is ignored after a newer load, whichever arrives first', async () => {
  for (const staleFirst of [true, false]) {
    const { session, client, named } = makeSession();
    client.cancelOnRestart = false;  // the old answer arrives anyway
    session.load({ sample: { name: 'fence', params: {} } });
    const [oldLoad] = client.open('load');
    const restarts = client.restarts;
    session.load({ file: { name: 'new.glb', bytes: new ArrayBuffer(8) } });
    assert.equal(client.restarts, restarts + 1, 'a load while loading restarts the worker');
    const [, newLoad] = client.open('load');
    assert.deepEqual(newLoad.options.transfer, [newLoad.payload.file.bytes], 'the file bytes are transferred');
    if (staleFirst) await client.answer(oldLoad, loaded(7));
    await client.answer(newLoad, loaded(4));
    if (!staleFirst) await client.answer(oldLoad, loaded(7));
    assert.equal(session.state.model.name, 'new.glb');
    assert.equal(session.state.model.info.triangles, 4);
    assert.deepEqual(named('model').map((c) => c[1].name), ['new.glb'], 'only the newer model was shown');
    assert.equal(client.sent('analyze').length, 1, 'only the newer model is analysed');
    await client.answer('analyze', analysed());
    assert.equal(session.state.status, 'ready');
    assert.equal(session.state.model.name, 'new.glb');
  }
});

test('a cancelled load (worker restarted) neither errors nor changes the state', async () => {
  const { session, client } = makeSession();
  const old = session.load({ sample: { name: 'fence', params: {} } });
  session.load({ sample: { name: 'bookshelf', params: {} } });
  await resolved(old);
  assert.equal(session.state.error, '');
  assert.equal(session.state.status, 'loading');
  await client.answer('load', loaded());
  await client.answer('analyze', analysed());
  assert.equal(session.state.model.name, 'sample: bookshelf');
  assert.equal(session.state.status, 'ready');
});

test('a stale analysis answer is dropped after a re-analysis', async () => {
  const { session, client, named } = makeSession();
  session.load({ sample: { name: 'bookshelf', params: {} } });
  await client.answer('load', loaded());
  const [oldAnalysis] = client.open('analyze');
  session.reanalyze();
  await client.answer(oldAnalysis, analysed([[9, 9, 9]]));
  assert.equal(session.state.analysis, null, 'the old analysis is not taken');
  assert.equal(session.state.status, 'analyzing');
  assert.equal(named('analysis').length, 0);
  await client.answer('analyze', analysed([[0.4, 0, 0]]));
  assert.deepEqual(session.state.analysis.principal_offsets, [[0.4, 0, 0]]);
  assert.equal(session.state.status, 'ready');
});

test('a new load rejects the pending resizes and drops the answer of the one in flight', async () => {
  const { session, client, named } = await readySession();
  const running = watch(session.resize([1, 0, 0], 'lattice'));
  const queued = watch(session.resize([2, 0, 0], 'lattice'));
  session.load({ sample: { name: 'fence', params: {} } });
  await flush();
  assert.equal(running.state, 'rejected');
  assert.match(running.value.message, /new model/);
  assert.equal(queued.state, 'rejected');
  assert.match(queued.value.message, /new model/);
  await client.answer('retarget', retargeted([1, 0, 0], 10));
  assert.equal(session.state.retarget, null, 'the old model\'s result is not shown');
  assert.equal(named('result').length, 0);
  assert.equal(client.sent('retarget').length, 1);
});

test('a worker error during a resize is shown as the error state, and a later resize recovers', async () => {
  const { session, client, named } = await readySession();
  const p = watch(session.resize([1, 0, 0], 'lattice'));
  await client.fail('retarget', 'the shelf cannot shrink that far', 'invalid_argument');
  assert.equal(p.state, 'rejected');
  assert.equal(p.value.message, 'the shelf cannot shrink that far');
  assert.equal(session.state.status, 'error');
  assert.equal(session.state.error, 'Resize failed: the shelf cannot shrink that far');
  assert.deepEqual(named('error').at(-1), ['error', 'Resize failed: the shelf cannot shrink that far']);
  const next = session.resize([2, 0, 0], 'lattice');
  assert.equal(client.open('retarget').length, 1, 'the queue goes on after a failure');
  await client.answer('retarget', retargeted([2, 0, 0], 12));
  assert.equal((await resolved(next)).triangles, 12);
  assert.equal(session.state.status, 'ready');
  assert.equal(session.state.error, '');
});

test('worker errors while loading or analysing are shown in words', async () => {
  {
    const { session, client, named } = makeSession();
    const done = session.load({ sample: { name: 'bookshelf', params: {} } });
    await client.fail('load', 'not a glTF file');
    await resolved(done);
    assert.equal(session.state.status, 'error');
    assert.equal(session.state.error, 'Could not open sample: bookshelf: not a glTF file');
    assert.equal(named('redraw').length, 1);
  }
  {
    const { session, client, named } = makeSession();
    session.load({ sample: { name: 'bookshelf', params: {} } });
    await client.answer('load', loaded());
    await client.fail('analyze', 'out of memory');
    assert.equal(session.state.status, 'error');
    assert.equal(session.state.error, 'Analysis failed: out of memory');
    assert.deepEqual(named('progress').at(-1), ['progress', null]);
    assert.deepEqual(session.statusHistory, ['loading', 'analyzing', 'error']);
  }
  {
    const { session, client } = makeSession();
    session.load({ sample: { name: 'bookshelf', params: {} } });
    await client.answer('load', loaded());
    await client.answer('analyze', analysed([]));
    assert.equal(session.state.status, 'error');
    assert.match(session.state.error, /^No repetition found/);
  }
});

test('start asks for the catalog; a failure is the error state', async () => {
  const { session, client } = makeSession();
  const started = session.start();
  assert.equal(client.restarts, 1, 'start creates the worker');
  await client.answer('catalog', { samples: [{ name: 'bookshelf', units: 'm' }], policies: { descriptors: ['shot'] } });
  assert.equal((await resolved(started)).samples[0].name, 'bookshelf');
  assert.deepEqual(session.state.catalog, [{ name: 'bookshelf', units: 'm' }]);

  const other = makeSession();
  const failed = other.session.start();
  await other.client.fail('catalog', 'the WebAssembly module did not load');
  assert.equal(await resolved(failed), null);
  assert.equal(other.session.state.status, 'error');
  assert.match(other.session.state.error, /could not start: the WebAssembly module did not load/);
});

test('a model opened while the page starts waits for the catalog, then loads; the start never fails', async () => {
  const catalog = { samples: [{ name: 'bookshelf', units: 'm' }], policies: { descriptors: ['shot'] } };
  // Opened before the catalog came: the load waits, the worker is not restarted under the start.
  const { session, client } = makeSession();
  const started = session.start();
  assert.equal(session.opened, false);
  const opening = session.load({ file: { name: 'a.glb', bytes: new ArrayBuffer(8) } });
  await flush();
  assert.equal(session.opened, true);
  assert.equal(client.sent('load').length, 0, 'the file waits for the catalog');
  assert.equal(client.open('catalog').length, 1, 'the catalog request was not cancelled');
  await client.answer('catalog', catalog);
  assert.equal((await resolved(started)).samples[0].name, 'bookshelf');
  assert.equal(client.sent('load').length, 1);
  await client.answer('load', loaded());
  await client.answer('analyze', analysed());
  await resolved(opening);
  assert.equal(session.state.status, 'ready');
  assert.equal(session.state.error, '');
  // Two files during the start: only the second loads.
  const two = makeSession();
  const twoStarted = two.session.start();
  two.session.load({ file: { name: 'first.glb', bytes: new ArrayBuffer(8) } });
  two.session.load({ file: { name: 'second.glb', bytes: new ArrayBuffer(8) } });
  await two.client.answer('catalog', catalog);
  await resolved(twoStarted);
  assert.deepEqual(two.client.sent('load').map((r) => r.payload.file.name), ['second.glb']);
  // The worker restarted under the catalog request (the old page's race): asked again, not failed.
  const third = makeSession();
  const thirdStarted = third.session.start();
  third.client.restart();
  await flush();
  assert.equal(third.client.sent('catalog').length, 2, 'asked the new worker');
  await third.client.answer('catalog', catalog);
  assert.equal((await resolved(thirdStarted)).samples.length, 1);
  assert.notEqual(third.session.state.status, 'error');
});

test('a failed start can be tried again; a model opened meanwhile loads once a start succeeds', async () => {
  const catalog = { samples: [{ name: 'bookshelf', units: 'm' }], policies: { descriptors: ['shot'] } };
  const { session, client } = makeSession();
  const first = session.start();
  await client.fail('catalog', 'the WebAssembly module did not load');
  assert.equal(await resolved(first), null);
  assert.equal(session.state.startFailed, true);
  assert.equal(session.state.status, 'error');
  // A file opened now waits: no worker to load it with.
  const opening = session.load({ file: { name: 'a.glb', bytes: new ArrayBuffer(8) } });
  await flush();
  await resolved(opening);
  assert.equal(client.sent('load').length, 0);
  assert.equal(session.opened, true);
  // Tried again: the error goes, the worker is created anew, and the file loads once the catalog is in.
  const second = session.start();
  assert.equal(session.state.startFailed, false);
  assert.equal(session.state.error, '');
  assert.equal(session.state.status, 'loading');
  assert.equal(client.restarts, 2);
  await client.answer('catalog', catalog);
  assert.equal((await resolved(second)).samples.length, 1);
  assert.deepEqual(client.sent('load').map((r) => r.payload.file.name), ['a.glb']);
  await client.answer('load', loaded());
  await client.answer('analyze', analysed());
  assert.equal(session.state.status, 'ready');
  // A start that fails again stays failed, and says so again.
  const { session: again, client: c2 } = makeSession();
  again.start();
  await c2.fail('catalog', 'out of memory');
  again.start();
  await c2.fail('catalog', 'out of memory');
  assert.equal(again.state.startFailed, true);
  assert.match(again.state.error, /could not start: out of memory/);
});

test('a promotion makes the 2-pin header resizable: the new analysis is shown, the sliders follow it', async () => {
  const { session, client, named } = makeSession();
  session.load({ sample: { name: 'pin_header', params: { pins: 2 } } });
  await client.answer('load', loaded());
  await client.answer('analyze', pinHeader());
  assert.equal(session.state.status, 'error');
  assert.match(session.state.error, /a candidate repeat .*Candidates/, 'the error points at the candidate');
  const before = session.state.analysis;
  const done = session.promote([pitch]);
  const [req] = client.open('promote');
  assert.deepEqual(req.payload, { offsets: [pitch] });
  assert.equal(session.state.analysis, before, 'nothing changes before the answer');
  await client.answer(req, promoted([pitch]));
  const a = await resolved(done);
  assert.deepEqual(a.principal_offsets, [pitch]);
  assert.equal(session.state.analysis, a);
  assert.deepEqual(session.state.promoted, [pitch]);
  assert.equal(session.state.status, 'ready');
  assert.equal(session.state.error, '');
  assert.deepEqual(named('analysis').map((c) => c[1].principal_offsets), [[], [pitch]], 'the sliders were rebuilt');
  const grown = session.resize([1, 0, 0], 'lattice');
  await client.answer('retarget', retargeted([1, 0, 0], 9));
  assert.equal((await resolved(grown)).triangles, 9);

  // Back to the detected offsets: none, so the error state again, the result gone.
  const back = session.promote([]);
  await client.answer('promote', { ...pinHeader(), type: 'promoted', offsets: [] });
  await resolved(back);
  assert.deepEqual(session.state.promoted, []);
  assert.equal(session.state.retarget, null, 'the input is shown again');
  assert.deepEqual(session.state.shown, { vertices: 12, triangles: 4 });
  assert.equal(session.state.status, 'error');
  assert.match(session.state.error, /candidate/);
});

test('a refused promotion rejects in words and leaves analysis, result and promoted offsets as they were', async () => {
  const { session, client, named } = await readySession();
  const r = session.resize([1, 0, 0], 'lattice');
  await client.answer('retarget', retargeted([1, 0, 0], 10));
  await resolved(r);
  const { analysis, extras, retarget, promoted: before } = session.state;
  const shown = { ...session.state.shown };
  const p = watch(session.promote([[0, 0, 0]]));
  await client.fail('promote', 'offset 1 is zero or not finite', 'invalid_argument');
  assert.equal(p.state, 'rejected');
  assert.equal(p.value.message, 'offset 1 is zero or not finite');
  assert.equal(p.value.superseded, undefined);
  assert.equal(session.state.analysis, analysis);
  assert.equal(session.state.extras, extras);
  assert.equal(session.state.retarget, retarget, 'the result is still shown');
  assert.deepEqual(session.state.shown, shown);
  assert.equal(session.state.promoted, before);
  assert.equal(named('analysis').length, 1, 'the sliders were not rebuilt');
  assert.equal(session.state.status, 'error');
  assert.match(session.state.error, /offset 1 is zero or not finite/);
  const next = session.resize([2, 0, 0], 'lattice');  // the model is still resizable, and that recovers
  await client.answer('retarget', retargeted([2, 0, 0], 12));
  assert.equal((await resolved(next)).triangles, 12);
  assert.equal(session.state.status, 'ready');
});

test('promotions are latest-wins; resizes wait for them and those asked for meanwhile are dropped', async () => {
  const { session, client, named } = await readySession();
  const running = watch(session.resize([1, 0, 0], 'lattice'));
  const A = [[0.4, 0, 0]], B = [[0, 0.3, 0]], C = [[0, 0, 0.2]];
  const first = watch(session.promote(A));
  const middle = watch(session.promote(B));
  const last = watch(session.promote(C));
  await flush();
  assert.deepEqual(client.sent('promote').map((q) => q.payload.offsets), [A], 'one promotion in flight at a time');
  assert.equal(middle.state, 'rejected');
  assert.equal(middle.value.superseded, true, middle.value.message);
  const waiting = watch(session.resize([2, 0, 0], 'lattice'));
  await flush();
  assert.equal(client.sent('retarget').length, 1, 'no resize is sent while a promotion runs');
  await client.answer('retarget', retargeted([1, 0, 0], 10));  // asked before the promotion: still shown
  assert.equal(running.state, 'fulfilled');
  await client.answer('promote', promoted(A));
  assert.equal(first.state, 'fulfilled');
  assert.deepEqual(session.state.promoted, A);
  assert.equal(session.state.retarget, null);
  assert.equal(waiting.state, 'rejected', 'its steps referred to the old offsets');
  assert.match(waiting.value.message, /principal offsets changed/);
  assert.notEqual(waiting.value.superseded, true);
  assert.deepEqual(client.sent('promote').map((q) => q.payload.offsets), [A, C]);
  await client.answer('promote', promoted(C));
  assert.equal(last.state, 'fulfilled');
  assert.deepEqual(session.state.promoted, C);
  assert.deepEqual(named('analysis').map((c) => c[1].principal_offsets), [[[0.4, 0, 0]], A, C]);
  assert.equal(client.sent('retarget').length, 1, 'the dropped resize never reached the worker');
  const after = session.resize([1, 0, 0], 'lattice');
  await client.answer('retarget', retargeted([1, 0, 0], 11));
  assert.equal((await resolved(after)).triangles, 11);
});

test('a load or a re-analysis drops a promotion in flight; no promotion before an analysis', async () => {
  const { session, client } = await readySession();
  const p = watch(session.promote([[0.4, 0, 0]]));
  const [old] = client.open('promote');
  session.load({ sample: { name: 'fence', params: {} } });
  await flush();
  assert.equal(p.state, 'rejected');
  assert.match(p.value.message, /new model/);
  await client.answer(old, promoted([[9, 9, 9]]));
  assert.equal(session.state.analysis, null, 'the old model\'s promotion is not taken');
  const early = watch(session.promote([[0.4, 0, 0]]));
  await flush();
  assert.equal(early.state, 'rejected');
  assert.match(early.value.message, /no analysed model/);
  await client.answer('load', loaded());
  await client.answer('analyze', analysed());
  assert.equal(session.state.status, 'ready');
  const q = watch(session.promote([[0.4, 0, 0]]));
  session.reanalyze();
  await flush();
  assert.equal(q.state, 'rejected');
  await client.answer('promote', promoted([[7, 7, 7]]));
  assert.equal(session.state.analysis, null, 'dropped: the model is being analysed again');
  await client.answer('analyze', analysed([[0.5, 0, 0]]));
  assert.deepEqual(session.state.analysis.principal_offsets, [[0.5, 0, 0]]);
  assert.deepEqual(session.state.promoted, []);
});
