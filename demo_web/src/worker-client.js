// worker-client.js - the page's side of the ./worker.js protocol: requests with ids, answers as promises.
//
//   const client = new WorkerClient(() => new Worker(new URL('./worker.js', import.meta.url), { type: 'module' }));
//   client.restart();                                   // (re)creates the worker; needed before the first request
//   const msg = await client.request('analyze', { descriptor, matcher },
//                                    { onProgress: (stage, fraction) => ..., transfer: [] });
//
// request(type, payload, {onProgress, transfer}) posts {type, id, ...payload} (the ArrayBuffers in `transfer`
// are moved, not copied) and resolves with the worker's answer carrying that id; {type: 'progress'} messages
// for it go to onProgress and leave it pending. An {type: 'error'} answer rejects with an Error whose
// `.code` is the worker's code ('internal' when the worker itself failed to start or died: every pending request
// rejects, and the next request replaces the worker first).
// restart() terminates the worker, which is the only way to stop a running analysis: every pending request
// rejects with an Error whose `.cancelled` is true. No DOM: the factory passed in makes the worker (a fake
// object with postMessage/terminate/onmessage/onerror in the node tests).

export function cancelledError() {
  return Object.assign(new Error('cancelled'), { cancelled: true });
}

export class WorkerClient {
  #create;
  #worker = null;
  #broken = false;  // the worker reported an error of its own (it failed to start or died)
  #nextId = 1;
  #pending = new Map();  // id -> {resolve, reject, onProgress}

  constructor(createWorker) {
    this.#create = createWorker;
  }

  restart() {
    if (this.#worker) this.#worker.terminate();
    this.#rejectAll(cancelledError);
    const worker = this.#create();
    worker.onmessage = (e) => this.#receive(e.data);
    worker.onerror = (e) => {
      e.preventDefault();
      this.#broken = true;
      const message = `the restitch worker stopped (${e.message || 'see the console'})`;
      this.#rejectAll(() => Object.assign(new Error(message), { code: 'internal' }));
    };
    this.#worker = worker;
    this.#broken = false;
  }

  request(type, payload = {}, { onProgress, transfer = [] } = {}) {
    if (this.#broken) this.restart();  // a worker that died is replaced, so the next file loads
    const id = this.#nextId++;
    return new Promise((resolve, reject) => {
      this.#pending.set(id, { resolve, reject, onProgress });
      this.#worker.postMessage({ type, id, ...payload }, transfer);
    });
  }

  #receive(msg) {
    const p = this.#pending.get(msg.id);
    if (!p) return;
    if (msg.type === 'progress') {
      if (p.onProgress) p.onProgress(msg.stage, msg.fraction);
      return;
    }
    this.#pending.delete(msg.id);
    if (msg.type === 'error') p.reject(Object.assign(new Error(msg.message), { code: msg.code }));
    else p.resolve(msg);
  }

  #rejectAll(makeError) {
    const pending = [...this.#pending.values()];
    this.#pending.clear();
    for (const p of pending) p.reject(makeError());
  }
}
