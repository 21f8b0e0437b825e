// End-to-end test of the demo page in Debian's Chromium (headless, SwiftShader WebGL) with playwright-core:
// serve demo_web/ on a free 127.0.0.1 port, open the page, wait for a sample to reach `ready`, drag a
// slider, call setSteps, switch views, download the .glb and validate it, open files from disk (one made by
// the module, one from ../shared/models when present, one broken), load the 2-pin header (its pitch principal
// offset 1: move the slider to 3 pins), load the fence (its rails a pair candidate: a resize along them refused,
// hover its peak in the histogram, click the candidate, move the slider one rail period up, undo, click the peak),
// switch the detector; check the console stayed clean, and save demo_web/screenshot.png. Prints one line per check and ends with "e2e: N passed, M failed".
// Usage: node demo_web/tests/e2e.mjs  (exit code 1 on any failure)
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';
import { serve, launch } from './browser.mjs';
import { assert, attempt, check, finish } from './checks.mjs';

const here = path.dirname(fileURLToPath(import.meta.url));
const demo = path.resolve(here, '..');
const require = createRequire(path.join(demo, 'package.json'));
const validator = require('gltf-validator');
const modelsDir = path.resolve(demo, '../../shared/models');
const realModel = path.join(modelsDir, 'scopia_japanese_style_screen.glb');


const server = await serve(demo);
const base = server.base;
const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'restitch-e2e-'));  // files the test writes
let context;
try {
  context = await launch({ acceptDownloads: true });
  const page = context.pages()[0] || await context.newPage();
  const consoleErrors = [];
  page.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(m.text()); });
  page.on('pageerror', (e) => consoleErrors.push(`page error: ${e.message}`));
  const status = () => page.evaluate(() => document.body.dataset.status);
  const waitStatus = (wanted, timeout = 120000) =>
    page.waitForFunction((w) => w.includes(document.body.dataset.status), wanted, { timeout, polling: 100 });

  // 1. The page starts, analyses the default sample in the worker and becomes ready.
  const t0 = Date.now();
  await page.goto(`${base}index.html?sample=bookshelf`);
  await attempt('the bookshelf sample reaches ready', async () => {
    await waitStatus(['ready', 'error']);
    assert((await status()) === 'ready', `status ${await status()}: ${await page.textContent('#error')}`);
    return `${((Date.now() - t0) / 1000).toFixed(1)} s from navigation`;
  });
  await attempt('status went loading -> analyzing -> ready, with progress reports on the way', async () => {
    const d = await page.evaluate(() => ({ h: window.restitchDemo.statusHistory, p: window.restitchDemo.progressReports }));
    assert(d.h.join(' ') === 'loading analyzing ready', `history ${d.h.join(' ')}`);
    assert(d.p > 5, `${d.p} progress reports`);
    return `${d.p} progress reports`;
  });
  const analysis = await page.evaluate(() => window.restitchDemo.analysis);
  await attempt('window.restitchDemo.analysis has the analyze --json fields, with the default policies', async () => {
    for (const k of ['scale', 'features', 'dominant_offsets', 'principal_offsets', 'dummy_directions', 'lattice_cells',
                     'lattice_axes', 'sparsity', 'descriptor', 'matcher', 'timings_ms'])
      assert(analysis && k in analysis, `missing ${k}`);
    assert(analysis.principal_offsets.length === 2, `${analysis.principal_offsets.length} principal offsets`);
    assert(analysis.descriptor === 'shot' && analysis.matcher === 'brute_force',
           `policies ${analysis.descriptor}/${analysis.matcher}, expected the defaults shot/brute_force`);
    const ms = await page.evaluate(() => window.restitchDemo.analysisMs);
    return `analysis ${ms.toFixed(0)} ms in the worker`;
  });
  const input = await page.evaluate(() => window.restitchDemo.result);

  // 2. Dragging the first slider resizes live.
  await attempt('dragging the v1 slider changes the triangle count', async () => {
    const slider = page.locator('.lil-gui .lil-controller.lil-number .lil-slider').first();
    const box = await slider.boundingBox();
    assert(box, 'no slider');
    await page.mouse.move(box.x + box.width * 0.2, box.y + box.height / 2);
    await page.mouse.down();
    for (let i = 1; i <= 6; ++i) await page.mouse.move(box.x + box.width * (0.2 + 0.1 * i), box.y + box.height / 2);
    await page.mouse.up();
    await page.waitForFunction((n) => window.restitchDemo.result.triangles !== n && window.restitchDemo.report,
                               input.triangles, { timeout: 30000 });
    const r = await page.evaluate(() => window.restitchDemo.result);
    return `${input.triangles} -> ${r.triangles} triangles`;
  });

  // 3. setSteps resolves once the view shows the result.
  await attempt('setSteps([1, 1, 0]) shows a grown model', async () => {
    const r = await page.evaluate(() => window.restitchDemo.setSteps([1, 1, 0]));
    const shown = await page.evaluate(() => ({ result: window.restitchDemo.result, report: window.restitchDemo.report }));
    assert(shown.result.triangles === r.triangles, 'resolved before the view showed it');
    assert(shown.result.triangles > input.triangles, `${shown.result.triangles} vs ${input.triangles}`);
    assert(shown.report.output.triangles === shown.result.triangles, 'report and view disagree');
    assert(shown.report.steps_principal.join() === '1,1', `steps_principal ${shown.report.steps_principal}`);
    return `${shown.result.triangles} triangles, ${shown.report.nodes} nodes, ${shown.report.labels} labels`;
  });
  await attempt('setSteps([-1, 0, 0]) shows a shrunk model', async () => {
    const r = await page.evaluate(() => window.restitchDemo.setSteps([-1, 0, 0]));
    assert(r.triangles < input.triangles, `${r.triangles} vs ${input.triangles}`);
  });
  const timings = [];
  await attempt('resize timings recorded (repeated slider moves)', async () => {
    for (const s of [[1, 0, 0], [2, 0, 0], [3, 0, 0], [2, 0, 0], [1, 0, 0], [0, 1, 0], [0, 2, 0], [1, 1, 0]]) {
      const r = await page.evaluate((st) => window.restitchDemo.setSteps(st), s);
      timings.push(r.ms);
    }
    assert(timings.every((t) => t > 0), 'missing timings');
    const sorted = timings.slice().sort((a, b) => a - b);
    return `page ms per resize: ${timings.map((t) => t.toFixed(0)).join(' ')}; median ${sorted[sorted.length >> 1].toFixed(0)}`;
  });

  // 4. Views and the label space switch without errors.
  await attempt('views: cells by label, seams, shaded', async () => {
    const views = page.locator('.lil-gui .lil-controller.lil-option').filter({ hasText: 'view' }).locator('select');
    for (const label of ['cells by label', 'seams', 'shaded']) {
      await views.selectOption({ label });
      await page.waitForTimeout(150);
    }
    assert((await status()) === 'ready', `status ${await status()}`);
  });
  await attempt('setView, setOverlays, getCamera/setCamera (the README pictures use them)', async () => {
    const moved = await page.evaluate(() => {
      const d = window.restitchDemo;
      d.setView('labels');
      d.setOverlays({ offsets: false, histogram: false });
      const cam = d.getCamera();
      const next = { target: cam.target, position: cam.position.map((x, k) => cam.target[k] + 0.5 * (x - cam.target[k])) };
      d.setCamera(next);
      const back = d.getCamera();
      d.setCamera(cam);
      d.setOverlays({ offsets: true, histogram: true });
      d.setView('shaded');
      return { next, back };
    });
    const err = Math.max(...moved.next.position.map((x, k) => Math.abs(x - moved.back.position[k])));
    assert(err < 1e-6, `setCamera then getCamera differ by ${err}`);
    assert((await status()) === 'ready', `status ${await status()}`);
    assert(!(await page.isHidden('#histogram-label')), 'the histogram is not shown again');
  });
  await attempt('the regular label space solves the same request', async () => {
    const labels = page.locator('.lil-gui .lil-controller.lil-option').filter({ hasText: 'label space' }).locator('select');
    await labels.selectOption({ label: 'regular' });
    await page.waitForFunction(() => window.restitchDemo.report && window.restitchDemo.report.label_space === 'regular',
                               null, { timeout: 60000 });
    const rep = await page.evaluate(() => window.restitchDemo.report);
    await labels.selectOption({ label: 'lattice' });
    await page.waitForFunction(() => window.restitchDemo.report.label_space === 'lattice', null, { timeout: 60000 });
    return `regular: ${rep.nodes} nodes, ${rep.labels} labels`;
  });

  await attempt('the pivot dropdown: max keeps the far end, the result moves by whole periods', async () => {
    await page.evaluate(() => window.restitchDemo.setSteps([2, 0, 0]));
    const pivot = page.locator('.lil-gui .lil-controller.lil-option').filter({ hasText: 'pivot' }).locator('select');
    await pivot.selectOption({ label: 'max' });
    await page.waitForFunction(() => window.restitchDemo.report && window.restitchDemo.report.pivot.modes[0] === 'max',
                               null, { timeout: 60000 });
    const p = await page.evaluate(() => window.restitchDemo.report.pivot);
    await pivot.selectOption({ label: 'origin' });
    await page.waitForFunction(() => window.restitchDemo.report.pivot.modes[0] === 'origin', null, { timeout: 60000 });
    assert(p.low_end_cells.some((c) => c !== 0) && p.translation.some((x) => x !== 0),
           `no translation with a max pivot: ${JSON.stringify(p)}`);
    return `translation ${p.translation.map((x) => x.toFixed(3)).join(', ')}`;
  });

  await attempt('typing a size in a size field gives that size exactly from the nearest whole repeats; the slider follows', async () => {
    await page.evaluate(() => window.restitchDemo.setSteps([0, 0, 0]));
    const a = await page.evaluate(() => window.restitchDemo.analysis);
    // The field of principal offset 1 is about the world axis v1 runs along; ask for 2.3 repeats more, less 0.3.
    const v = a.principal_offsets[0], axis = v.map(Math.abs).indexOf(Math.max(...v.map(Math.abs)));
    const sizeIn = (await page.evaluate(() => window.restitchDemo.report)).size_in[axis], pitch = Math.abs(v[axis]);
    const want = Number((sizeIn + 2.3 * pitch).toFixed(4));
    const field = page.locator('[data-size="0"] input');
    await field.fill(String(want));
    await field.press('Enter');
    await page.waitForFunction((w) => { const r = window.restitchDemo.report; return r && r.exact && r.exact.applied; },
                               want, { timeout: 60000 });
    const r = await page.evaluate(() => window.restitchDemo.report);
    assert(Math.abs(r.size_out[axis] - want) < 1e-5 * want, `size ${r.size_out[axis]} for ${want}`);
    assert(r.steps_principal[0] === 2, `steps_principal ${r.steps_principal} (2 repeats are the nearest)`);
    assert(Math.abs(r.exact.size_nearest[axis] - (sizeIn + 2 * pitch)) < 1e-4 * want, `nearest ${r.exact.size_nearest[axis]}`);
    // The report is in the page's state before the view has drawn it; the slider follows once the resize's
    // promise resolves (after the view), so it is read until it shows the steps, for up to 10 s.
    const sliderInput = page.locator('.lil-gui .lil-controller.lil-number').filter({ hasText: 'v1 steps' }).locator('input').first();
    let slider = await sliderInput.inputValue();
    for (let t = 0; Number(slider) !== 2 && t < 100; ++t) {
      await page.waitForTimeout(100);
      slider = await sliderInput.inputValue();
    }
    assert(Number(slider) === 2, `the v1 slider shows ${slider}`);
    assert(Math.abs(Number(await field.inputValue()) - want) < 1e-3, `the field shows ${await field.inputValue()}`);
    await page.evaluate(() => window.restitchDemo.setSteps([0, 0, 0]));
    return `${want} asked along ${'xyz'[axis]}: 2 repeats scaled by ${r.exact.scale[axis].toFixed(4)}`;
  });

  // 5. Download the result and validate it.
  await attempt('download .glb validates', async () => {
    await page.evaluate(() => window.restitchDemo.setSteps([2, 1, 0]));
    const [download] = await Promise.all([
      page.waitForEvent('download', { timeout: 30000 }),
      page.locator('.lil-gui .lil-controller.lil-function').filter({ hasText: 'download' }).locator('button').click(),
    ]);
    const file = path.join(userDataDir, 'result.glb');
    await download.saveAs(file);
    const bytes = new Uint8Array(fs.readFileSync(file));
    const report = await validator.validateBytes(bytes, { maxIssues: 20 });
    assert(report.issues.numErrors === 0, `${report.issues.numErrors} validator errors`);
    return `${bytes.length} bytes, 0 validator errors`;
  });

  // 6. The screenshot for the README: the resized bookshelf, offsets and histogram shown.
  await attempt('screenshot saved', async () => {
    await page.evaluate(() => window.restitchDemo.setSteps([2, 1, 0]));
    await page.waitForTimeout(300);
    await page.screenshot({ path: path.join(demo, 'screenshot.png') });
    return `${fs.statSync(path.join(demo, 'screenshot.png')).size} bytes`;
  });

  // 7. Files from disk through the file picker.
  // Opens a file and waits for the page to settle: the status history grows and ends in ready or error.
  const settleAfter = async (action) => {
    const before = await page.evaluate(() => window.restitchDemo.statusHistory.length);
    await action();
    await page.waitForFunction((n) => {
      const h = window.restitchDemo.statusHistory;
      return h.length > n + 1 && ['ready', 'error'].includes(h[h.length - 1]);
    }, before, { timeout: 120000, polling: 50 });
  };
  const openFile = (file) => settleAfter(() => page.setInputFiles('#file', file));
  await attempt('a broken file shows an error in words', async () => {
    const bad = path.join(userDataDir, 'broken.glb');
    fs.writeFileSync(bad, 'this is not a glTF file');
    await openFile(bad);
    assert((await status()) === 'error', `status ${await status()}`);
    const text = await page.textContent('#error');
    assert(await page.isVisible('#error') && /broken\.glb/.test(text) && /glTF/.test(text), `error text: ${text}`);
  });
  await attempt('a .glb from disk (fence sample written by the module) reaches ready', async () => {
    const { loadRestitch } = await import('../npm/index.js');
    const restitch = await loadRestitch();
    const s = new restitch.Session();
    s.loadSample('fence', {});
    const file = path.join(userDataDir, 'fence.glb');
    fs.writeFileSync(file, s.saveGlb('input').bytes);
    s.delete();
    await openFile(file);
    assert((await status()) === 'ready', `status ${await status()}: ${await page.textContent('#error')}`);
    assert(await page.isHidden('#error'), 'the old error is still shown');
    const a = await page.evaluate(() => window.restitchDemo.analysis);
    assert(a.principal_offsets.length >= 1, 'no principal offsets');
    const before = (await page.evaluate(() => window.restitchDemo.result)).triangles;
    const r = await page.evaluate(() => window.restitchDemo.setSteps([2, 0, 0]));
    assert(r.triangles !== before, 'triangle count unchanged');
    return `${before} -> ${r.triangles} triangles`;
  });
  await attempt('a .glb dropped on the page opens too', async () => {
    const bytes = [...fs.readFileSync(path.join(userDataDir, 'fence.glb'))];
    const dataTransfer = await page.evaluateHandle((b) => {
      const dt = new DataTransfer();
      dt.items.add(new File([new Uint8Array(b)], 'dropped-fence.glb', { type: 'model/gltf-binary' }));
      return dt;
    }, bytes);
    await settleAfter(() => page.dispatchEvent('body', 'drop', { dataTransfer }));
    assert((await page.textContent('#model-name')) === 'dropped-fence.glb', 'the dropped file is not the one shown');
    assert((await status()) === 'ready', `status ${await status()}: ${await page.textContent('#error')}`);
  });
  if (fs.existsSync(realModel)) {
    await attempt(`a real model from disk (${path.basename(realModel)}) reaches ready and resizes`, async () => {
      await openFile(realModel);
      assert((await status()) === 'ready', `status ${await status()}: ${await page.textContent('#error')}`);
      const before = (await page.evaluate(() => window.restitchDemo.result)).triangles;
      const r = await page.evaluate(() => window.restitchDemo.setSteps([1, 0, 0]));
      assert(r.triangles !== before, 'triangle count unchanged');
      return `${before} -> ${r.triangles} triangles, ${r.ms.toFixed(0)} ms`;
    });
  } else {
    console.log(`skip - a real model from disk: ${realModel} is absent`);
  }

  // 8. Two copies and candidates. The 2-pin header (a bundled sample with pins = 2) repeats only once, but its two
  // pins pair vertex for vertex, so its pitch (2.54 mm) is principal offset 1 and the slider grows it at once. The
  // fence's two rails are a pair too, but only a detail of the fence: a candidate, rejected by a pattern test, that
  // one click makes principal (the fence then resizes along y, one rail-pair period of 0.55 m at a time).
  const isPitch = (v) => Math.abs(Math.abs(v[0]) - 2.54) < 2e-3 && Math.abs(v[1]) < 2e-3 && Math.abs(v[2]) < 2e-3;
  const isPicketPitch = (v) => Math.abs(Math.abs(v[0]) - 0.15) < 2e-3 && Math.abs(v[1]) < 2e-3 && Math.abs(v[2]) < 2e-3;
  const isRail = (v) => Math.abs(v[0]) < 2e-3 && Math.abs(Math.abs(v[1]) - 0.55) < 2e-3 && Math.abs(v[2]) < 2e-3;
  const fenceHeight = 1.19;  // the posts'
  // Clicks the first slider (v1) at `steps` and waits for that result; its range is that of panel.js.
  const clickFirstSlider = async (steps, cells) => {
    const slider = page.locator('.lil-gui .lil-controller.lil-number .lil-slider').first();
    const box = await slider.boundingBox();
    const min = 1 - cells, max = Math.min(24, Math.max(6, 2 * cells));
    await page.mouse.click(box.x + box.width * (steps - min) / (max - min), box.y + box.height / 2);
    await page.waitForFunction((s) => window.restitchDemo.report && window.restitchDemo.report.steps_principal[0] === s,
                               steps, { timeout: 30000 });
    return page.evaluate(() => window.restitchDemo.report);
  };
  const firstSliderName = () => page.textContent('.lil-gui .lil-controller.lil-number .lil-name');
  await attempt('the 2-pin header: its pitch is principal offset 1; the slider grows it to 3 pins (8.22 mm) without promotion', async () => {
    await settleAfter(() => page.evaluate(() => { window.restitchDemo.loadSample('pin_header', { pins: 2 }); }));
    assert((await status()) === 'ready', `status ${await status()}: ${await page.textContent('#error')}`);
    const a = await page.evaluate(() => window.restitchDemo.analysis);
    assert(a.principal_offsets.length === 1 && isPitch(a.principal_offsets[0]), JSON.stringify(a.principal_offsets));
    assert(!a.candidates.some((c) => isPitch(c.offset)), `the pitch is a candidate: ${JSON.stringify(a.candidates)}`);
    const before = (await page.evaluate(() => window.restitchDemo.result)).triangles;
    const rep = await clickFirstSlider(1, a.lattice_cells[a.resizable.indexOf(true)]);
    assert(rep.steps_principal.join() === '1', `steps_principal ${rep.steps_principal}`);
    assert(Math.abs(rep.size_out[0] - 8.22) < 1e-3, `size out ${rep.size_out}`);
    const name = await firstSliderName();
    assert(/→ 8\.22 mm/.test(name), `the slider reads '${name}'`);
    const after = (await page.evaluate(() => window.restitchDemo.result)).triangles;
    assert(after > before, `${before} -> ${after} triangles`);
    return `${rep.size_out[0].toFixed(2)} mm wide, ${before} -> ${after} triangles`;
  });
  let railCandidate = -1;
  await attempt('the fence: one principal offset, its rails listed as a candidate; a resize along v2 is refused in words', async () => {
    await settleAfter(() => page.evaluate(() => { window.restitchDemo.loadSample('fence', {}); }));
    assert((await status()) === 'ready', `status ${await status()}: ${await page.textContent('#error')}`);
    const a = await page.evaluate(() => window.restitchDemo.analysis);
    assert(a.principal_offsets.length === 1 && isPicketPitch(a.principal_offsets[0]), JSON.stringify(a.principal_offsets));
    railCandidate = a.candidates.findIndex((c) => isRail(c.offset));
    assert(railCandidate >= 0, `candidates ${JSON.stringify(a.candidates)}`);
    const label = await page.textContent(`[data-candidate="${railCandidate}"]`);
    assert(/0\.550.*2 copies.*pair/.test(label), `the button reads '${label}'`);
    const refused = await page.evaluate(() => window.restitchDemo.setSteps([0, 1, 0]).then(() => null, (e) => e.message));
    assert(refused && /the model has 1 principal offset/.test(refused), `setSteps([0, 1, 0]) gave ${refused}`);
    assert((await status()) === 'error', `status ${await status()}`);
    const text = await page.textContent('#error');
    assert(await page.isVisible('#error') && /^Resize failed: the model has 1 principal offset/.test(text), `error text: ${text}`);
    return `${label.trim()}; ${text}`;
  });
  const peakOf = async (candidate) => {
    const peaks = await page.evaluate(() => window.restitchDemo.histogramPeaks());
    const p = peaks.find((q) => q.candidate === candidate);
    assert(p, `no peak for candidate ${candidate} in ${JSON.stringify(peaks)}`);
    return p;
  };
  await attempt('hovering the rails\' candidate\'s peak in the histogram shows its tests and why it was rejected', async () => {
    const p = await peakOf(railCandidate);
    await page.mouse.move(p.x + 60, p.y - 60);
    await page.mouse.move(p.x, p.y, { steps: 4 });
    await page.waitForSelector('#peak-tip:not([hidden])', { timeout: 5000 });
    const text = await page.innerText('#peak-tip');
    for (const want of [/dominant offset \d+: \(/, /votes/, /overlap/, /passed/, /FAILED/, /rejected by \w+/, /divisor 1/,
                        /not promoted/, /\(pair, 2 copies\): click to resize along it/])
      assert(want.test(text), `${want} not in '${text}'`);
    await page.mouse.move(p.x + 120, p.y - 120);
    await page.waitForSelector('#peak-tip', { state: 'hidden', timeout: 5000 });
    return text.match(/rejected by \w+/)[0];
  });
  await attempt('clicking the candidate makes it principal offset 1; the slider grows the fence by one rail period (1.19 -> 1.74 m)', async () => {
    const before = (await page.evaluate(() => window.restitchDemo.result)).triangles;
    await page.locator(`[data-candidate="${railCandidate}"] button`).click();
    await waitStatus(['ready']);
    const a = await page.evaluate(() => window.restitchDemo.analysis);
    assert(a.principal_offsets.length === 2 && isRail(a.principal_offsets[0]) && isPicketPitch(a.principal_offsets[1]),
           JSON.stringify(a.principal_offsets));
    assert(await page.isHidden('#error'), 'the error is still shown');
    const sliders = await page.locator('.lil-gui .lil-controller.lil-number .lil-slider').count();
    assert(sliders === 2, `${sliders} sliders`);
    const rep = await clickFirstSlider(1, a.lattice_cells[a.resizable.indexOf(true)]);
    assert(rep.steps_principal.join() === '1,0', `steps_principal ${rep.steps_principal}`);
    const tall = fenceHeight + Math.hypot(...a.principal_offsets[0]);
    assert(Math.abs(rep.size_out[1] - tall) < 1e-3 && Math.abs(rep.size_out[1] - 1.74) < 2e-3, `size out ${rep.size_out}`);
    const name = await firstSliderName();
    assert(/→ 1\.74 m/.test(name), `the slider reads '${name}'`);
    const after = (await page.evaluate(() => window.restitchDemo.result)).triangles;
    assert(after > before, `${before} -> ${after} triangles`);
    return `${rep.size_out[1].toFixed(2)} m tall, ${before} -> ${after} triangles`;
  });
  await attempt('\'detected offsets\' undoes the promotion; clicking the candidate\'s peak promotes it again', async () => {
    await page.locator('[data-detected] button').click();
    await page.waitForFunction(() => window.restitchDemo.analysis.principal_offsets.length === 1 &&
                               window.restitchDemo.promoted.length === 0, null, { timeout: 30000 });
    assert((await status()) === 'ready', `status ${await status()}: the picket pitch still resizes`);
    assert((await page.evaluate(() => window.restitchDemo.report)) === null, 'the result is still shown');
    const refused = await page.evaluate(() => window.restitchDemo.setSteps([0, 1, 0]).then(() => null, (e) => e.message));
    assert(refused && /the model has 1 principal offset/.test(refused), `setSteps([0, 1, 0]) gave ${refused}`);
    await page.waitForTimeout(100);
    const p = await peakOf(railCandidate);
    await page.mouse.move(p.x, p.y, { steps: 2 });
    await page.mouse.down();
    await page.mouse.up();
    await waitStatus(['ready'], 30000);
    const a = await page.evaluate(() => window.restitchDemo.analysis);
    assert(a.principal_offsets.length === 2 && isRail(a.principal_offsets[0]), JSON.stringify(a.principal_offsets));
    const r = await page.evaluate(() => window.restitchDemo.setSteps([2, 0, 0]));
    const rep = await page.evaluate(() => window.restitchDemo.report);
    const tall = fenceHeight + 2 * Math.hypot(...a.principal_offsets[0]);
    assert(Math.abs(rep.size_out[1] - tall) < 2e-3, `size out ${rep.size_out}, expected ${tall} tall`);
    return `two more rail periods: ${rep.size_out[1].toFixed(2)} m, ${r.triangles} triangles`;
  });

  await attempt('the detector choice re-analyses with autocorrelation (the promotion is dropped)', async () => {
    const detector = page.locator('.lil-gui .lil-controller.lil-option').filter({ hasText: 'detector' }).locator('select');
    await settleAfter(() => detector.selectOption({ label: 'autocorrelation' }));
    const a = await page.evaluate(() => window.restitchDemo.analysis);
    assert(a.detector === 'autocorrelation', `detector ${a.detector}`);
    assert((await page.evaluate(() => window.restitchDemo.promoted)).length === 0, 'the old promotion is kept');
    await settleAfter(() => detector.selectOption({ label: 'histogram' }));
    return `${a.principal_offsets.length} principal offsets, ${a.candidates.length} candidates`;
  });

  await attempt('a model the worker runs out of memory on gives a message; the page stays usable, the next model opens', async () => {
    // ?memory=64 caps the module at 64 MB: a 40 x 30 bookshelf (237k triangles) loads but its analysis does
    // not fit (module.test.mjs measures the same in node). A page of its own: the module prints 'Aborted()'.
    const p2 = await context.newPage();
    try {
      await p2.goto(`${base}index.html?sample=pin_header&memory=64`);
      const settled = () => p2.waitForFunction(() => ['ready', 'error'].includes(document.body.dataset.status),
                                               null, { timeout: 120000, polling: 100 });
      await settled();
      const st = () => p2.evaluate(() => document.body.dataset.status);
      assert((await st()) === 'ready', `the pin header did not open: ${await p2.textContent('#error')}`);
      await p2.evaluate(() => window.restitchDemo.loadSample('bookshelf', { columns: 40, shelves: 30 }));
      await settled();
      const text = await p2.textContent('#error');
      assert((await st()) === 'error', `status ${await st()}`);
      assert(/ran out of memory while (opening|analysing) the model \(the page can use at most 64 MB/.test(text), `error: ${text}`);
      await p2.evaluate(() => window.restitchDemo.loadSample('fence', {}));
      await settled();
      assert((await st()) === 'ready', `the fence did not open after: ${await p2.textContent('#error')}`);
      const r = await p2.evaluate(() => window.restitchDemo.setSteps([1, 0, 0]));
      return `then the fence resized to ${r.triangles} triangles`;
    } finally {
      await p2.close();
    }
  });

  await attempt('a file opened at any moment of the start is the model shown, and the page ends ready', async () => {
    // A page of its own per moment: the file goes in before the page's script has run (its module held back
    // for 1.5 s, as on a slow connection: the picker is in the page already), while the module loads, while
    // the catalog is asked for, or while the bundled bookshelf is loading or being analysed. The fence has one
    // principal offset, the bookshelf two, so the analysis shown says which model won.
    const moments = ['before the script', 0, 20, 100, 400, 1000];
    const seen = [];
    for (const ms of moments) {
      const p3 = await context.newPage();
      const errors = [];
      p3.on('pageerror', (e) => errors.push(e.message));
      try {
        if (ms === 'before the script') {
          await p3.route('**/src/app.js', async (route) => {
            await new Promise((r) => setTimeout(r, 1500));
            await route.continue();
          });
        }
        await p3.goto(`${base}index.html?sample=bookshelf`, { waitUntil: 'commit' });
        if (typeof ms === 'number') await p3.waitForTimeout(ms);
        await p3.waitForSelector('#file', { state: 'attached', timeout: 30000 });
        await p3.setInputFiles('#file', path.join(userDataDir, 'fence.glb'));
        const shown = await p3.waitForFunction(() => document.body.dataset.status === 'error' ||
                                                 (document.body.dataset.status === 'ready' && window.restitchDemo.analysis &&
                                                  window.restitchDemo.analysis.principal_offsets.length === 1),
                                               null, { timeout: 60000, polling: 100 }).then(() => true, () => false);
        const st = await p3.evaluate(() => ({
          status: document.body.dataset.status,
          principal: window.restitchDemo && window.restitchDemo.analysis
            ? window.restitchDemo.analysis.principal_offsets.length : null,
        }));
        assert(shown && st.status === 'ready',
               `${ms}: status ${st.status}, ${st.principal} principal offsets: ${await p3.textContent('#error')}`);
        assert(errors.length === 0, `${ms}: ${errors[0]}`);
        seen.push(ms);
      } finally {
        await p3.close();
      }
    }
    return `opened ${seen.length} times: ${seen.map((m) => (typeof m === 'number' ? `${m} ms after navigation` : m)).join(', ')}`;
  });

  await attempt('a failed start says what failed and offers to retry; the retry starts the page', async () => {
    // The worker's script is refused once (as a dropped connection would), then served.
    const p4 = await context.newPage();
    let refused = 0;
    const handler = async (route) => {
      if (refused++ === 0) await route.fulfill({ status: 503, body: 'unavailable' });
      else await route.continue();
    };
    await p4.route('**/src/worker.js', handler);
    try {
      await p4.goto(`${base}index.html?sample=fence`);
      await p4.waitForFunction(() => document.body.dataset.status === 'error', null, { timeout: 60000 });
      const message = await p4.textContent('#error');
      assert(/could not start/.test(message), `the error says: ${message}`);
      assert(await p4.isVisible('#retry'), 'no Retry button');
      await p4.click('#retry');
      await p4.waitForFunction(() => document.body.dataset.status === 'ready' && window.restitchDemo.analysis,
                               null, { timeout: 120000 });
      assert(!(await p4.isVisible('#error')), 'the error is still shown');
      return `${message.replace(/\s*Retry$/, '')}; after Retry: ready (${refused} requests for the worker's script)`;
    } finally {
      await p4.close();
    }
  });

  await attempt('the console has no errors', async () => {
    assert(consoleErrors.length === 0, consoleErrors.slice(0, 3).join(' | '));
  });
} catch (e) {
  check('the end-to-end run completed', false, e && e.message ? e.message.split('\n')[0] : String(e));
} finally {
  if (context) await context.close().catch(() => {});
  server.close();
  fs.rmSync(userDataDir, { recursive: true, force: true });
}
finish('e2e');
