// app.js - the restitch demo page: open a model, analyse it in a worker, resize it live with sliders.
//
// The wiring of the page's parts: ./worker-client.js talks to ./worker.js (the WebAssembly work, protocol
// there), ./session.js is the load / analyse / resize state machine, ./view.js the three.js view,
// ./layers.js makes its objects, ./panel.js the controls, figures and messages. This file adds the file
// picker, drag and drop, the download, and the automation contract below. URL parameters:
// ?sample=NAME picks the first sample (default bookshelf), ?descriptor=, ?matcher=, ?detector=, ?labels= preset
// the policy choices (default: the library's defaults, the first of each list the module reports); ?memory=MB
// caps the WebAssembly memory (64 to 2048, the default): a model that needs more is refused in words.
// Candidate repeats (a pair, or a repeat weaker than a parallel principal offset) are listed under Candidates
// and drawn in cyan in the histogram inset; clicking one (either place) promotes it: it becomes a principal
// offset and a resize slider moves along it. Hovering a dominant offset's peak in the inset explains it.
//
// Contract for automated checks:
//   document.body.dataset.status: 'loading' | 'analyzing' | 'ready' | 'error'
//   window.restitchDemo.analysis  the fields of `restitch analyze --json` (model units)
//   window.restitchDemo.analysisMs  the analysis's time in the worker (ms)
//   window.restitchDemo.result    {vertices, triangles} of the model shown
//   window.restitchDemo.report    the fields of `restitch resize --json` for the result shown
//   window.restitchDemo.error     the error shown ('' when none)
//   window.restitchDemo.setSteps([a, b, c])  resolves with {vertices, triangles, steps, ms} once the view shows
//     that result (rejects with the message when the resize fails, with an Error whose .superseded is true
//     when a later request replaced it before it ran)
//   window.restitchDemo.setSize(i, value)  the size field of principal offset i typed: the model resized to that
//     size (model units) along the world axis the offset runs along, exactly (the nearest whole repeats scaled
//     about the pivot; the other axes keep the size shown); resolves as setSteps, with the steps it took
//   window.restitchDemo.resizeTimings (ms per shown resize), .statusHistory, .progressReports,
//   window.restitchDemo.promoted   the offsets promoted on request (model units; [] for the detected ones)
//   window.restitchDemo.promote([[x, y, z], ...])  resolves with the new analysis once the sliders follow it
//     ([] = back to the detected offsets; rejects with the worker's message when refused)
//   window.restitchDemo.histogramPeaks() -> [{index, x, y, candidate}]  where the dominant offsets' peaks are
//     drawn in the histogram inset (CSS pixels, page coordinates; candidate: index in analysis.candidates or -1)
//   .loadSample(name, params), .setView('shaded' | 'labels' | 'seams'), .setOverlays({offsets, histogram}),
//   .getCamera() -> {position, target}, .setCamera({position, target}) (model units; a later resize moves the
//   camera with the model again, so set it after setSteps resolves for a fixed framing)
import { WorkerClient } from './worker-client.js';
import { Session } from './session.js';
import { View } from './view.js';
import { Panel } from './panel.js';
import { boxOf, disposeGroup, histogramObjects, materialsFromGlb, modelObjects, offsetArrows } from './layers.js';
import { peakExplanation, withOffset } from './peaks.js';

const query = new URLSearchParams(location.search);
const $ = (id) => document.getElementById(id);
const nextFrame = () => new Promise((resolve) => requestAnimationFrame(() => resolve()));

const settings = {
  sample: query.get('sample') || 'bookshelf',
  descriptor: query.get('descriptor'),  // null: the module's default, set in start()
  matcher: query.get('matcher'),
  detector: query.get('detector'),
  labelSpace: query.get('labels'),
  pivot: query.get('pivot') || 'origin',  // what stays put when resizing (restitch resize --pivot)
  seamEnergy: query.get('seam'),  // the pairwise term (restitch resize --seam-energy); null: the module's default
  view: 'shaded',
  offsets: true,
  histogram: true,
  steps: { v1: 0, v2: 0, v3: 0 },
};

const workerUrl = new URL('./worker.js', import.meta.url);
if (query.get('memory')) workerUrl.searchParams.set('memory', query.get('memory'));  // MB the module may use
const client = new WorkerClient(() => new Worker(workerUrl, { type: 'module' }));
const panel = new Panel(settings, { figures: $('figures'), progress: $('progress'), progressLabel: $('progress-label'),
                                    progressFill: $('progress-fill'), error: $('error') });
const view = new View({ container: $('viewport'), histogramLabel: $('histogram-label'), insets: overlayInsets });
const session = new Session(client, {
  policy: () => ({ descriptor: settings.descriptor, matcher: settings.matcher, detector: settings.detector,
                   labelSpace: settings.labelSpace, seamEnergy: settings.seamEnergy }),
  hooks: {
    status: (s) => { document.body.dataset.status = s; },
    error: (message) => panel.showError(message, session.state.startFailed ? () => start() : null),
    loading: (label) => { $('model-name').textContent = label; },
    materials: materialsFromGlb,
    model: (model) => { showModel(); showOffsets(); view.fitCamera(boxOf(model.info)); view.render(); },
    progress: (stage, fraction) => panel.showProgress(stage, fraction),
    analysis: (analysis) => {
      panel.buildSliders(analysis, session.state.model, () => resizeTo(currentSteps()).catch(() => {}),
                         (i, value) => setSize(i, value).catch(() => {}));
      panel.buildCandidates(analysis, session.state.model, session.state.promoted,
                            { promote: (offset) => promoteOffset(offset), detected: () => promote([]).catch(() => {}) });
      hidePeakTip();
      showOffsets();
      showModel();
      view.render();
    },
    result: async (retarget) => {
      showModel();
      panel.showSizes(retarget.result.report.size_out);
      view.followBox(view.boxOf(view.modelGroup));
      view.render();
      await nextFrame();
    },
    timed: () => panel.showFigures(session.state),
    redraw: () => view.render(),
  },
});
view.showHistogram = () => settings.histogram && !!session.state.extras;

// The overlays' widths: figures on the left, controls on the right (0 on narrow windows).
function overlayInsets() {
  if (window.innerWidth <= 900) return { left: 0, right: 0 };
  return { left: $('figures').getBoundingClientRect().right, right: panel.element.getBoundingClientRect().width };
}

// Shows the resize result if there is one, else the input; in the chosen view.
function showModel() {
  disposeGroup(view.modelGroup);
  disposeGroup(view.seamGroup);
  const mesh = session.present();
  if (!mesh) return;
  const { model, retarget } = session.state;
  const objects = modelObjects({ mesh, view: settings.view, materials: model.materials,
                                 result: retarget ? retarget.result : null });
  view.modelGroup.add(objects.model);
  if (objects.seams) view.seamGroup.add(objects.seams);
  panel.showFigures(session.state);
}

// The principal offsets on the model and the histogram inset, once there is an analysis.
function showOffsets() {
  disposeGroup(view.arrowGroup);
  disposeGroup(view.histGroup);
  const { model, analysis, extras } = session.state;
  if (!analysis || !extras) return;
  for (const arrow of offsetArrows(analysis.principal_offsets, boxOf(model.info))) view.arrowGroup.add(arrow);
  view.arrowGroup.visible = settings.offsets;
  for (const object of histogramObjects(analysis, extras)) view.histGroup.add(object);
}

// ---- resizing and controls ------------------------------------------------------------------------------------------

function currentSteps() { return [settings.steps.v1, settings.steps.v2, settings.steps.v3]; }

function resizeTo(steps) { return session.resize(steps, settings.labelSpace, settings.pivot, settings.seamEnergy); }

function setSteps(steps) {
  if (!session.state.analysis) return Promise.reject(new Error('no analysed model yet'));
  const s = [0, 1, 2].map((i) => Math.trunc(Number(steps[i] || 0)));
  settings.steps.v1 = s[0]; settings.steps.v2 = s[1]; settings.steps.v3 = s[2];
  panel.refresh();
  return resizeTo(s);
}

// A size typed for principal offset i: that size along its world axis, the other axes as shown now.
function setSize(i, value) {
  const { analysis, retarget, model } = session.state;
  if (!analysis) return Promise.reject(new Error('no analysed model yet'));
  const axis = panel.sizeAxis(i);
  if (axis === undefined || !(value > 0)) return Promise.reject(new Error('a size is a positive length'));
  const size = retarget ? retarget.result.report.size_out.slice() : model.info.bbox_max.map((x, k) => x - model.info.bbox_min[k]);
  size[axis] = value;
  return session.resize({ size }, settings.labelSpace, settings.pivot, settings.seamEnergy).then((r) => {
    settings.steps.v1 = r.steps[0]; settings.steps.v2 = r.steps[1]; settings.steps.v3 = r.steps[2];
    panel.refresh();
    return r;
  });
}

// Promotion: the offsets made principal on request (the session refits the analysis in the worker).
function promote(offsets) {
  if (!session.state.analysis) return Promise.reject(new Error('no analysed model yet'));
  return session.promote(offsets);
}

function promoteOffset(offset) {
  return promote(withOffset(session.state.promoted, offset)).catch(() => {});
}

// ---- the histogram inset: hovering a dominant offset's peak explains it, clicking a candidate's promotes it -----

const peakTip = $('peak-tip');

function histogramPeaks() {
  const { analysis, extras } = session.state;
  if (!analysis || !extras) return [];
  const canvas = view.renderer.domElement.getBoundingClientRect();
  const out = [];
  extras.dominant_normalized.forEach((p, index) => {
    const at = view.histogramToScreen(p);
    if (!at) return;
    const candidate = (analysis.candidates || []).findIndex((c) => c.dominant === index);
    out.push({ index, x: canvas.left + at.x, y: canvas.top + at.y, candidate });
  });
  return out;
}

// The peak under the pointer (within 8 CSS pixels), nearest first; null when none.
function peakAt(x, y) {
  let best = null, bestD = 8;
  for (const p of histogramPeaks()) {
    const d = Math.hypot(p.x - x, p.y - y);
    if (d <= bestD) { best = p; bestD = d; }
  }
  return best;
}

function hidePeakTip() {
  peakTip.hidden = true;
  $('viewport').classList.remove('over-candidate');
}

function showPeakTip(peak, x, y) {
  const { analysis, model } = session.state;
  const longest = Math.max(...model.info.bbox_max.map((v, k) => v - model.info.bbox_min[k]));
  const e = peakExplanation(analysis, peak.index, model.units, longest);
  const title = document.createElement('div');
  title.className = 'title';
  title.textContent = e.title;
  const table = document.createElement('table');
  for (const [name, value, verdict] of e.tests) {
    const tr = table.insertRow();
    tr.insertCell().textContent = name;
    tr.insertCell().textContent = value;
    const v = tr.insertCell();
    v.textContent = verdict;
    v.className = verdict === 'passed' ? 'passed' : 'failed';
  }
  const notes = e.notes.map((n) => {
    const d = document.createElement('div');
    d.className = 'note';
    d.textContent = n;
    return d;
  });
  peakTip.replaceChildren(title, table, ...notes);
  peakTip.hidden = false;
  peakTip.style.left = `${x + 14}px`;
  peakTip.style.top = `${Math.max(4, y - peakTip.offsetHeight - 10)}px`;
  $('viewport').classList.toggle('over-candidate', peak.candidate >= 0);
}

$('viewport').addEventListener('pointermove', (e) => {
  const peak = e.buttons ? null : peakAt(e.clientX, e.clientY);
  if (peak) showPeakTip(peak, e.clientX, e.clientY);
  else if (!peakTip.hidden) hidePeakTip();
});
$('viewport').addEventListener('pointerleave', hidePeakTip);
// Capture: a click on a candidate's peak promotes it and does not start an orbit.
$('viewport').addEventListener('pointerdown', (e) => {
  const peak = peakAt(e.clientX, e.clientY);
  if (!peak || peak.candidate < 0) return;
  e.stopPropagation();
  e.preventDefault();
  hidePeakTip();
  promoteOffset(session.state.analysis.candidates[peak.candidate].offset);
}, { capture: true });

function loadSample(name, params = {}) {
  settings.sample = name;
  panel.refresh();
  return session.load({ sample: { name, params } });
}

async function download() {
  if (!session.state.model) return;
  try {
    const bytes = await session.save();
    const blob = new Blob([bytes], { type: 'model/gltf-binary' });
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = `${session.state.model.name.replace(/^sample: /, '').replace(/\.(glb|gltf)$/i, '')}-resized.glb`;
    a.click();
    setTimeout(() => URL.revokeObjectURL(a.href), 10000);
  } catch (e) {
    session.fail(`Saving failed: ${e.message}`);
  }
}

// The controls' actions (panel.js).
const handlers = {
  sample: (name) => session.load({ sample: { name, params: {} } }),
  open: () => $('file').click(),
  download,
  policy: () => session.state.model && session.reanalyze(),
  labelSpace: () => session.state.analysis && resizeTo(currentSteps()).catch(() => {}),
  pivot: () => session.state.analysis && resizeTo(currentSteps()).catch(() => {}),
  seamEnergy: () => session.state.analysis && resizeTo(currentSteps()).catch(() => {}),
  view: () => { showModel(); view.render(); },
  offsets: (v) => { view.arrowGroup.visible = v; view.render(); },
  histogram: () => view.render(),
};

// ---- files: picker and drag and drop --------------------------------------------------------------------------------

async function openFile(file) {
  if (!/\.(glb|gltf)$/i.test(file.name)) {
    session.fail(`${file.name} is not a glTF file: open a .glb or a .gltf file.`);
    return;
  }
  const bytes = await file.arrayBuffer();
  await session.load({ file: { name: file.name, bytes } });
}

$('file').addEventListener('change', (e) => {
  const f = e.target.files[0];
  if (f) openFile(f);
  e.target.value = '';
});
// A file chosen before this script ran (the picker is in the page before the modules have loaded) is in the
// input already, and its change event has gone by: open it now.
if ($('file').files[0]) {
  openFile($('file').files[0]);
  $('file').value = '';
}
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
  get status() { return session.state.status; },
  get analysis() { return session.state.analysis; },
  get analysisMs() { return session.state.analysis ? session.state.analysisMs : null; },
  get result() {
    const shown = session.state.shown;
    return shown ? { vertices: shown.vertices, triangles: shown.triangles } : null;
  },
  get report() { return session.state.retarget ? session.state.retarget.result.report : null; },
  get error() { return session.state.error; },
  get promoted() { return session.state.promoted; },
  promote,
  histogramPeaks,
  get progressReports() { return session.progressReports; },
  statusHistory: session.statusHistory,
  resizeTimings: session.resizeTimings,
  setSteps,
  setSize,
  setView: (name) => {
    settings.view = name;
    panel.refresh();
    showModel();
    view.render();
  },
  setOverlays: ({ offsets = settings.offsets, histogram = settings.histogram } = {}) => {
    settings.offsets = offsets;
    settings.histogram = histogram;
    view.arrowGroup.visible = offsets;
    panel.refresh();
    view.render();
  },
  getCamera: () => view.getCamera(),
  setCamera: (camera) => view.setCamera(camera),
  loadSample,
};

// ---- start ----------------------------------------------------------------------------------------------------------

async function start() {
  const catalog = await session.start();
  if (!catalog) return;
  const pick = (wanted, known) => (known.includes(wanted) ? wanted : known[0]);
  settings.descriptor = pick(settings.descriptor, catalog.policies.descriptors);
  settings.matcher = pick(settings.matcher, catalog.policies.matchers);
  settings.detector = pick(settings.detector, catalog.policies.detectors || ['histogram']);
  settings.labelSpace = pick(settings.labelSpace, catalog.policies.label_spaces);
  settings.pivot = pick(settings.pivot, catalog.policies.pivots || ['origin']);
  settings.seamEnergy = pick(settings.seamEnergy, catalog.policies.seam_energies || ['descriptor']);
  panel.build({ samples: catalog.samples.map((s) => s.name), policies: catalog.policies }, handlers);
  if (!catalog.samples.some((s) => s.name === settings.sample)) settings.sample = catalog.samples[0].name;
  panel.refresh();
  // The bundled sample, unless a model was opened while the page started.
  if (!session.opened) await session.load({ sample: { name: settings.sample, params: {} } });
}

start();
