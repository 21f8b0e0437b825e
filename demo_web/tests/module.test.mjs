// Node tests of the WebAssembly module (npm/dist/restitch_web.mjs) through the package's loader (npm/index.js):
// bytes in, analyze, retarget, .glb bytes out that the Khronos glTF-Validator accepts.
// Run: node --test demo_web/tests/module.test.mjs (after building the module; tests/run.sh does both).
import test from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';
import { loadRestitch } from '../npm/index.js';
import { WorkerClient } from '../src/worker-client.js';
import { Session as PageSession } from '../src/session.js';

const here = path.dirname(fileURLToPath(import.meta.url));
const require = createRequire(path.join(here, '../package.json'));
const validator = require('gltf-validator');
const modelsDir = path.resolve(here, '../../../shared/models');
const restitch = await loadRestitch();

async function validate(bytes) {
  const report = await validator.validateBytes(bytes, { maxIssues: 50 });
  return report.issues;
}

// The JSON chunk of a .glb.
function glbJson(bytes) {
  const dv = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  assert.equal(dv.getUint32(0, true), 0x46546c67, 'glTF magic');
  const length = dv.getUint32(12, true);
  return JSON.parse(new TextDecoder().decode(bytes.subarray(20, 20 + length)));
}

// A minimal .gltf (JSON, data-URI buffer) holding one tetrahedron: nothing repeats in it.
function tetrahedronGltf() {
  const pos = new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1]);
  const idx = new Uint16Array([0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3]);
  const bin = new Uint8Array(pos.byteLength + idx.byteLength);
  bin.set(new Uint8Array(pos.buffer), 0);
  bin.set(new Uint8Array(idx.buffer), pos.byteLength);
  const gltf = {
    asset: { version: '2.0' },
    scene: 0, scenes: [{ nodes: [0] }], nodes: [{ mesh: 0 }],
    meshes: [{ primitives: [{ attributes: { POSITION: 0 }, indices: 1 }] }],
    buffers: [{ byteLength: bin.byteLength, uri: `data:application/octet-stream;base64,${Buffer.from(bin).toString('base64')}` }],
    bufferViews: [{ buffer: 0, byteOffset: 0, byteLength: pos.byteLength },
                  { buffer: 0, byteOffset: pos.byteLength, byteLength: idx.byteLength }],
    accessors: [{ bufferView: 0, componentType: 5126, count: 4, type: 'VEC3', min: [0, 0, 0], max: [1, 1, 1] },
                { bufferView: 1, componentType: 5123, count: 12, type: 'SCALAR' }],
  };
  return new TextEncoder().encode(JSON.stringify(gltf));
}

const near = (a, b, tol) => Math.abs(a - b) <= tol;

// One analysed bookshelf shared by the tests below (analysis is the slow part), with the default policies.
const shelf = new restitch.Session();
const shelfInfo = shelf.loadSample('bookshelf', {});
const progress = [];
const shelfAnalysis = shelf.analyze('shot', 'reduced', (stage, f) => progress.push([stage, f]));

test('the module lists its samples and policies', () => {
  const names = restitch.samples().map((s) => s.name);
  // The library's catalog (restitch/families/families.hpp), in its alphabetical order: the plain families and
  // those with structure around the repeat (restitch/families/structured.hpp).
  assert.deepEqual(names, ['bookshelf', 'box_header', 'cabinet', 'connector', 'dip', 'facade', 'facade_sheared',
                           'fence', 'pin_header', 'radiator', 'railing', 'shutter', 'tube_rail']);
  const p = restitch.policies();
  // The library's lists (restitch/runtime.hpp), the default first: the page preselects the first.
  assert.deepEqual(p.descriptors, ['shot', 'fpfh']);
  assert.deepEqual(p.matchers, ['brute_force', 'reduced']);
  assert.deepEqual(p.detectors, ['histogram', 'autocorrelation']);
  assert.deepEqual(p.label_spaces, ['lattice', 'regular']);
  assert.deepEqual(p.pivots, ['origin', 'min', 'center', 'max']);
  assert.deepEqual(p.seam_energies, ['descriptor', 'geometry']);
  assert.match(restitch.version(), /^restitch \d+\.\d+\.\d+$/);
});

test('bad bytes and bad requests give a status in words, never a throw', () => {
  const s = new restitch.Session();
  try {
    let r = s.loadGltf(new Uint8Array([1, 2, 3, 4]));
    assert.equal(r.ok, false);
    assert.equal(r.code, 'parse_error');
    assert.match(r.message, /glTF/);
    // A .glb header that promises more bytes than there are.
    const truncated = new Uint8Array(20);
    new DataView(truncated.buffer).setUint32(0, 0x46546c67, true);
    new DataView(truncated.buffer).setUint32(4, 2, true);
    new DataView(truncated.buffer).setUint32(8, 4000, true);
    r = s.loadGltf(truncated);
    assert.equal(r.ok, false);
    assert.ok(r.message.length > 10, r.message);
    r = s.loadSample('no_such_sample', {});
    assert.equal(r.code, 'invalid_argument');
    assert.match(r.message, /bookshelf/);
    r = s.analyze('shot', 'brute_force', null);
    assert.equal(r.ok, false, 'analysis before any model');
    assert.equal(s.retarget(1, 0, 0, 'lattice').ok, false, 'retarget before analysis');
    assert.equal(s.loadSample('bookshelf', { columns: 2 }).ok, true);
    r = s.analyze('nope', 'brute_force', null);
    assert.equal(r.code, 'invalid_argument');
    assert.match(r.message, /shot, fpfh/, 'the known descriptors are listed');
    r = s.analyze('shot', 'nope', null);
    assert.equal(r.code, 'invalid_argument');
    assert.match(r.message, /brute_force, reduced/, 'the known matchers are listed');
    assert.equal(s.mesh('result').ok, false, 'no result yet');
  } finally {
    s.delete();
  }
});

test('a sample loads with the size of its parameters', () => {
  assert.equal(shelfInfo.ok, true);
  assert.ok(shelfInfo.triangles > 1000 && shelfInfo.triangles < 6000, `${shelfInfo.triangles}`);
  // Defaults: 4 columns of 0.4 m plus two 0.02 m side panels.
  assert.ok(near(shelfInfo.bbox_max[0] - shelfInfo.bbox_min[0], 4 * 0.4 + 0.02, 1e-5));
  const m = shelf.mesh('input');
  assert.equal(m.positions.length, shelfInfo.vertices * 3);
  assert.equal(m.indices.length, shelfInfo.triangles * 3);
  assert.equal(m.groups.reduce((n, g) => n + g.count, 0), m.indices.length, 'draw ranges cover every face once');
  assert.ok(Math.max(...m.indices) < shelfInfo.vertices);
});

test('analysis finds the bookshelf generators as principal offsets (model units)', () => {
  assert.equal(shelfAnalysis.ok, true, shelfAnalysis.message);
  const a = shelfAnalysis.analysis;
  // Exactly the fields of `restitch analyze --json` (restitch/io/json_report.hpp).
  assert.deepEqual(Object.keys(a).sort(),
                   ['candidates', 'descriptor', 'detector', 'dominant_offsets', 'dummy_directions', 'features', 'lattice_axes',
                    'lattice_cells', 'lattice_origin', 'matcher', 'principal_offsets', 'resizable', 'scale', 'sparsity',
                    'timings_ms']);
  assert.equal(a.descriptor, 'shot');
  assert.equal(a.matcher, 'reduced');
  assert.equal(a.detector, 'histogram');
  // The principal offsets are the lattice's resizable (non-dummy) axes, in order (what the retarget steps refer to).
  const dummy = (c) => a.dummy_directions.some((d) => d.every((x, k) => x === a.lattice_axes[c][k]));
  assert.deepEqual(a.resizable, [0, 1, 2].map((c) => !dummy(c)), 'resizable is false exactly on the dummy directions');
  const real = [0, 1, 2].filter((c) => a.resizable[c]);
  assert.equal(real.length, a.principal_offsets.length);
  real.forEach((c, i) => assert.ok(a.principal_offsets[i].every((x, k) => near(x, a.lattice_axes[c][k], 1e-9))));
  assert.ok(near(a.scale, 2 / 1.62, 1e-6), `scale ${a.scale}`);
  assert.equal(a.principal_offsets.length, 2);
  assert.equal(a.dummy_directions.length, 1);
  const gens = shelfInfo.generators;  // (0.4, 0, 0) and (0, 0.35, 0)
  for (const g of gens) {
    const hit = a.principal_offsets.some((v) => [1, -1].some((s) => v.every((x, i) => near(s * x, g[i], 2e-3))));
    assert.ok(hit, `generator ${g} among ${JSON.stringify(a.principal_offsets)}`);
  }
  assert.ok(a.lattice_cells.slice(0, 2).every((c) => c >= 4 && c <= 6), `cells ${a.lattice_cells}`);
  assert.ok(a.dominant_offsets[0].votes >= a.dominant_offsets.at(-1).votes, 'dominant offsets ranked by votes');
  // Every dominant offset explains itself: the tests it ran, and the one that rejected it (null when none did).
  for (const d of a.dominant_offsets) {
    assert.ok(d.tests.length >= 1 && d.tests[0].name === 'votes', JSON.stringify(d.tests));
    for (const t of d.tests) {
      assert.deepEqual(Object.keys(t).sort(), ['at_most', 'name', 'passed', 'threshold', 'value']);
      assert.equal(t.passed, t.at_most ? t.value <= t.threshold : t.value >= t.threshold, JSON.stringify(t));
    }
    const failed = d.tests.find((t) => !t.passed);
    assert.equal(d.rejected_by, failed ? failed.name : null);
    assert.equal(d.promoted, false);
  }
  // Progress went through every stage, in order, ending at 1.
  const stages = [...new Set(progress.map(([s]) => s))];
  for (const s of ['sampling', 'descriptors', 'matching', 'lattice']) assert.ok(stages.includes(s), s);
  assert.deepEqual(progress.at(-1), ['lattice', 1]);
  const e = shelfAnalysis.extras;
  assert.equal(e.dominant_normalized.length, a.dominant_offsets.length);
  e.dominant_normalized.forEach((d, i) =>
    assert.ok(d.every((x, k) => near(x / a.scale, a.dominant_offsets[i].offset[k], 1e-9)), 'normalized = scale x model'));
  assert.equal(e.match_offsets.length % 3, 0);
  assert.ok(e.match_offsets.length / 3 > a.features / 2);
});

test('retarget grows and shrinks by whole repeats, and the .glb validates', async () => {
  const a = shelfAnalysis.analysis;
  const v1 = a.principal_offsets[0];
  const len1 = Math.hypot(...v1);
  const axis = v1.map(Math.abs).indexOf(Math.max(...v1.map(Math.abs)));
  for (const k of [1, 2, -1]) {
    const r = shelf.retarget(k, 0, 0, 'lattice');
    assert.equal(r.ok, true, r.message);
    const rep = r.report;
    assert.ok(near(rep.size_out[axis] - rep.size_in[axis], k * len1, 2e-3), `k=${k}: ${rep.size_out} vs ${rep.size_in}`);
    // The fields of `restitch resize --json`: steps along the principal offsets and on the lattice, cells.
    assert.deepEqual(rep.steps_principal, [k, 0]);
    assert.deepEqual(rep.steps, [k, 0, 0]);
    assert.deepEqual(rep.cells_in, a.lattice_cells);
    assert.deepEqual(rep.cells_out, [a.lattice_cells[0] + k, a.lattice_cells[1], a.lattice_cells[2]]);
    assert.equal(rep.label_space, 'lattice');
    const out = rep.output.triangles;
    assert.ok(k > 0 ? out > shelfInfo.triangles : out < shelfInfo.triangles, `k=${k}`);
    assert.ok(rep.nodes > 0 && rep.labels === Math.abs(k) + 1, `labels ${rep.labels}`);
    const m = shelf.mesh('result');
    assert.equal(m.indices.length, out * 3);
    assert.equal(m.positions.length, rep.output.vertices * 3);
    assert.equal(r.face_labels.length, out);
    assert.equal(r.cell_labels.length, rep.cells_out[0] * rep.cells_out[1] * rep.cells_out[2]);
    assert.equal(r.label_shifts.length, rep.labels * 3);
    assert.ok(r.face_labels.every((l) => l >= 0 && l < rep.labels));
    const glb = shelf.saveGlb('result');
    assert.equal(glb.ok, true);
    const issues = await validate(glb.bytes);
    assert.equal(issues.numErrors, 0, JSON.stringify(issues.messages.slice(0, 5)));
    // Round trip: the saved bytes load back as the same mesh size.
    const back = new restitch.Session();
    const info = back.loadGltf(glb.bytes);
    back.delete();
    assert.equal(info.ok, true);
    assert.equal(info.triangles, out);
  }
  // Steps of zero give the input back; shrinking past one cell and steps along the dummy axis are refused.
  const same = shelf.retarget(0, 0, 0, 'lattice');
  assert.equal(same.report.output.triangles, shelfInfo.triangles);
  const cells = a.lattice_cells[0];
  const tooSmall = shelf.retarget(-cells, 0, 0, 'lattice');
  assert.equal(tooSmall.ok, false);
  assert.match(tooSmall.message, /shrink/);
  const third = shelf.retarget(0, 0, 1, 'lattice');
  assert.equal(third.code, 'invalid_argument', 'the bookshelf has no third principal offset');
  assert.match(third.message, /2 principal offset/);
  const unknown = shelf.retarget(1, 0, 0, 'hexagonal');
  assert.equal(unknown.code, 'invalid_argument');
  assert.match(unknown.message, /lattice, regular/);
  // A refused label space keeps the session usable.
  assert.equal(shelf.retarget(1, 0, 0, 'lattice').ok, true);
});

test('the pivot stays put: max keeps the far end, center splits, origin is the default, a bad one is refused', () => {
  // The bookshelf's origin is its min corner: by default growth goes to +x, and nothing moves.
  const plain = shelf.retarget(2, 0, 0, 'lattice');
  assert.equal(plain.ok, true, plain.message);
  assert.deepEqual(plain.report.pivot.modes, ['origin', 'origin', 'origin']);
  assert.deepEqual(plain.report.pivot.translation, [0, 0, 0]);
  const v1 = shelfAnalysis.analysis.principal_offsets[0];
  const max = shelf.retarget(2, 0, 0, 'lattice', 'max');
  assert.equal(max.ok, true, max.message);
  assert.deepEqual(max.report.pivot.modes, ['max', 'max', 'max']);
  assert.ok(near(max.report.pivot.translation[0], -2 * v1[0], 1e-6), JSON.stringify(max.report.pivot));
  assert.deepEqual(max.report.pivot.low_end_cells, [2, 0, 0]);
  // The label grid moves with the result.
  assert.ok(near(max.grid.origin[0], plain.grid.origin[0] - 2 * v1[0], 1e-6));
  const center = shelf.retarget(3, 0, 0, 'lattice', 'center,origin,origin');
  assert.equal(center.ok, true, center.message);
  assert.deepEqual(center.report.pivot.low_end_cells, [1, 0, 0], 'the odd column goes to the max side');
  // Where the centre stays, the result is centred where the input was: half the growth at each end,
  // half a column more than the whole cells at an odd count (docs/method.md 2.7).
  assert.ok(near(center.report.pivot.translation[0], -1.5 * v1[0], 1e-6), JSON.stringify(center.report.pivot));
  const bad = shelf.retarget(1, 0, 0, 'lattice', 'middle');
  assert.equal(bad.ok, false);
  assert.equal(bad.code, 'invalid_argument');
  assert.match(bad.message, /origin, min, center, max/);
});

test('every seam is reported with its mismatch; the seam energy is chosen by name', () => {
  const geo = shelf.retarget(2, 0, 0, 'lattice', 'origin', 'geometry');
  assert.equal(geo.ok, true, geo.message);
  assert.equal(geo.report.seam_energy, 'geometry');
  assert.ok(geo.report.seams.length > 0);
  assert.ok(geo.report.max_seam_mismatch <= geo.report.seam_tolerance, 'an exact resize has no seam over the tolerance');
  assert.deepEqual(geo.report.warnings, []);
  assert.equal(geo.seam_faces.length, geo.face_labels.length);
  assert.ok(geo.seam_faces.every((f) => f === 0));
  assert.equal(geo.report.checked, true, 'the result check ran');
  assert.equal(geo.report.boundary_edges.new, 0);
  assert.ok(geo.open_edges instanceof Float32Array && geo.open_edges.length === 0);
  const desc = shelf.retarget(2, 0, 0, 'lattice', 'origin', 'descriptor');
  assert.equal(desc.ok, true, desc.message);
  assert.equal(desc.report.seam_energy, 'descriptor');
  const unknown = shelf.retarget(2, 0, 0, 'lattice', 'origin', 'hausdorff');
  assert.equal(unknown.ok, false);
  assert.match(unknown.message, /descriptor, geometry/);
  assert.equal(shelf.retarget(2, 0, 0, 'lattice').report.seam_energy, 'descriptor', 'the default');
});

test('the regular baseline needs more nodes for the same request', () => {
  const lattice = shelf.retarget(1, 0, 0, 'lattice');
  const regular = shelf.retarget(1, 0, 0, 'regular');
  assert.equal(regular.ok, true, regular.message);
  assert.equal(regular.report.label_space, 'regular');
  assert.ok(regular.report.nodes > lattice.report.nodes, `${regular.report.nodes} vs ${lattice.report.nodes}`);
  assert.ok(near(regular.report.size_out[0], lattice.report.size_out[0], 0.1 * 1.62 / 2 + 1e-6));
});

test('the same requests give the same bytes; the reduced matcher gives what brute force gives', () => {
  const s = new restitch.Session();
  try {
    s.loadSample('bookshelf', {});
    // The reference matcher in a second session: the reduced one (the shelf's) is exact, so everything agrees.
    const b = s.analyze('shot', 'brute_force', null);
    assert.equal(b.ok, true, b.message);
    const strip = (x) => ({ ...x, matcher: '', timings_ms: {} });
    assert.deepEqual(strip(b.analysis), strip(shelfAnalysis.analysis));
    assert.deepEqual(b.extras.match_offsets, shelfAnalysis.extras.match_offsets);
    assert.equal(s.retarget(2, 1, 0, 'lattice').ok, true);
    assert.equal(shelf.retarget(2, 1, 0, 'lattice').ok, true);
    assert.deepEqual(s.saveGlb('result').bytes, shelf.saveGlb('result').bytes);
  } finally {
    s.delete();
  }
});

// The extent of a mesh's positions along world axis k (0: x, 1: y, 2: z).
function extent(mesh, k) {
  let lo = Infinity, hi = -Infinity;
  for (let i = k; i < mesh.positions.length; i += 3) {
    lo = Math.min(lo, mesh.positions[i]);
    hi = Math.max(hi, mesh.positions[i]);
  }
  return hi - lo;
}
const xSize = (mesh) => extent(mesh, 0);
const ySize = (mesh) => extent(mesh, 1);
// The pin header's pitch, 2.54 mm along x.
const isPitch = (v) => near(Math.abs(v[0]), 2.54, 2e-3) && near(v[1], 0, 2e-3) && near(v[2], 0, 2e-3);
// The fence (default parameters): its pickets' pitch, 0.15 m along x, and the offset between its two rails,
// 0.55 m along y (rails centred at 0.2 and 0.75 of the 1 m pickets). The fence stands 1.19 m tall (its posts).
const isPicketPitch = (v) => near(Math.abs(v[0]), 0.15, 2e-3) && near(v[1], 0, 2e-3) && near(v[2], 0, 2e-3);
const isRail = (v) => near(v[0], 0, 2e-3) && near(Math.abs(v[1]), 0.55, 2e-3) && near(v[2], 0, 2e-3);
const fenceHeight = 1.19;

test('the 2-pin header: its pitch is principal offset 1 (two exact copies), a resize grows it to 3 pins without promotion', () => {
  const s = new restitch.Session();
  try {
    const info = s.loadSample('pin_header', { pins: 2 });
    assert.ok(near(info.bbox_max[0] - info.bbox_min[0], 5.68, 1e-4), 'two pitches of 2.54 mm plus the ends');
    const r = s.analyze('shot', 'brute_force', null);
    assert.equal(r.ok, true, r.message);
    const a = r.analysis;
    assert.equal(a.principal_offsets.length, 1, JSON.stringify(a.principal_offsets));
    assert.ok(isPitch(a.principal_offsets[0]), `the pitch is principal offset 1: ${JSON.stringify(a.principal_offsets)}`);
    assert.ok(!a.candidates.some((k) => isPitch(k.offset)), `the pitch is no candidate: ${JSON.stringify(a.candidates)}`);
    // docs/method.md 1.13: significant by the two-copies tests, not promoted by hand.
    const d = a.dominant_offsets.find((x) => isPitch(x.offset));
    assert.ok(d, 'the pitch is a dominant offset');
    assert.equal(d.significant, true);
    assert.equal(d.rejected_by, null);
    assert.equal(d.promoted, false);
    for (const name of ['pair_exact_vertices', 'pair_exact_area', 'pair_third_copy'])
      assert.ok(d.tests.some((t) => t.name === name && t.passed), `${name} passed: ${JSON.stringify(d.tests)}`);
    assert.equal(a.lattice_cells[a.resizable.indexOf(true)], 2, 'two cells along the pitch');

    const t = s.retarget(1, 0, 0, 'lattice');
    assert.equal(t.ok, true, t.message);
    assert.deepEqual(t.report.steps_principal, [1]);
    assert.ok(near(xSize(s.mesh('result')), 8.22, 1e-3), `3 pins: ${xSize(s.mesh('result'))} mm, expected 8.22`);
    assert.ok(near(t.report.size_out[0], 8.22, 1e-3), `size_out ${t.report.size_out}`);
    assert.ok(t.report.output.triangles > info.triangles);
    const second = s.retarget(0, 1, 0, 'lattice');
    assert.equal(second.code, 'invalid_argument', 'one principal offset only');
    assert.match(second.message, /1 principal offset/);
  } finally {
    s.delete();
  }
});

test('the fence: its two rails are a pair candidate with the failed test named; promoting it resizes along y, [] undoes it', () => {
  const s = new restitch.Session();
  try {
    assert.equal(s.promote([[0, 0.55, 0]]).code, 'invalid_argument', 'promotion before any analysis');
    const info = s.loadSample('fence', {});
    assert.ok(near(info.bbox_max[1] - info.bbox_min[1], fenceHeight, 1e-4), `height ${info.bbox_max[1] - info.bbox_min[1]}`);
    const r = s.analyze('shot', 'brute_force', null);
    assert.equal(r.ok, true, r.message);
    const a = r.analysis;
    assert.equal(a.principal_offsets.length, 1, JSON.stringify(a.principal_offsets));
    assert.ok(isPicketPitch(a.principal_offsets[0]), JSON.stringify(a.principal_offsets));
    // A size change along y (a step along a second principal offset) is refused in words before the promotion.
    const refused = s.retarget(0, 1, 0, 'lattice');
    assert.equal(refused.code, 'invalid_argument');
    assert.match(refused.message, /the model has 1 principal offset/);
    const c = a.candidates.find((k) => isRail(k.offset));
    assert.ok(c, `the rails' offset among the candidates ${JSON.stringify(a.candidates)}`);
    assert.equal(c.reason, 'pair');
    assert.equal(c.copies, 2);
    const d = a.dominant_offsets[c.dominant];
    assert.ok(isRail(d.offset), 'the candidate names its dominant offset');
    assert.equal(d.significant, false);
    assert.ok(d.rejected_by, 'a test rejected it');
    assert.equal(d.rejected_by, d.tests.find((t) => !t.passed).name, 'the first failed test');
    assert.ok(!d.tests.some((t) => t.name.startsWith('pair_') && t.passed), 'the two-copies rule did not pass it');

    const p = s.promote([c.offset]);
    assert.equal(p.ok, true, p.message);
    const q = p.analysis;
    assert.equal(q.principal_offsets.length, 2, JSON.stringify(q.principal_offsets));
    assert.ok(isRail(q.principal_offsets[0]), 'the promoted offset comes first');
    assert.ok(isPicketPitch(q.principal_offsets[1]), 'the detected one after it');
    assert.equal(q.dominant_offsets[c.dominant].promoted, true);
    assert.ok(!q.candidates.some((k) => isRail(k.offset)), 'no longer a candidate');
    const axes = [0, 1, 2].filter((k) => q.resizable[k]);
    assert.equal(q.lattice_cells[axes[0]], 2, 'two cells along the rails\' offset');
    assert.equal(p.extras.dominant_normalized.length, q.dominant_offsets.length);
    const t = s.retarget(1, 0, 0, 'lattice');
    assert.equal(t.ok, true, t.message);
    assert.deepEqual(t.report.steps_principal, [1, 0]);
    const tall = fenceHeight + Math.hypot(...c.offset);  // about 1.74 m: one more rail-pair period
    assert.ok(near(t.report.size_out[1], tall, 1e-3), `size_out ${t.report.size_out}, expected ${tall} tall`);
    assert.ok(near(ySize(s.mesh('result')), tall, 1e-3), `${ySize(s.mesh('result'))} m tall`);
    assert.ok(near(t.report.size_out[0], t.report.size_in[0], 1e-3), 'as wide as before');
    const wider = s.retarget(0, 1, 0, 'lattice');  // the pickets' pitch is principal offset 2 now
    assert.equal(wider.ok, true, wider.message);
    assert.ok(near(wider.report.size_out[0] - wider.report.size_in[0], 0.15, 1e-3), `size_out ${wider.report.size_out}`);

    const back = s.promote([]);
    assert.equal(back.ok, true, back.message);
    assert.equal(back.analysis.principal_offsets.length, 1, 'the detected offset again');
    assert.ok(isPicketPitch(back.analysis.principal_offsets[0]));
    assert.ok(back.analysis.dominant_offsets.every((x) => !x.promoted));
    assert.ok(back.analysis.candidates.some((k) => isRail(k.offset)), 'a candidate again');
    assert.equal(s.mesh('result').ok, false, 'the result of the promoted offsets is gone');
    assert.match(s.retarget(0, 1, 0, 'lattice').message, /the model has 1 principal offset/);
  } finally {
    s.delete();
  }
});

test('a refused promotion leaves the analysis and the last result as they were', () => {
  const s = new restitch.Session();
  try {
    s.loadSample('fence', {});
    const a = s.analyze('shot', 'brute_force', null).analysis;
    const c = a.candidates.find((k) => isRail(k.offset));
    assert.ok(c, JSON.stringify(a.candidates));
    const p = s.promote([c.offset]);
    assert.equal(p.ok, true, p.message);
    const before = s.retarget(1, 0, 0, 'lattice');
    assert.equal(before.ok, true, before.message);
    const bytes = s.saveGlb('result').bytes;
    for (const bad of [[[0, 0, 0]], [c.offset, c.offset.map((x) => -x)], [[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]],
                       [[1, 2]], [['1', 0, 0]], 'x', null]) {
      const r = s.promote(bad);
      assert.equal(r.ok, false, JSON.stringify(bad));
      assert.equal(r.code, 'invalid_argument', JSON.stringify(bad));
      assert.ok(r.message.length > 10, r.message);
    }
    assert.deepEqual(s.saveGlb('result').bytes, bytes, 'the result is still there');
    const again = s.retarget(1, 0, 0, 'lattice');
    assert.equal(again.ok, true, again.message);
    assert.deepEqual(again.report, { ...before.report, timings_ms: again.report.timings_ms },
                     'the same principal offsets as before the refused requests');
  } finally {
    s.delete();
  }
});

// ../src/worker.js run in this process: its `self` is a stand-in whose postMessage answers the one fake Worker
// the client made (asynchronously, as a real worker does).
async function inProcessWorker() {
  let current = null;
  globalThis.self = { postMessage: (data) => setImmediate(() => current && current.onmessage({ data })) };
  await import('../src/worker.js');
  const handle = globalThis.self.onmessage;
  return () => {
    current = { postMessage: (data) => setImmediate(() => handle({ data })), terminate: () => { current = null; } };
    return current;
  };
}

test('the page\'s session through worker.js: the 2-pin header resizes to 3 pins; the fence\'s rail candidate promoted, a resize along y', async () => {
  const session = new PageSession(new WorkerClient(await inProcessWorker()),
                                  { policy: () => ({ descriptor: 'shot', matcher: 'brute_force', detector: 'histogram' }) });
  const catalog = await session.start();
  assert.deepEqual(catalog.policies.detectors, ['histogram', 'autocorrelation']);
  // The 2-pin header: ready as analysed, its pitch principal offset 1.
  await session.load({ sample: { name: 'pin_header', params: { pins: 2 } } });
  assert.equal(session.state.status, 'ready', session.state.error);
  assert.ok(isPitch(session.state.analysis.principal_offsets[0]), JSON.stringify(session.state.analysis.principal_offsets));
  await session.resize([1, 0, 0], 'lattice');
  assert.ok(near(xSize(session.state.retarget.mesh), 8.22, 1e-3), `${xSize(session.state.retarget.mesh)} mm`);

  // The fence: one principal offset, so a step along a second is refused in words (the error state), until the
  // rails' candidate is promoted.
  await session.load({ sample: { name: 'fence', params: {} } });
  assert.equal(session.state.status, 'ready', session.state.error);
  assert.equal(session.state.analysis.principal_offsets.length, 1);
  await assert.rejects(session.resize([0, 1, 0], 'lattice'), /the model has 1 principal offset/);
  assert.equal(session.state.status, 'error');
  assert.match(session.state.error, /^Resize failed: the model has 1 principal offset/);
  const c = session.state.analysis.candidates.find((k) => isRail(k.offset));
  assert.ok(c, JSON.stringify(session.state.analysis.candidates));
  const detected = session.state.analysis;
  await assert.rejects(session.promote([c.offset, c.offset]), /too close in direction/);
  assert.equal(session.state.analysis, detected, 'a refused promotion changes nothing');
  const a = await session.promote([c.offset]);
  assert.ok(isRail(a.principal_offsets[0]));
  assert.equal(session.state.status, 'ready');
  assert.equal(session.state.error, '');
  const shown = await session.resize([1, 0, 0], 'lattice');
  const tall = fenceHeight + Math.hypot(...c.offset);
  assert.ok(near(ySize(session.state.retarget.mesh), tall, 1e-3), `${ySize(session.state.retarget.mesh)} m, expected ${tall}`);
  assert.ok(shown.triangles > session.state.model.info.triangles);
  const back = await session.promote([]);
  assert.equal(back.principal_offsets.length, 1);
  assert.ok(isPicketPitch(back.principal_offsets[0]));
  assert.equal(session.state.status, 'ready', 'the detected offset still resizes');
  assert.equal(session.state.retarget, null, 'the input is shown again');
  await assert.rejects(session.resize([0, 1, 0], 'lattice'), /the model has 1 principal offset/);
});

test('the autocorrelation detector is a compiled choice; an unknown detector is refused in words', () => {
  const s = new restitch.Session();
  try {
    s.loadSample('fence', {});
    const r = s.analyze('shot', 'reduced', 'autocorrelation', null);
    assert.equal(r.ok, true, r.message);
    assert.equal(r.analysis.detector, 'autocorrelation');
    assert.ok(r.analysis.principal_offsets.length >= 1, JSON.stringify(r.analysis.principal_offsets));
    const bad = s.analyze('shot', 'reduced', 'nope', null);
    assert.equal(bad.code, 'invalid_argument');
    assert.match(bad.message, /histogram, autocorrelation/);
  } finally {
    s.delete();
  }
});

test('FPFH with the reduced matcher is a compiled choice too', () => {
  const s = new restitch.Session();
  try {
    s.loadSample('fence', {});
    const r = s.analyze('fpfh', 'reduced', null);
    assert.equal(r.ok, true, r.message);
    assert.equal(r.analysis.descriptor, 'fpfh');
    assert.equal(r.analysis.matcher, 'reduced');
    assert.ok(r.analysis.features > 0);
    assert.ok(r.analysis.principal_offsets.length >= 1, JSON.stringify(r.analysis.principal_offsets));
  } finally {
    s.delete();
  }
});

test('a model without repetition: no principal offsets, and a resize is refused in words', () => {
  const s = new restitch.Session();
  try {
    const info = s.loadGltf(tetrahedronGltf());
    assert.equal(info.ok, true, info.message);
    assert.equal(info.triangles, 4);
    const r = s.analyze('shot', 'brute_force', null);
    assert.equal(r.ok, true, r.message);
    assert.equal(r.analysis.principal_offsets.length, 0);
    assert.equal(r.analysis.dummy_directions.length, 3);
    assert.deepEqual(r.analysis.resizable, [false, false, false]);
    const t = s.retarget(1, 0, 0, 'lattice');
    assert.equal(t.ok, false);
    assert.equal(t.code, 'no_repetition');
    assert.match(t.message, /repetition/);
  } finally {
    s.delete();
  }
});

const screen = path.join(modelsDir, 'scopia_japanese_style_screen.glb');
test('a textured real model keeps its textures through a resize', { skip: !fs.existsSync(screen) && `${screen} is absent` }, async () => {
  const bytes = new Uint8Array(fs.readFileSync(screen));
  const s = new restitch.Session();
  try {
    const info = s.loadGltf(bytes);
    assert.equal(info.ok, true, info.message);
    const a = s.analyze('shot', 'reduced', null);
    assert.equal(a.ok, true, a.message);
    assert.ok(a.analysis.principal_offsets.length >= 1, 'the lattice rails repeat');
    const r = s.retarget(1, 0, 0, 'lattice');
    assert.equal(r.ok, true, r.message);
    assert.notEqual(r.report.output.triangles, info.triangles);
    const out = s.saveGlb('result').bytes;
    const issues = await validate(out);
    assert.equal(issues.numErrors, 0, JSON.stringify(issues.messages.slice(0, 5)));
    const jin = glbJson(bytes), jout = glbJson(out);
    assert.ok((jin.images || []).length >= 1);
    assert.equal((jout.images || []).length, jin.images.length, 'images kept');
    assert.equal((jout.textures || []).length, (jin.textures || []).length, 'textures kept');
    assert.equal((jout.materials || []).length, (jin.materials || []).length, 'materials kept');
  } finally {
    s.delete();
  }
});

test('a module that runs out of memory traps with Aborted(); trap.js reads it so; a fresh instance loads the next model', async () => {
  // 64 MB at most (the worker's ?memory=64): a 40 x 30 bookshelf (237k triangles) loads but its analysis
  // does not fit.
  const { trapAnswer } = await import('../src/trap.js');
  const small = await loadRestitch({ wasmMemory: new WebAssembly.Memory({ initial: 512, maximum: 1024 }) });
  const s = new small.Session();
  assert.ok(s.loadSample('bookshelf', { columns: 40, shelves: 30 }).ok);
  let trapped = null;
  const quiet = console.warn;  // the module prints 'Aborted()' on stderr
  console.warn = () => {};
  try {
    s.analyze('shot', 'brute_force', 'histogram', () => {});
  } catch (e) {
    trapped = e;
  } finally {
    console.warn = quiet;
  }
  assert.ok(trapped, 'the analysis did not run out of memory');
  assert.equal(trapAnswer(trapped, 'analyze', 64).code, 'out_of_memory', String(trapped));
  const fresh = await loadRestitch({ wasmMemory: new WebAssembly.Memory({ initial: 512, maximum: 1024 }) });
  const t = new fresh.Session();
  assert.ok(t.loadSample('pin_header', {}).ok);
  const a = t.analyze('shot', 'brute_force', 'histogram', () => {});
  assert.ok(a.ok, a.message);
  assert.ok(a.analysis.principal_offsets.length >= 1);
  t.delete();
});

// The native command-line tool, when built beside (tests/run.sh runs after the native build stage).
const nativeCli = process.env.RESTITCH_CLI || path.resolve(here, '../../build/native/restitch');

test('the module writes the same bytes as the native command-line tool, from the same input and options', { skip: !fs.existsSync(nativeCli) && `no native build at ${nativeCli}` }, async () => {
  // Same .glb in (written by the native tool), default policies, the same resize: byte-identical .glb out.
  const { execFileSync } = await import('node:child_process');
  const os = await import('node:os');
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'restitch-native-wasm-'));
  try {
    for (const [name, steps] of [['pin_header', [2, 0, 0]], ['fence', [-1, 0, 0]], ['bookshelf', [1, -1, 0]],
                                 ['facade_sheared', [0, 1, 0]]]) {
      const input = path.join(dir, `${name}.glb`), output = path.join(dir, `${name}-out.glb`);
      execFileSync(nativeCli, ['sample', name, '-o', input]);
      execFileSync(nativeCli, ['resize', input, '--steps', steps.join(','), '-o', output]);
      const s = new restitch.Session();
      assert.ok(s.loadGltf(new Uint8Array(fs.readFileSync(input))).ok);
      const a = s.analyze('shot', 'brute_force', 'histogram', () => {});
      assert.ok(a.ok, a.message);
      const r = s.retarget(steps[0], steps[1], steps[2], 'lattice');
      assert.ok(r.ok, r.message);
      const wasm = Buffer.from(s.saveGlb('result').bytes);
      s.delete();
      const native = fs.readFileSync(output);
      assert.equal(wasm.length, native.length, `${name} ${steps}: ${wasm.length} bytes in WebAssembly, ${native.length} native`);
      assert.ok(Buffer.compare(wasm, native) === 0, `${name} ${steps}: the bytes differ`);
    }
  } finally {
    fs.rmSync(dir, { recursive: true, force: true });
  }
});

test('prepare builds the first resize\'s retargeter and warms it: same result bytes, no result shown, refusals in words', () => {
  // prepare also runs one resize per principal offset (+1 along it) and throws it away (the warm-up, bindings.cpp): the session
  // must show no result after it, and every later resize, the warm-up's own steps included and about another
  // pivot, must give the bytes of a session that never prepared.
  const resized = (prepareFirst, steps, pivot, sample = 'pin_header') => {
    const s = new restitch.Session();
    assert.ok(s.loadSample(sample, {}).ok);
    assert.ok(s.analyze('shot', 'brute_force', 'histogram', () => {}).ok);
    if (prepareFirst) {
      const p = s.prepare('lattice', 'descriptor');
      assert.ok(p.ok, p.message);
      assert.ok(p.ms >= 0);
      assert.ok(s.prepare('lattice', 'descriptor').ok, 'a second prepare keeps the retargeter');
      assert.equal(s.saveGlb('result').ok, false, 'the warm-up resize is not the session\'s result');
      assert.equal(s.mesh('result').ok, false);
    }
    const r = s.retarget(...steps, 'lattice', pivot);
    assert.ok(r.ok, r.message);
    const bytes = Buffer.from(s.saveGlb('result').bytes);
    s.delete();
    return bytes;
  };
  for (const [steps, pivot] of [[[2, 0, 0], 'origin'], [[1, 0, 0], 'origin'], [[1, 0, 0], 'max'], [[-1, 0, 0], 'center']])
    assert.ok(Buffer.compare(resized(true, steps, pivot), resized(false, steps, pivot)) === 0, `${steps} about ${pivot}`);
  // two principal offsets: the warm-up resizes along each
  assert.ok(Buffer.compare(resized(true, [1, 1, 0], 'min', 'bookshelf'), resized(false, [1, 1, 0], 'min', 'bookshelf')) === 0);
  const s = new restitch.Session();
  assert.equal(s.prepare('lattice', 'descriptor').code, 'invalid_argument', 'nothing analysed yet');
  assert.ok(s.loadSample('pin_header', {}).ok);
  assert.ok(s.analyze('shot', 'brute_force', 'histogram', () => {}).ok);
  const bad = s.prepare('hexagonal', 'descriptor');
  assert.equal(bad.ok, false);
  assert.match(bad.message, /label space/);
  assert.equal(s.prepare('lattice', 'telepathy').ok, false);
  s.delete();
});

test('the result check names what is wrong and gives the open edges to draw red', () => {
  // The paper's regular labels on the fence cut its rails where nothing continues them.
  const c = new restitch.Session();
  try {
    assert.equal(c.loadSample('fence', {}).ok, true);
    assert.equal(c.analyze('shot', 'brute_force', () => {}).ok, true);
    const r = c.retarget(1, 0, 0, 'regular');
    assert.equal(r.ok, true, r.message);
    assert.equal(r.report.checked, true);
    assert.ok(r.report.warnings.some((w) => w.check === 'open seam' && /open where the input is closed/.test(w.message)));
    assert.ok(r.report.boundary_edges.new > 0);
    assert.equal(r.open_edges.length, 6 * r.report.boundary_edges.new, 'two corners per new open edge');
    assert.ok(r.open_edges.every(Number.isFinite));
  } finally {
    c.delete();
  }
});
