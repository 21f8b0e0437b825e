// Node tests of the page's worker client (src/worker-client.js) with a fake Worker: ids matched to answers,
// progress, errors with their code, transfer lists, and restarts cancelling what was pending; and the page's
// Session over it, answered by hand the way ../src/worker.js answers (the promote flow).
// Run: node --test demo_web/tests/worker-client.test.mjs (tests/run.sh runs it with the other node tests).
import test from 'node:test';
import assert from 'node:assert/strict';
import { WorkerClient } from '../src/worker-client.js';
import { Session } from '../src/session.js';
import { trapAnswer, memoryLimitPages } from '../src/trap.js';

class FakeWorker {
  posted = [];  // [message, transfer]
  terminated = false;
  postMessage(message, transfer) { this.posted.push([message, transfer]); }
  terminate() { this.terminated = true; }
  reply(data) { this.onmessage({ data }); }
}

function makeClient() {
  const workers = [];
  const client = new WorkerClient(() => { const w = new FakeWorker(); workers.push(w); return w; });
  client.restart();
  return { client, workers, worker: () => workers.at(-1) };
}

const state = async (promise) => {
  let out = 'pending';
  promise.then((v) => { out = ['fulfilled', v]; }, (e) => { out = ['rejected', e]; });
  await new Promise((r) => setImmediate(r));
  return out;
};

test('requests carry ids and their payload; answers resolve the request with their id, in any order', async () => {
  const { client, worker } = makeClient();
  const bytes = new ArrayBuffer(4);
  const a = client.request('load', { file: { name: 'a.glb', bytes } }, { transfer: [bytes] });
  const b = client.request('catalog');
  const [[ma, ta], [mb, tb]] = worker().posted;
  assert.equal(ma.type, 'load');
  assert.equal(ma.file.name, 'a.glb');
  assert.deepEqual(ta, [bytes], 'the transfer list is handed to postMessage');
  assert.deepEqual(tb, []);
  assert.notEqual(ma.id, mb.id);
  worker().reply({ type: 'catalog', id: mb.id, samples: [] });
  assert.equal(await state(a), 'pending');
  assert.deepEqual((await b).samples, []);
  worker().reply({ type: 'loaded', id: ma.id, info: { triangles: 4 } });
  assert.equal((await a).info.triangles, 4);
});

test('progress goes to onProgress and leaves the request pending; an error answer rejects with its code', async () => {
  const { client, worker } = makeClient();
  const seen = [];
  const p = client.request('analyze', {}, { onProgress: (stage, f) => seen.push([stage, f]) });
  const { id } = worker().posted[0][0];
  worker().reply({ type: 'progress', id, stage: 'matching', fraction: 0.25 });
  worker().reply({ type: 'progress', id: id + 100, stage: 'lattice', fraction: 1 });  // someone else's: ignored
  assert.deepEqual(seen, [['matching', 0.25]]);
  assert.equal(await state(p), 'pending');
  worker().reply({ type: 'error', id, code: 'no_repetition', message: 'nothing repeats' });
  const r = await state(p);
  assert.equal(r[0], 'rejected');
  assert.equal(r[1].message, 'nothing repeats');
  assert.equal(r[1].code, 'no_repetition');
});

test('restart terminates the worker, cancels what was pending and sends later requests to the new one', async () => {
  const { client, workers, worker } = makeClient();
  const p = client.request('analyze');
  client.restart();
  assert.equal(workers.length, 2);
  assert.equal(workers[0].terminated, true);
  const r = await state(p);
  assert.equal(r[0], 'rejected');
  assert.equal(r[1].cancelled, true);
  const q = client.request('catalog');
  assert.equal(workers[0].posted.length, 1);
  assert.equal(worker().posted.length, 1);
  worker().reply({ type: 'catalog', id: worker().posted[0][0].id });
  assert.equal((await q).type, 'catalog');
});

test('a worker that fails to start rejects what was pending with code internal', async () => {
  const { client, worker } = makeClient();
  const p = client.request('catalog');
  let prevented = false;
  worker().onerror({ message: 'SyntaxError in worker.js', preventDefault: () => { prevented = true; } });
  const r = await state(p);
  assert.equal(r[0], 'rejected');
  assert.equal(r[1].code, 'internal');
  assert.match(r[1].message, /worker stopped \(SyntaxError in worker\.js\)/);
  assert.ok(prevented);
});

test('after the worker died, the next request goes to a new worker (the next file loads)', async () => {
  const { client, workers, worker } = makeClient();
  const p = client.request('analyze');
  const dead = worker();
  dead.onerror({ message: 'out of memory', preventDefault: () => {} });
  assert.equal((await state(p))[0], 'rejected');
  const q = client.request('load', { sample: { name: 'fence' } });
  assert.equal(workers.length, 2, 'a new worker was made');
  assert.ok(dead.terminated, 'the dead one was terminated');
  assert.equal(worker().posted.length, 1);
  assert.equal(worker().posted[0][0].type, 'load');
  worker().reply({ type: 'loaded', id: worker().posted[0][0].id });
  assert.equal((await q).type, 'loaded');
  client.request('catalog');
  assert.equal(workers.length, 2, 'a working worker is kept');
});

test('trap answers: an uncaught C++ exception (a number) is out_of_memory, anything else internal; ?memory in pages', () => {
  const oom = trapAnswer(5251384, 'analyze', 64);
  assert.equal(oom.code, 'out_of_memory');
  assert.match(oom.message, /ran out of memory while analysing the model \(the page can use at most 64 MB/);
  assert.match(oom.message, /open it or another one again/);
  const bug = trapAnswer(new WebAssembly.RuntimeError('memory access out of bounds'), 'retarget');
  assert.equal(bug.code, 'internal');
  assert.match(bug.message, /stopped unexpectedly while resizing \(memory access out of bounds\); this is a bug/);
  const aborted = new WebAssembly.RuntimeError('Aborted(). Build with -s ASSERTIONS=1 for more info.');
  assert.equal(trapAnswer(aborted, 'load').code, 'out_of_memory', 'what a failed allocation gives (measured)');
  assert.equal(memoryLimitPages(null), 0);
  assert.equal(memoryLimitPages('abc'), 0);
  assert.equal(memoryLimitPages('100'), 1600);
  assert.equal(memoryLimitPages('1'), 64 * 16, 'at least 64 MB');
  assert.equal(memoryLimitPages('99999'), 2048 * 16, 'at most the module maximum');
});

test('a Session over the client: promote posts the offsets, a refusal changes nothing, the answer replaces the analysis', async () => {
  const { client, worker } = makeClient();
  const session = new Session(client, { now: () => 0 });
  const last = () => worker().posted.at(-1)[0];
  const tick = () => new Promise((r) => setImmediate(r));
  const mesh = { positions: new Float32Array(9), indices: new Uint32Array(3), groups: [] };
  session.load({ sample: { name: 'pin_header', params: { pins: 2 } } });
  worker().reply({ type: 'loaded', id: last().id, info: { triangles: 1, bbox_min: [0, 0, 0], bbox_max: [1, 1, 1] }, mesh });
  await tick();
  const detected = { principal_offsets: [], resizable: [false, false, false], lattice_cells: [1, 1, 1],
                     candidates: [{ offset: [2.54, 0, 0], copies: 2, reason: 'pair', dominant: 0 }] };
  worker().reply({ type: 'analyzed', id: last().id, analysis: detected, extras: {}, ms: 1 });
  await tick();
  assert.equal(session.state.status, 'error');

  const refused = state(session.promote([[0, 0, 0]]));
  assert.equal(last().type, 'promote');
  assert.deepEqual(last().offsets, [[0, 0, 0]]);
  worker().reply({ type: 'error', id: last().id, request: 'promote', code: 'invalid_argument',
                   message: 'offset 1 is zero or not finite' });
  const r = await refused;
  assert.equal(r[0], 'rejected');
  assert.equal(r[1].message, 'offset 1 is zero or not finite');
  assert.equal(session.state.analysis, detected, 'the analysis is unchanged');
  assert.deepEqual(session.state.promoted, []);

  const done = state(session.promote([[2.54, 0, 0]]));
  const next = { ...detected, principal_offsets: [[2.54, 0, 0]], resizable: [true, false, false] };
  worker().reply({ type: 'promoted', id: last().id, offsets: last().offsets, analysis: next, extras: {}, ms: 2 });
  assert.deepEqual(await done, ['fulfilled', next]);
  assert.equal(session.state.analysis, next);
  assert.equal(session.state.status, 'ready');
  session.resize([1, 0, 0], 'lattice');
  assert.deepEqual([last().type, last().steps], ['retarget', [1, 0, 0]], 'resizes go out again');
});
