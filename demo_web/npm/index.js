// restitch - resize man-made 3D models along their repeats, in node and in the browser.
//
//   import { init } from 'restitch';
//   const restitch = await init();                      // loads the WebAssembly module once
//   const model = restitch.open(glbBytes);              // a .glb, or a .gltf with embedded buffers
//   const analysis = model.analyze();                   // finds the repeats (blocks the thread it runs on)
//   const result = model.resize({ steps: [2, 0, 0] });  // two more repeats along the first principal offset
//   fs.writeFileSync('out.glb', result.glb());
//   model.delete();                                     // frees the model's WebAssembly memory
//
// A thin layer over the WebAssembly build of the C++ library (demo_web/bindings.cpp): `analysis` is what
// `restitch analyze --json` prints and `result.report` what `restitch resize --json` prints, so the
// command-line tool's documentation describes every field. Failures throw a RestitchError carrying the
// library's code and message. Deterministic: the same bytes and options give the same output bytes, equal
// to the native tool's with --threads 1.
//
// Environments: node 18+ (no flags), browsers (main thread or a module worker). Under node the Emscripten
// loader wants `require` and `__dirname` as globals and cannot fetch a file: URL, so `loadRestitch` sets
// them and hands it the .wasm bytes. Cost: compiling about 0.6 MB of WebAssembly, once per init.

const moduleUrl = new URL('./dist/restitch_web.mjs', import.meta.url);
const wasmUrl = new URL('./dist/restitch_web.wasm', import.meta.url);
const isNode = typeof process !== 'undefined' && !!(process.versions && process.versions.node);

/** The raw embind module (Session, version, samples, policies): what `init` wraps. */
export async function loadRestitch(options = {}) {
  const opts = { ...options };
  if (isNode) {
    const { createRequire } = await import('node:module');
    const { fileURLToPath } = await import('node:url');
    const path = await import('node:path');
    const fs = await import('node:fs');
    if (!globalThis.require) globalThis.require = createRequire(import.meta.url);
    if (!globalThis.__dirname) globalThis.__dirname = path.dirname(fileURLToPath(moduleUrl));
    // (a build linked with -sSINGLE_FILE carries the .wasm inside the .mjs and has no file beside it)
    if (!opts.wasmBinary && fs.existsSync(fileURLToPath(wasmUrl))) opts.wasmBinary = fs.readFileSync(fileURLToPath(wasmUrl));
  }
  const { default: createRestitch } = await import(moduleUrl.href);
  return createRestitch(opts);
}

/** A failure of the library: `code` is its StatusCode name ("parse_error", "no_repetition", ...). */
export class RestitchError extends Error {
  constructor(code, message) {
    super(message);
    this.name = 'RestitchError';
    this.code = code;
  }
}

function check(answer) {
  if (!answer || answer.ok !== true) {
    throw new RestitchError(answer ? answer.code : 'internal', answer ? answer.message : 'no answer from the module');
  }
  return answer;
}

/** Loads the module and returns a Restitch. Each call makes a new module instance (its own memory). */
export async function init(options = {}) {
  return new Restitch(await loadRestitch(options));
}

export class Restitch {
  constructor(module) {
    this.module = module;
  }

  /** "restitch X.Y.Z" */
  get version() {
    return this.module.version();
  }

  /** The policy names the command-line tool knows, each list with its default first. */
  policies() {
    return this.module.policies();
  }

  /** The bundled generated samples: [{name, description, units, parameters}]. */
  samples() {
    return this.module.samples();
  }

  /** A model from glTF bytes (.glb, or .gltf with data: URIs). */
  open(bytes) {
    if (!(bytes instanceof Uint8Array)) {
      if (bytes instanceof ArrayBuffer) bytes = new Uint8Array(bytes);
      else throw new RestitchError('invalid_argument', 'open() takes the bytes of a .glb or .gltf as a Uint8Array');
    }
    return this.#model((s) => s.loadGltf(bytes));
  }

  /** A model from arrays: {positions, indices, normals?, uvs?: [...], colors?, groups?: [{start, count, material?, name?}]}. */
  fromArrays(arrays) {
    return this.#model((s) => s.loadArrays(arrays));
  }

  /** A bundled sample, generated: sample('bookshelf', {columns: 5}). */
  sample(name, params = {}) {
    return this.#model((s) => s.loadSample(String(name), params));
  }

  #model(load) {
    const session = new this.module.Session();
    let info;
    try {
      info = check(load(session));
    } catch (e) {
      session.delete();
      throw e;
    }
    return new Model(this, session, info);
  }
}

const defaults = (restitch) => {
  const p = restitch.policies();
  return { descriptor: p.descriptors[0], matcher: p.matchers[0], detector: p.detectors[0], labelSpace: p.label_spaces[0], seamEnergy: p.seam_energies[0] };
};

export class Model {
  #session;
  #restitch;
  #generation = 0;

  constructor(restitch, session, info) {
    this.#restitch = restitch;
    this.#session = session;
    /** {vertices, triangles, bbox_min, bbox_max, warnings[], generators?} */
    this.info = { ...info };
    delete this.info.ok;
    /** The last analysis (restitch analyze --json), or null. */
    this.analysis = null;
  }

  #live() {
    if (!this.#session) throw new RestitchError('invalid_argument', 'this model was deleted');
    return this.#session;
  }

  /** Finds the model's repeats. Options: descriptor, matcher, detector (policy names), onProgress(stage, fraction). */
  analyze(options = {}) {
    const d = defaults(this.#restitch);
    const s = this.#live();
    const answer = check(s.analyze(options.descriptor ?? d.descriptor, options.matcher ?? d.matcher,
      options.detector ?? d.detector, typeof options.onProgress === 'function' ? options.onProgress : null));
    this.analysis = answer.analysis;
    return this.analysis;
  }

  /** The principal offsets of the last analysis (model units): what `steps` step along, in order. */
  get principalOffsets() {
    return this.analysis ? this.analysis.principal_offsets : [];
  }

  /**
   * Builds what resizes with these policies need (the label grid, cell descriptors, the stitcher's cache)
   * and runs one throw-away resize per principal offset, so that the first real resize costs what later
   * ones do: call it after analyze() while the user looks at the model. Returns the milliseconds spent.
   */
  prepare(options = {}) {
    const d = defaults(this.#restitch);
    const s = this.#live();
    if (!this.analysis) this.analyze();
    return check(s.prepare(options.labelSpace ?? d.labelSpace, options.seamEnergy ?? d.seamEnergy)).ms;
  }

  /** Makes these offsets ([x, y, z] in model units, at most three; [] goes back) the principal ones. */
  promote(offsets) {
    this.analysis = check(this.#live().promote(offsets)).analysis;
    return this.analysis;
  }

  /**
   * Resizes. Either `steps` (whole repeats added or removed along each principal offset: a number or up to
   * three) or `size` ([x, y, z] bounding box in model units, 0 or null keeps an axis; `exact` scales the
   * nearest whole repeats to it about the pivot). `pivot`: what stays put ("origin", "min", "center", "max",
   * or one per axis "min,origin,max"). `labelSpace`, `seamEnergy`: policy names.
   */
  resize(options = {}) {
    const s = this.#live();
    if (!this.analysis) this.analyze();
    const d = defaults(this.#restitch);
    const labelSpace = options.labelSpace ?? d.labelSpace;
    const seamEnergy = options.seamEnergy ?? d.seamEnergy;
    const pivot = options.pivot ?? 'origin';
    let answer;
    if (options.size != null) {
      if (options.steps != null) throw new RestitchError('invalid_argument', 'give steps or size, not both');
      const size = Array.from(options.size, (v) => (v == null ? 0 : Number(v)));
      if (size.length !== 3) throw new RestitchError('invalid_argument', 'size is [x, y, z]');
      answer = check(s.retargetToSize(size[0], size[1], size[2], !!options.exact, labelSpace, pivot, seamEnergy));
    } else if (options.steps != null) {
      const steps = typeof options.steps === 'number' ? [options.steps] : Array.from(options.steps);
      if (steps.length > 3 || !steps.every(Number.isInteger)) {
        throw new RestitchError('invalid_argument', 'steps are up to three whole numbers, one per principal offset');
      }
      while (steps.length < 3) steps.push(0);
      answer = check(s.retarget(steps[0], steps[1], steps[2], labelSpace, pivot, seamEnergy));
    } else {
      throw new RestitchError('invalid_argument', 'give steps or size');
    }
    const generation = ++this.#generation;
    const mesh = check(s.mesh('result'));
    delete mesh.ok;
    return new Result(answer, mesh, () => {
      if (generation !== this.#generation || !this.#session) {
        throw new RestitchError('invalid_argument', 'a later resize (or delete) replaced this result: call glb() first');
      }
      return check(this.#session.saveGlb('result')).bytes;
    });
  }

  /** The input model's arrays: {positions, normals?, uvs?, uvSets, colors?, indices, groups}. */
  mesh() {
    const m = check(this.#live().mesh('input'));
    delete m.ok;
    return m;
  }

  /** The input model as .glb bytes. */
  glb() {
    return check(this.#live().saveGlb('input')).bytes;
  }

  /** Frees the model's WebAssembly memory; the model cannot be used after. */
  delete() {
    if (this.#session) this.#session.delete();
    this.#session = null;
  }
}
if (typeof Symbol.dispose === 'symbol') Model.prototype[Symbol.dispose] = Model.prototype.delete;  // `using model = ...`

export class Result {
  #glb;
  constructor(answer, mesh, glb) {
    /** What `restitch resize --json` prints: steps, sizes, seams, warnings, timings. */
    this.report = answer.report;
    /** The label grid (model units) and the labels, for drawing the cells. */
    this.grid = answer.grid;
    this.cellLabels = answer.cell_labels;
    this.labelShifts = answer.label_shifts;
    /** Two corners (x, y, z) per open edge the result check found that the input does not have. */
    this.openEdges = answer.open_edges;
    /** {positions, normals?, uvs?, uvSets, colors?, indices, groups: [{start, count, material, group, name, colors}]} */
    this.mesh = mesh;
    this.#glb = glb;
  }

  /** The result as .glb bytes (materials, textures and extensions of the input kept). */
  glb() {
    return this.#glb();
  }

  /** The result check's warnings: [{check, message}]; empty on a result that needs no look. */
  get warnings() {
    return this.report.warnings;
  }
}
