// app.js - the restitch demo page: open a model, analyse it in a worker, resize it live with sliders.
//
// The WebAssembly work runs in ./worker.js (protocol there); this file owns the
// view (three.js), the controls (lil-gui) and the overlays. URL parameters:
// ?sample=NAME picks the first sample (default bookshelf), ?descriptor=,
// ?matcher=, ?labels= preset the policy choices (default: the library's
// defaults, the first of each list the module reports).
//
// Contract for automated checks:
//   document.body.dataset.status: 'loading' | 'analyzing' | 'ready' | 'error'
//   window.restitchDemo.analysis  the fields of `restitch analyze --json` (model units)
//   window.restitchDemo.analysisMs  the analysis's time in the worker (ms)
//   window.restitchDemo.result    {vertices, triangles} of the model shown
//   window.restitchDemo.report    the fields of `restitch resize --json` for the result shown
//   window.restitchDemo.setSteps([a, b, c])  resolves once the view shows that result
//     (rejects with the message when the resize fails)
//   window.restitchDemo.resizeTimings (ms per shown resize), .statusHistory, .progressReports,
//   .loadSample(name), .setView('shaded' | 'labels' | 'seams'), .setOverlays({offsets, histogram}),
//   .getCamera() -> {position, target}, .setCamera({position, target}) (model units; a later resize moves the
//   camera with the model again, so set it after setSteps resolves for a fixed framing)
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { RoomEnvironment } from 'three/addons/environments/RoomEnvironment.js';
import GUI from 'lil-gui';

const query = new URLSearchParams(location.search);
const STAGES = ['sampling', 'descriptors', 'matching', 'histogram', 'refinement', 'lattice'];
const AXIS_COLORS = [0xe0483e, 0x3ec94a, 0x3e7de0];
const $ = (id) => document.getElementById(id);

// ---- state ----------------------------------------------------------------------------------------------------------

const state = {
  status: 'loading',
  catalog: [],
  policies: { descriptors: [], matchers: [], label_spaces: [] },  // from the module; the default first
  model: null,        // {name, units, info, inputMesh, materials, extentAlong}
  analysis: null,     // analyze --json fields
  extras: null,       // lattice, raw offsets
  analysisMs: 0,
  retarget: null,     // last shown {steps, result, mesh, ms, pageMs}
  shown: null,        // {vertices, triangles}
  error: '',
};
const settings = {
  sample: query.get('sample') || 'bookshelf',
  descriptor: query.get('descriptor'),  // null: the module's default, set in start()
  matcher: query.get('matcher'),
  labelSpace: query.get('labels'),
  view: 'shaded',
  offsets: true,
  histogram: true,
  steps: { v1: 0, v2: 0, v3: 0 },
};

const statusHistory = [];  // every status change, for automated checks
let progressReports = 0;

function setStatus(s) {
  if (s !== state.status || !statusHistory.length) statusHistory.push(s);
  state.status = s;
  document.body.dataset.status = s;
}

function showError(message) {
  state.error = message;
  $('error').textContent = message;
  $('error').hidden = false;
  setStatus('error');
}

function clearError() {
  state.error = '';
  $('error').hidden = true;
}

// ---- worker ---------------------------------------------------------------------------------------------------------

let worker = null;
let nextId = 1;
const pending = new Map();  // id -> {resolve, reject, onProgress}

function startWorker() {
  if (worker) worker.terminate();
  for (const p of pending.values()) p.reject(Object.assign(new Error('cancelled'), { cancelled: true }));
  pending.clear();
  worker = new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
  worker.onmessage = (e) => {
    const msg = e.data;
    const p = pending.get(msg.id);
    if (!p) return;
    if (msg.type === 'progress') {
      if (p.onProgress) p.onProgress(msg.stage, msg.fraction);
      return;
    }
    pending.delete(msg.id);
    if (msg.type === 'error') p.reject(Object.assign(new Error(msg.message), { code: msg.code }));
    else p.resolve(msg);
  };
  worker.onerror = (e) => {
    e.preventDefault();
    const message = `the restitch worker failed to start (${e.message || 'see the console'})`;
    for (const p of pending.values()) p.reject(Object.assign(new Error(message), { code: 'internal' }));
    pending.clear();
  };
  retargetQueue.inFlight = false;
  retargetQueue.next = null;
}

function request(type, payload = {}, { onProgress, transfer = [] } = {}) {
  const id = nextId++;
  return new Promise((resolve, reject) => {
    pending.set(id, { resolve, reject, onProgress });
    worker.postMessage({ type, id, ...payload }, transfer);
  });
}

// ---- three.js view --------------------------------------------------------------------------------------------------

const renderer = new THREE.WebGLRenderer({ antialias: true });
renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
renderer.setSize(window.innerWidth, window.innerHeight);
renderer.autoClear = false;
$('viewport').appendChild(renderer.domElement);

const scene = new THREE.Scene();
scene.background = new THREE.Color(0x2a2d33);
scene.environment = new THREE.PMREMGenerator(renderer).fromScene(new RoomEnvironment(), 0.04).texture;
scene.environmentIntensity = 0.7;
const sun = new THREE.DirectionalLight(0xffffff, 0.9);
sun.position.set(1, 2, 3);
scene.add(sun);

const camera = new THREE.PerspectiveCamera(40, window.innerWidth / window.innerHeight, 0.001, 1000);
const controls = new OrbitControls(camera, renderer.domElement);
controls.addEventListener('change', () => render());

const modelGroup = new THREE.Group();   // the model shown (input or result)
const arrowGroup = new THREE.Group();   // principal offsets on the model (paper Fig. 2)
const seamGroup = new THREE.Group();    // seam faces between differently labelled cells
scene.add(modelGroup, arrowGroup, seamGroup);

// The histogram view: the offsets of all matches and the dominant offsets, in normalized units.
const histScene = new THREE.Scene();
histScene.background = new THREE.Color(0x16181c);
const histCamera = new THREE.PerspectiveCamera(35, 1, 0.01, 100);
const histGroup = new THREE.Group();
histScene.add(histGroup, new THREE.AxesHelper(0.5));
const HIST_SIZE = 240;

function render() {
  const w = window.innerWidth, h = window.innerHeight;
  updateViewOffset();
  renderer.setViewport(0, 0, w, h);
  renderer.setScissorTest(false);
  renderer.clear();
  renderer.render(scene, camera);
  if (settings.histogram && state.extras) {
    const dir = camera.position.clone().sub(controls.target).normalize();
    histCamera.position.copy(dir.multiplyScalar(6.5));
    histCamera.up.copy(camera.up);
    histCamera.lookAt(0, 0, 0);
    renderer.setScissorTest(true);
    renderer.setScissor(8, 8, HIST_SIZE, HIST_SIZE);
    renderer.setViewport(8, 8, HIST_SIZE, HIST_SIZE);
    renderer.clear();
    renderer.render(histScene, histCamera);
    renderer.setScissorTest(false);
  }
  $('histogram-label').hidden = !(settings.histogram && state.extras);
}

window.addEventListener('resize', () => {
  camera.aspect = window.innerWidth / window.innerHeight;
  camera.updateProjectionMatrix();
  renderer.setSize(window.innerWidth, window.innerHeight);
  render();
});

function disposeGroup(group) {
  for (const child of [...group.children]) {
    group.remove(child);
    child.traverse((o) => {
      if (o.geometry) o.geometry.dispose();
      for (const m of [o.material || []].flat()) if (m.userData.owned) m.dispose();
    });
  }
}

// The distance at which a box fills the view, and its centre.
function framing(box) {
  const size = box.getSize(new THREE.Vector3());
  const radius = Math.max(size.length() / 2, 1e-6);
  const free = freeWidth() / window.innerHeight;  // the aspect of the view between the overlays
  const fov = Math.min(camera.fov, 2 * THREE.MathUtils.radToDeg(Math.atan(Math.tan(THREE.MathUtils.degToRad(camera.fov / 2)) * free)));
  return { center: box.getCenter(new THREE.Vector3()), dist: radius / Math.sin(THREE.MathUtils.degToRad(fov / 2)) * 1.1 };
}
let framed = null;  // the framing of the box shown last: resized models keep the user's pan and zoom relative to it

function fitCamera(box) {
  framed = framing(box);
  camera.position.copy(framed.center).add(new THREE.Vector3(0.35, 0.3, 1).normalize().multiplyScalar(framed.dist));
  camera.near = framed.dist / 100;
  camera.far = framed.dist * 100;
  camera.updateProjectionMatrix();
  controls.target.copy(framed.center);
  controls.update();
}

// Follows a resized model: same view direction, pan and zoom relative to its new bounding box.
function followBox(box) {
  if (!framed) return fitCamera(box);
  const next = framing(box);
  const offset = camera.position.clone().sub(controls.target);
  const zoom = offset.length() / framed.dist;
  const pan = controls.target.clone().sub(framed.center).multiplyScalar(next.dist / framed.dist);
  controls.target.copy(next.center).add(pan);
  camera.position.copy(controls.target).add(offset.setLength(next.dist * zoom));
  camera.near = next.dist / 100;
  camera.far = next.dist * 100;
  camera.updateProjectionMatrix();
  controls.update();
  framed = next;
}

// The overlays' widths: figures on the left, controls on the right (0 on narrow windows).
function overlays() {
  if (window.innerWidth <= 900) return { left: 0, right: 0 };
  const panel = document.querySelector('.lil-gui.lil-root');
  return { left: $('figures').getBoundingClientRect().right, right: panel ? panel.getBoundingClientRect().width : 0 };
}
function freeWidth() {
  const o = overlays();
  return Math.max(window.innerWidth - o.left - o.right, window.innerWidth * 0.4);
}

// Centre the projection between the overlays.
function updateViewOffset() {
  const w = window.innerWidth, h = window.innerHeight, o = overlays();
  camera.setViewOffset(w, h, -Math.round((o.left - o.right) / 2), 0, w, h);
}

function geometryOf(mesh) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(mesh.positions, 3));
  if (mesh.normals) g.setAttribute('normal', new THREE.BufferAttribute(mesh.normals, 3));
  if (mesh.uvs) g.setAttribute('uv', new THREE.BufferAttribute(mesh.uvs, 2));
  if (mesh.colors) g.setAttribute('color', new THREE.BufferAttribute(mesh.colors, 4));
  g.setIndex(new THREE.BufferAttribute(mesh.indices, 1));
  mesh.groups.forEach((grp, i) => g.addGroup(grp.start, grp.count, i));
  if (!mesh.normals) g.computeVertexNormals();
  g.computeBoundingBox();
  g.computeBoundingSphere();
  return g;
}

const defaultMaterial = new THREE.MeshStandardMaterial({ color: 0xb0b0b0, roughness: 0.8 });
const neutralMaterial = new THREE.MeshStandardMaterial({ color: 0x9a9a9a, roughness: 0.85, side: THREE.DoubleSide });

function materialFor(group) {
  let m = (state.model && state.model.materials[group.material]) || defaultMaterial;
  if (group.colors) {
    m = m.clone();
    m.vertexColors = true;
    m.userData.owned = true;
  }
  return m;
}

// Distinct colours for label indices (golden-ratio hues).
function labelColor(label, out) {
  return out.setHSL((label * 0.618033988749895 + 0.1) % 1, 0.7, 0.45);
}

// Non-indexed copy with one colour per face: the output cells coloured by their label (paper Fig. 4c).
function labelGeometry(mesh, faceLabels) {
  const idx = mesh.indices, pos = mesh.positions, nor = mesh.normals;
  const n = idx.length;
  const p = new Float32Array(n * 3), c = new Float32Array(n * 3), nn = nor ? new Float32Array(n * 3) : null;
  const col = new THREE.Color();
  for (let i = 0; i < n; ++i) {
    const v = idx[i];
    p[3 * i] = pos[3 * v]; p[3 * i + 1] = pos[3 * v + 1]; p[3 * i + 2] = pos[3 * v + 2];
    if (nn) { nn[3 * i] = nor[3 * v]; nn[3 * i + 1] = nor[3 * v + 1]; nn[3 * i + 2] = nor[3 * v + 2]; }
    if (i % 3 === 0) labelColor(faceLabels ? faceLabels[i / 3] : 0, col);
    c[3 * i] = col.r; c[3 * i + 1] = col.g; c[3 * i + 2] = col.b;
  }
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(p, 3));
  g.setAttribute('color', new THREE.BufferAttribute(c, 3));
  if (nn) g.setAttribute('normal', new THREE.BufferAttribute(nn, 3));
  else g.computeVertexNormals();
  return g;
}

// Seam faces: every face shared by two 6-neighbour output cells with different labels.
function seamObject(result) {
  const [U, V, W] = result.report.cells_out;
  const labels = result.cell_labels;
  const A = result.grid.axes.map((a) => new THREE.Vector3(...a));
  const o = new THREE.Vector3(...result.grid.origin);
  const toModel = (c) => o.clone().addScaledVector(A[0], c[0]).addScaledVector(A[1], c[1]).addScaledVector(A[2], c[2]);
  const quads = [], lines = [];
  const at = (i, j, k) => labels[i + U * (j + V * k)];
  const dims = [U, V, W];
  for (let k = 0; k < W; ++k) for (let j = 0; j < V; ++j) for (let i = 0; i < U; ++i) {
    const x = [i, j, k];
    for (let a = 0; a < 3; ++a) {
      const y = x.slice(); y[a] += 1;
      if (y[a] >= dims[a] || at(...x) === at(...y)) continue;
      const b = (a + 1) % 3, c = (a + 2) % 3;
      const corners = [[0, 0], [1, 0], [1, 1], [0, 1]].map(([s, t]) => {
        const q = x.slice(); q[a] += 1; q[b] += s; q[c] += t;
        return toModel(q);
      });
      for (const idx of [0, 1, 2, 0, 2, 3]) quads.push(corners[idx].x, corners[idx].y, corners[idx].z);
      for (let e = 0; e < 4; ++e) {
        const p = corners[e], q = corners[(e + 1) % 4];
        lines.push(p.x, p.y, p.z, q.x, q.y, q.z);
      }
    }
  }
  const group = new THREE.Group();
  if (!quads.length) return group;
  const qg = new THREE.BufferGeometry();
  qg.setAttribute('position', new THREE.Float32BufferAttribute(quads, 3));
  const qm = new THREE.MeshBasicMaterial({ color: 0xff8a1c, transparent: true, opacity: 0.35, side: THREE.DoubleSide,
                                           depthWrite: false });
  qm.userData.owned = true;
  const lg = new THREE.BufferGeometry();
  lg.setAttribute('position', new THREE.Float32BufferAttribute(lines, 3));
  const lm = new THREE.LineBasicMaterial({ color: 0xffb060 });
  lm.userData.owned = true;
  group.add(new THREE.Mesh(qg, qm), new THREE.LineSegments(lg, lm));
  return group;
}

// Shows the retarget result if there is one, else the input; in the chosen view.
function showModel() {
  disposeGroup(modelGroup);
  disposeGroup(seamGroup);
  if (!state.model) return;
  const r = state.retarget;
  const mesh = r ? r.mesh : state.model.inputMesh;
  let object;
  if (settings.view === 'labels') {
    const m = new THREE.MeshStandardMaterial({ vertexColors: true, roughness: 0.75, side: THREE.DoubleSide });
    m.userData.owned = true;
    object = new THREE.Mesh(labelGeometry(mesh, r ? r.result.face_labels : null), m);
  } else if (settings.view === 'seams') {
    object = new THREE.Mesh(geometryOf(mesh), neutralMaterial);
    if (r) seamGroup.add(seamObject(r.result));
  } else {
    object = new THREE.Mesh(geometryOf(mesh), mesh.groups.map(materialFor));
  }
  modelGroup.add(object);
  state.shown = { vertices: mesh.positions.length / 3, triangles: mesh.indices.length / 3 };
  updateFigures();
}

function showOffsets() {
  disposeGroup(arrowGroup);
  disposeGroup(histGroup);
  const a = state.analysis, e = state.extras;
  if (!a || !e) return;
  // Principal offsets as arrows on the model, from the centre of the input's bounding box.
  const box = state.model.box;
  const center = box.getCenter(new THREE.Vector3());
  a.principal_offsets.forEach((v, i) => {
    const dir = new THREE.Vector3(...v);
    const len = dir.length();
    const arrow = new THREE.ArrowHelper(dir.clone().normalize(), center, len, AXIS_COLORS[i], len * 0.25, len * 0.12);
    arrow.line.material.depthTest = false;
    arrow.cone.material.depthTest = false;
    arrow.renderOrder = 10;
    arrowGroup.add(arrow);
  });
  arrowGroup.visible = settings.offsets;
  // Histogram view.
  const pg = new THREE.BufferGeometry();
  pg.setAttribute('position', new THREE.BufferAttribute(e.match_offsets, 3));
  const pm = new THREE.PointsMaterial({ color: 0x8a8f98, size: 1.5, sizeAttenuation: false });
  pm.userData.owned = true;
  histGroup.add(new THREE.Points(pg, pm));
  const dom = e.dominant_normalized.flat();
  if (dom.length) {
    const dg = new THREE.BufferGeometry();
    dg.setAttribute('position', new THREE.Float32BufferAttribute(dom, 3));
    const dm = new THREE.PointsMaterial({ color: 0xffa030, size: 7, sizeAttenuation: false });
    dm.userData.owned = true;
    histGroup.add(new THREE.Points(dg, dm));
  }
  const scale = a.scale;
  a.principal_offsets.forEach((v, i) => {
    const dir = new THREE.Vector3(...v).multiplyScalar(scale);
    const len = dir.length();
    histGroup.add(new THREE.ArrowHelper(dir.clone().normalize(), new THREE.Vector3(), len, AXIS_COLORS[i],
                                        Math.min(0.15, len * 0.3), Math.min(0.08, len * 0.15)));
  });
}

// ---- figures --------------------------------------------------------------------------------------------------------

const fmt = (x, d = 3) => (Number.isFinite(x) ? Number(x.toPrecision(d)).toString() : '–');
const vfmt = (v, d = 3) => v.map((x) => fmt(x, d)).join(' × ');

// A model-unit length with three decimals below the model's leading digit (so 7e-7 m on a 1.6 m model is 0.000).
function lengthFormat(x) {
  const longest = state.model ? Math.max(...state.model.box.getSize(new THREE.Vector3()).toArray()) : 1;
  const decimals = Math.min(8, Math.max(0, 3 - Math.floor(Math.log10(longest))));
  const s = x.toFixed(decimals);
  return /^-0\.?0*$/.test(s) ? s.slice(1) : s;
}

function updateFigures() {
  const rows = [];
  const m = state.model, a = state.analysis, r = state.retarget;
  if (m) {
    rows.push(['model', `${m.name} (${m.units})`]);
    rows.push(['triangles in', String(m.info.triangles)]);
    rows.push(['triangles out', r ? String(r.result.report.output.triangles) : '–']);
    if (state.shown) rows.push(['shown', `${state.shown.vertices} vertices, ${state.shown.triangles} triangles`]);
    const s = m.box.getSize(new THREE.Vector3());
    rows.push(['size in', `${vfmt(s.toArray())} ${m.units}`]);
  }
  if (a) {
    rows.push(['features', `${a.features}`]);
    rows.push(['dominant offsets', `${a.dominant_offsets.length}`]);
    a.principal_offsets.forEach((v, i) => rows.push([`v${i + 1}`, `(${v.map(lengthFormat).join(', ')}) ${m.units}`]));
    rows.push(['lattice cells', a.lattice_cells.join(' × ')]);
    rows.push(['sparsity', `top7 ${fmt(a.sparsity.top7)}, top20 ${fmt(a.sparsity.top20)}`]);
    rows.push(['analysis', `${fmt(state.analysisMs, 4)} ms in the worker`]);
  }
  if (r) {
    const rep = r.result.report;
    rows.push(['size out', `${vfmt(rep.size_out)} ${m.units}`]);
    rows.push(['label space', `${rep.label_space}, ${rep.cells_out.join(' × ')} cells`]);
    rows.push(['nodes', `${rep.nodes}`]);
    rows.push(['labels', `${rep.labels}`]);
    rows.push(['cycles', `${rep.cycles}, energy ${fmt(rep.energy, 4)}`]);
    rows.push(['solve', `${fmt(rep.timings_ms.solve || 0, 3)} ms (energy ${fmt(rep.timings_ms.energy || 0, 3)} ms, ` +
                        `stitch ${fmt(rep.timings_ms.stitch || 0, 3)} ms)`]);
    rows.push(['resize', `${fmt(r.pageMs, 3)} ms in the page (${fmt(r.ms, 3)} ms in the worker)`]);
  }
  const table = document.createElement('table');
  for (const [k, v] of rows) {
    const tr = table.insertRow();
    tr.insertCell().textContent = k;
    tr.insertCell().textContent = v;
  }
  $('figures').replaceChildren(table);
}

function showProgress(stage, fraction) {
  ++progressReports;
  $('progress').hidden = false;
  const i = Math.max(0, STAGES.indexOf(stage));
  const total = (i + Math.min(Math.max(fraction, 0), 1)) / STAGES.length;
  $('progress-label').textContent = `analysing: ${stage} ${Math.round(fraction * 100)}%`;
  $('progress-fill').style.width = `${(total * 100).toFixed(1)}%`;
}

// ---- loading and analysis -------------------------------------------------------------------------------------------

async function materialsFromGlb(glb) {
  if (!glb) return [];
  try {
    const gltf = await new GLTFLoader().parseAsync(glb.buffer, '');
    return await gltf.parser.getDependencies('material');
  } catch (e) {
    console.warn('restitch demo: materials could not be read, showing grey:', e);
    return [];
  }
}

let loadGeneration = 0;

// Loads a model ({file: {name, bytes}} or {sample: {name, params}}) and analyses it.
async function load(what) {
  const generation = ++loadGeneration;
  if (state.status === 'analyzing' || state.status === 'loading') startWorker();  // drop the running job
  clearError();
  setStatus('loading');
  state.analysis = null;
  state.extras = null;
  state.retarget = null;
  retargetQueue.inFlight = false;
  retargetQueue.next = null;
  rejectWaiters('a new model was opened');
  const label = what.file ? what.file.name : `sample: ${what.sample.name}`;
  $('model-name').textContent = label;
  try {
    const transfer = what.file ? [what.file.bytes] : [];
    const msg = await request('load', what, { transfer });
    if (generation !== loadGeneration) return;
    const materials = await materialsFromGlb(msg.glb);
    if (generation !== loadGeneration) return;
    const info = msg.info;
    const units = what.sample ? (state.catalog.find((s) => s.name === what.sample.name) || {}).units || 'm' : 'm';
    const box = new THREE.Box3(new THREE.Vector3(...info.bbox_min), new THREE.Vector3(...info.bbox_max));
    state.model = { name: label, units, info, inputMesh: msg.mesh, materials, box };
    for (const w of info.warnings) console.info(`restitch: ${w}`);
    showModel();
    showOffsets();
    fitCamera(box);
    render();
    await analyze(generation);
  } catch (e) {
    if (e.cancelled || generation !== loadGeneration) return;
    showError(`Could not open ${label}: ${e.message}`);
    render();
  }
}

// Analyses the loaded model with the chosen policies; a re-analysis (new policy) starts a new generation, so
// answers about the previous analysis are ignored.
async function analyze(generation = null) {
  if (generation === null) {
    generation = ++loadGeneration;
    retargetQueue.inFlight = false;
    retargetQueue.next = null;
    rejectWaiters('the model is being analysed again');
  }
  setStatus('analyzing');
  clearError();
  state.retarget = null;
  state.analysis = null;
  state.extras = null;
  showProgress('sampling', 0);
  try {
    const msg = await request('analyze', { descriptor: settings.descriptor, matcher: settings.matcher },
                              { onProgress: showProgress });
    if (generation !== loadGeneration) return;
    $('progress').hidden = true;
    state.analysis = msg.analysis;
    state.extras = msg.extras;
    state.analysisMs = msg.ms;
    buildSliders();
    showOffsets();
    showModel();
    render();
    if (msg.analysis.principal_offsets.length === 0) {
      showError('No repetition found: restitch found no repeated part in this model, so there is nothing to ' +
                'resize along. Try a model with repeated parts (shelves, windows, fence pickets).');
      return;
    }
    setStatus('ready');
  } catch (e) {
    if (e.cancelled || generation !== loadGeneration) return;
    $('progress').hidden = true;
    showError(`Analysis failed: ${e.message}`);
    render();
  }
}

// ---- resizing -------------------------------------------------------------------------------------------------------

// At most one retarget in flight; slider moves while it runs replace the queued one.
const retargetQueue = { inFlight: false, next: null };
let waiters = [];  // setSteps promises: {key, resolve, reject}

function stepsKey(steps, labelSpace) { return `${steps.join(',')}|${labelSpace}`; }

function rejectWaiters(message) {
  for (const w of waiters) w.reject(new Error(message));
  waiters = [];
}

function requestResize(steps) {
  retargetQueue.next = { steps: steps.slice(), labelSpace: settings.labelSpace, t0: performance.now() };
  pumpResize();
}

async function pumpResize() {
  if (retargetQueue.inFlight || !retargetQueue.next || !state.analysis) return;
  const job = retargetQueue.next;
  retargetQueue.next = null;
  retargetQueue.inFlight = true;
  const generation = loadGeneration;
  try {
    const msg = await request('retarget', { steps: job.steps, labelSpace: job.labelSpace });
    if (generation !== loadGeneration) return;
    state.retarget = { steps: job.steps, labelSpace: job.labelSpace, result: msg.result, mesh: msg.mesh, ms: msg.ms };
    showModel();
    followBox(new THREE.Box3().setFromObject(modelGroup));
    render();
    await new Promise((r) => requestAnimationFrame(() => r()));
    state.retarget.pageMs = performance.now() - job.t0;
    resizeTimings.push(state.retarget.pageMs);
    updateFigures();
    if (state.status === 'error' && state.analysis.principal_offsets.length) clearError(), setStatus('ready');
    const key = stepsKey(job.steps, job.labelSpace);
    const done = waiters.filter((w) => w.key === key);
    waiters = waiters.filter((w) => w.key !== key);
    for (const w of done) w.resolve({ ...state.shown, steps: job.steps, ms: state.retarget.pageMs });
  } catch (e) {
    if (e.cancelled || generation !== loadGeneration) return;
    showError(`Resize failed: ${e.message}`);
    const key = stepsKey(job.steps, job.labelSpace);
    const failed = waiters.filter((w) => w.key === key);
    waiters = waiters.filter((w) => w.key !== key);
    for (const w of failed) w.reject(new Error(e.message));
  } finally {
    if (generation === loadGeneration) {
      retargetQueue.inFlight = false;
      pumpResize();
    }
  }
}

function currentSteps() { return [settings.steps.v1, settings.steps.v2, settings.steps.v3]; }

function setSteps(steps) {
  if (!state.analysis) return Promise.reject(new Error('no analysed model yet'));
  const s = [0, 1, 2].map((i) => Math.trunc(Number(steps[i] || 0)));
  settings.steps.v1 = s[0]; settings.steps.v2 = s[1]; settings.steps.v3 = s[2];
  for (const c of sliderControllers) c.updateDisplay();
  updateSliderNames();
  const promise = new Promise((resolve, reject) => waiters.push({ key: stepsKey(s, settings.labelSpace), resolve, reject }));
  requestResize(s);
  return promise;
}

const resizeTimings = [];

// ---- controls -------------------------------------------------------------------------------------------------------

const gui = new GUI({ title: 'restitch' });
let sampleController = null;
const modelFolder = gui.addFolder('Model');
const analysisFolder = gui.addFolder('Analysis');
const resizeFolder = gui.addFolder('Resize');
const viewFolder = gui.addFolder('View');
let sliderControllers = [];

function extentAlong(dir) {
  const pos = state.model.inputMesh.positions;
  let lo = Infinity, hi = -Infinity;
  for (let i = 0; i < pos.length; i += 3) {
    const t = pos[i] * dir.x + pos[i + 1] * dir.y + pos[i + 2] * dir.z;
    if (t < lo) lo = t;
    if (t > hi) hi = t;
  }
  return hi - lo;
}

function updateSliderNames() {
  const a = state.analysis;
  if (!a) return;
  sliderControllers.forEach((c, i) => {
    const v = new THREE.Vector3(...a.principal_offsets[i]);
    const len = v.length();
    const base = state.model.extent[i];
    const k = settings.steps[`v${i + 1}`];
    c.name(`v${i + 1} steps → ${fmt(base + k * len)} ${state.model.units}`);
  });
}

function buildSliders() {
  for (const c of sliderControllers) c.destroy();
  sliderControllers = [];
  settings.steps.v1 = settings.steps.v2 = settings.steps.v3 = 0;
  const a = state.analysis;
  state.model.extent = a.principal_offsets.map((v) => extentAlong(new THREE.Vector3(...v).normalize()));
  // Slider i moves along principal offset v_i, the i-th lattice axis that is not a dummy (restitch::lattice_steps_from_principal).
  const real = [0, 1, 2].filter((c) => !a.dummy_directions.some((d) => d.every((x, k) => x === a.lattice_axes[c][k])));
  a.principal_offsets.forEach((v, i) => {
    const cells = a.lattice_cells[real[i]];
    const c = resizeFolder.add(settings.steps, `v${i + 1}`, 1 - cells, Math.min(24, Math.max(6, 2 * cells)), 1)
                  .onChange(() => { updateSliderNames(); requestResize(currentSteps()); });
    sliderControllers.push(c);
  });
  updateSliderNames();
}

function buildGui() {
  const names = state.catalog.map((s) => s.name);
  sampleController = modelFolder.add(settings, 'sample', names).name('bundled sample')
                                .onChange((name) => load({ sample: { name, params: {} } }));
  modelFolder.add({ open: () => $('file').click() }, 'open').name('open .glb / .gltf…');
  modelFolder.add({ download }, 'download').name('download .glb');
  analysisFolder.add(settings, 'descriptor', state.policies.descriptors).onChange(() => state.model && analyze());
  analysisFolder.add(settings, 'matcher', state.policies.matchers).onChange(() => state.model && analyze());
  resizeFolder.add(settings, 'labelSpace', state.policies.label_spaces).name('label space')
              .onChange(() => state.analysis && requestResize(currentSteps()));
  viewFolder.add(settings, 'view', { shaded: 'shaded', 'cells by label': 'labels', seams: 'seams' })
            .onChange(() => { showModel(); render(); });
  viewFolder.add(settings, 'offsets').name('principal offsets').onChange((v) => { arrowGroup.visible = v; render(); });
  viewFolder.add(settings, 'histogram').name('offset histogram').onChange(() => render());
}

async function download() {
  if (!state.model) return;
  try {
    const msg = await request('save', { which: state.retarget ? 'result' : 'input' });
    const blob = new Blob([msg.bytes], { type: 'model/gltf-binary' });
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = `${state.model.name.replace(/^sample: /, '').replace(/\.(glb|gltf)$/i, '')}-resized.glb`;
    a.click();
    setTimeout(() => URL.revokeObjectURL(a.href), 10000);
  } catch (e) {
    showError(`Saving failed: ${e.message}`);
  }
}

// ---- files: picker and drag and drop --------------------------------------------------------------------------------

async function openFile(file) {
  if (!/\.(glb|gltf)$/i.test(file.name)) {
    showError(`${file.name} is not a glTF file: open a .glb or a .gltf file.`);
    return;
  }
  const bytes = await file.arrayBuffer();
  await load({ file: { name: file.name, bytes } });
}

$('file').addEventListener('change', (e) => {
  const f = e.target.files[0];
  if (f) openFile(f);
  e.target.value = '';
});
window.addEventListener('dragover', (e) => { e.preventDefault(); document.body.classList.add('dragging'); });
window.addEventListener('dragleave', (e) => { if (!e.relatedTarget) document.body.classList.remove('dragging'); });
window.addEventListener('drop', (e) => {
  e.preventDefault();
  document.body.classList.remove('dragging');
  const f = e.dataTransfer && e.dataTransfer.files[0];
  if (f) openFile(f);
});

// ---- the automation contract ----------------------------------------------------------------------------------------

window.restitchDemo = {
  get status() { return state.status; },
  get analysis() { return state.analysis; },
  get analysisMs() { return state.analysis ? state.analysisMs : null; },
  get result() { return state.shown ? { vertices: state.shown.vertices, triangles: state.shown.triangles } : null; },
  get report() { return state.retarget ? state.retarget.result.report : null; },
  get error() { return state.error; },
  get progressReports() { return progressReports; },
  statusHistory,
  resizeTimings,
  setSteps,
  setView: (view) => {
    settings.view = view;
    for (const c of viewFolder.controllers) c.updateDisplay();
    showModel();
    render();
  },
  setOverlays: ({ offsets = settings.offsets, histogram = settings.histogram } = {}) => {
    settings.offsets = offsets;
    settings.histogram = histogram;
    arrowGroup.visible = offsets;
    for (const c of viewFolder.controllers) c.updateDisplay();
    render();
  },
  getCamera: () => ({ position: camera.position.toArray(), target: controls.target.toArray() }),
  setCamera: ({ position, target }) => {
    controls.target.fromArray(target);
    camera.position.fromArray(position);
    controls.update();
    render();
  },
  loadSample: (name, params = {}) => {
    settings.sample = name;
    if (sampleController) sampleController.updateDisplay();
    return load({ sample: { name, params } });
  },
};

// ---- start ----------------------------------------------------------------------------------------------------------

async function start() {
  setStatus('loading');
  startWorker();
  try {
    const msg = await request('catalog');
    state.catalog = msg.samples;
    state.policies = msg.policies;
    const pick = (wanted, known) => (known.includes(wanted) ? wanted : known[0]);
    settings.descriptor = pick(settings.descriptor, msg.policies.descriptors);
    settings.matcher = pick(settings.matcher, msg.policies.matchers);
    settings.labelSpace = pick(settings.labelSpace, msg.policies.label_spaces);
  } catch (e) {
    showError(`restitch could not start: ${e.message}`);
    return;
  }
  buildGui();
  if (!state.catalog.some((s) => s.name === settings.sample)) settings.sample = state.catalog[0].name;
  sampleController.updateDisplay();
  await load({ sample: { name: settings.sample, params: {} } });
}

start();
