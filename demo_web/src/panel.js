// panel.js - the page's 2D parts: the lil-gui controls, the step sliders, the figures table, progress and errors.
//
//   const panel = new Panel(settings, { figures, progress, progressLabel, progressFill, error });  // elements
//   panel.build({ samples, policies }, handlers)   the Model / Analysis / Resize / View folders
//   panel.buildSliders(analysis, model, onSteps, onSize)   one slider per principal offset; onSteps() on every
//                                                 move; and one size field per principal offset, the model's size
//                                                 along the world axis it runs along: onSize(i, value) when one
//                                                 is typed (a configurator's "make it 1.8 m wide")
//   panel.showSizes(size)                         the size fields show this box size [x, y, z]
//   panel.buildCandidates(analysis, model, promoted, { promote(offset), detected() })   the Candidates folder:
//                                                 one button per candidate repeat, and 'detected offsets'
//   panel.refresh()                               shows `settings` again after it was changed in code
//   panel.showFigures(state)                      the figures table of a Session's state (./session.js)
//   panel.showProgress(stage, fraction) / panel.showError(message)   (null / '' hide them)
// `settings` is the object the controls edit: sample, descriptor, matcher, detector, labelSpace, pivot, seamEnergy, view ('shaded' |
// 'labels' | 'seams'), offsets, histogram (booleans), steps {v1, v2, v3}. handlers: sample(name), open(),
// download(), policy() (descriptor or matcher changed), labelSpace(), pivot(), seamEnergy(), view(), offsets(), histogram().
// The slider names give the size each step count makes along its principal offset, in model units.
import GUI from 'lil-gui';
import { candidateLabel, fmt, lengthFormat } from './peaks.js';

const STAGES = ['sampling', 'descriptors', 'matching', 'histogram', 'refinement', 'lattice'];

export { fmt };
const vfmt = (v, d = 3) => v.map((x) => fmt(x, d)).join(' × ');
const sizeOf = (info) => info.bbox_max.map((x, k) => x - info.bbox_min[k]);
const norm = (v) => Math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);  // as THREE.Vector3.length()

// The extent of a mesh along a direction (any length): the length of its shadow on that axis.
function extentAlong(positions, v) {
  const inv = 1 / (norm(v) || 1), d = v.map((x) => x * inv);  // as THREE.Vector3.normalize()
  let lo = Infinity, hi = -Infinity;
  for (let i = 0; i < positions.length; i += 3) {
    const t = positions[i] * d[0] + positions[i + 1] * d[1] + positions[i + 2] * d[2];
    if (t < lo) lo = t;
    if (t > hi) hi = t;
  }
  return hi - lo;
}

// The rows [name, value] of the figures table.
export function figureRows({ model: m, analysis: a, retarget: r, shown, analysisMs }) {
  const rows = [];
  if (m) {
    rows.push(['model', `${m.name} (${m.units})`]);
    rows.push(['triangles in', String(m.info.triangles)]);
    rows.push(['triangles out', r ? String(r.result.report.output.triangles) : '–']);
    if (shown) rows.push(['shown', `${shown.vertices} vertices, ${shown.triangles} triangles`]);
    rows.push(['size in', `${vfmt(sizeOf(m.info))} ${m.units}`]);
  }
  if (a) {
    const longest = Math.max(...sizeOf(m.info));
    rows.push(['features', `${a.features}`]);
    rows.push(['dominant offsets', `${a.dominant_offsets.length}`]);
    const promoted = a.dominant_offsets.filter((d) => d.promoted).length;
    a.principal_offsets.forEach((v, i) =>
      rows.push([`v${i + 1}`, `(${v.map((x) => lengthFormat(x, longest)).join(', ')}) ${m.units}` +
                              (i < promoted ? ' (promoted)' : '')]));
    rows.push(['candidates', `${(a.candidates || []).length}`]);
    rows.push(['lattice cells', a.lattice_cells.join(' × ')]);
    rows.push(['sparsity', `top7 ${fmt(a.sparsity.top7)}, top20 ${fmt(a.sparsity.top20)}`]);
    rows.push(['analysis', `${fmt(analysisMs, 4)} ms in the worker`]);
  }
  if (r) {
    const rep = r.result.report;
    rows.push(['size out', `${vfmt(rep.size_out)} ${m.units}`]);
    if (rep.checked)
      rows.push(['check', rep.warnings.length
        ? rep.warnings.map((w) => w.check).join(', ') + (rep.boundary_edges.new ? ` (${rep.boundary_edges.new} open edges, in red)` : '')
        : 'passed']);
    for (const w of rep.warnings) rows.push([w.check, w.message]);
    rows.push(['label space', `${rep.label_space}, ${rep.cells_out.join(' × ')} cells`]);
    rows.push(['nodes', `${rep.nodes}`]);
    rows.push(['labels', `${rep.labels}`]);
    rows.push(['cycles', `${rep.cycles}, energy ${fmt(rep.energy, 4)}` + (rep.seam_energy ? ` (${rep.seam_energy})` : '')]);
    if (rep.seams) {
      const over = rep.seams.filter((s) => s.mismatch > rep.seam_tolerance).length;
      rows.push(['worst seam', `${fmt(rep.max_seam_mismatch, 3)} ${m.units} (tolerance ` +
                 `${fmt(rep.seam_tolerance, 3)})` + (over ? `: ${over} over, in red` : '')]);
    }
    rows.push(['solve', `${fmt(rep.timings_ms.solve || 0, 3)} ms (energy ${fmt(rep.timings_ms.energy || 0, 3)} ms, ` +
                        `stitch ${fmt(rep.timings_ms.stitch || 0, 3)} ms)`]);
    rows.push(['resize', `${fmt(r.pageMs, 3)} ms in the page (${fmt(r.ms, 3)} ms in the worker)`]);
  }
  return rows;
}

export class Panel {
  #sliders = [];
  #sizeFields = [];
  #sizes = { s1: 0, s2: 0, s3: 0 };  // what the size fields show
  #sizeAxes = [];                    // per principal offset, the world axis its size field is about
  #sliderBase = { extents: [], lengths: [], units: 'm' };  // per principal offset, for the slider names
  #sampleController = null;
  #candidateControls = [];

  constructor(settings, elements) {
    this.settings = settings;
    this.el = elements;
    this.gui = new GUI({ title: 'restitch' });
    this.modelFolder = this.gui.addFolder('Model');
    this.analysisFolder = this.gui.addFolder('Analysis');
    this.candidatesFolder = this.gui.addFolder('Candidates');
    this.resizeFolder = this.gui.addFolder('Resize');
    this.viewFolder = this.gui.addFolder('View');
  }

  build({ samples, policies }, on) {
    const s = this.settings;
    this.#sampleController = this.modelFolder.add(s, 'sample', samples).name('bundled sample').onChange(on.sample);
    this.modelFolder.add({ open: on.open }, 'open').name('open .glb / .gltf…');
    this.modelFolder.add({ download: on.download }, 'download').name('download .glb');
    this.analysisFolder.add(s, 'descriptor', policies.descriptors).onChange(on.policy);
    this.analysisFolder.add(s, 'matcher', policies.matchers).onChange(on.policy);
    if (policies.detectors) this.analysisFolder.add(s, 'detector', policies.detectors).onChange(on.policy);
    this.resizeFolder.add(s, 'labelSpace', policies.label_spaces).name('label space').onChange(on.labelSpace);
    if (policies.pivots) this.resizeFolder.add(s, 'pivot', policies.pivots).name('pivot (stays put)').onChange(on.pivot);
    if (policies.seam_energies)
      this.resizeFolder.add(s, 'seamEnergy', policies.seam_energies).name('seam energy').onChange(on.seamEnergy);
    this.viewFolder.add(s, 'view', { shaded: 'shaded', 'cells by label': 'labels', seams: 'seams' }).onChange(on.view);
    this.viewFolder.add(s, 'offsets').name('principal offsets').onChange(on.offsets);
    this.viewFolder.add(s, 'histogram').name('offset histogram').onChange(on.histogram);
  }

  // The root panel's element (its width is an overlay the view centres around), or null before build().
  get element() {
    return this.gui.domElement;
  }

  // Slider i moves along principal offset v_i, the i-th resizable lattice axis (analysis.resizable, in the
  // order of lattice_axes; restitch::lattice_steps_from_principal), from one cell left up to about twice the
  // cells there are.
  buildSliders(analysis, model, onSteps, onSize = null) {
    for (const c of [...this.#sliders, ...this.#sizeFields]) c.destroy();
    this.#sliders = [];
    this.#sizeFields = [];
    const steps = this.settings.steps;
    steps.v1 = steps.v2 = steps.v3 = 0;
    this.#sliderBase = {
      extents: analysis.principal_offsets.map((v) => extentAlong(model.inputMesh.positions, v)),
      lengths: analysis.principal_offsets.map(norm),
      units: model.units,
    };
    const resizable = [0, 1, 2].filter((c) => analysis.resizable[c]);
    analysis.principal_offsets.forEach((v, i) => {
      const cells = analysis.lattice_cells[resizable[i]];
      const c = this.resizeFolder.add(steps, `v${i + 1}`, 1 - cells, Math.min(24, Math.max(6, 2 * cells)), 1)
                                 .onChange(() => { this.#nameSliders(); onSteps(); });
      this.#sliders.push(c);
    });
    // The size fields: the world axis each principal offset runs along most.
    this.#sizeAxes = analysis.principal_offsets.map((v) => v.map(Math.abs).indexOf(Math.max(...v.map(Math.abs))));
    if (onSize) {
      this.#sizeAxes.forEach((axis, i) => {
        const c = this.resizeFolder.add(this.#sizes, `s${i + 1}`).name(`v${i + 1} exact size (${'xyz'[axis]}), ${model.units}`)
                                   .onFinishChange((value) => onSize(i, Number(value)));
        c.domElement.dataset.size = String(i);
        c.domElement.title = 'type a size: the nearest whole repeats, scaled about the pivot to this size exactly';
        this.#sizeFields.push(c);
      });
    }
    this.showSizes(sizeOf(model.info));
    this.#nameSliders();
  }

  // The world axis the size field of principal offset i is about.
  sizeAxis(i) {
    return this.#sizeAxes[i];
  }

  showSizes(size) {
    this.#sizeAxes.forEach((axis, i) => { this.#sizes[`s${i + 1}`] = Number(fmt(size[axis], 4)); });
    for (const c of this.#sizeFields) c.updateDisplay();
  }

  // Candidates: repeats the analysis found but does not resize along (a pair, or weaker than a parallel
  // principal offset). A click promotes one (it becomes a principal offset, and a slider moves along it);
  // 'detected offsets' undoes the promotions. Each button's element carries data-candidate="i" (or
  // data-detected) for automated checks.
  buildCandidates(analysis, model, promoted, on) {
    for (const c of this.#candidateControls) c.destroy();
    this.#candidateControls = [];
    const longest = Math.max(...model.info.bbox_max.map((x, k) => x - model.info.bbox_min[k]));
    (analysis.candidates || []).forEach((cand, i) => {
      const c = this.candidatesFolder.add({ promote: () => on.promote(cand.offset) }, 'promote')
                                     .name(`${i + 1}: ${candidateLabel(cand, model.units, longest)}`);
      c.domElement.dataset.candidate = String(i);
      c.domElement.title = 'make this offset principal: a resize slider then moves along it';
      this.#candidateControls.push(c);
    });
    if (!this.#candidateControls.length) {
      const c = this.candidatesFolder.add({ none: () => {} }, 'none').name('none').disable();
      this.#candidateControls.push(c);
    }
    const back = this.candidatesFolder.add({ detected: on.detected }, 'detected')
                                      .name('↺ detected offsets');
    back.domElement.dataset.detected = '';
    back.domElement.title = 'undo the promotions: back to the offsets the analysis chose';
    if (!promoted.length) back.disable();
    this.#candidateControls.push(back);
  }

  refresh() {
    for (const c of this.gui.controllersRecursive()) c.updateDisplay();
    this.#nameSliders();
  }

  #nameSliders() {
    const { extents, lengths, units } = this.#sliderBase;
    this.#sliders.forEach((c, i) => {
      const k = this.settings.steps[`v${i + 1}`];
      c.name(`v${i + 1} steps → ${fmt(extents[i] + k * lengths[i])} ${units}`);
    });
  }

  showFigures(state) {
    const table = document.createElement('table');
    for (const [k, v] of figureRows(state)) {
      const tr = table.insertRow();
      tr.insertCell().textContent = k;
      tr.insertCell().textContent = v;
    }
    this.el.figures.replaceChildren(table);
  }

  showProgress(stage, fraction) {
    this.el.progress.hidden = stage === null;
    if (stage === null) return;
    const i = Math.max(0, STAGES.indexOf(stage));
    const total = (i + Math.min(Math.max(fraction, 0), 1)) / STAGES.length;
    this.el.progressLabel.textContent = `analysing: ${stage} ${Math.round(fraction * 100)}%`;
    this.el.progressFill.style.width = `${(total * 100).toFixed(1)}%`;
  }

  showError(message, retry = null) {
    this.el.error.textContent = message;
    this.el.error.hidden = !message;
    if (message && retry) {  // a button that tries again (a failed start)
      const button = document.createElement('button');
      button.id = 'retry';
      button.textContent = 'Retry';
      button.addEventListener('click', () => retry());
      this.el.error.append(' ', button);
    }
  }
}
