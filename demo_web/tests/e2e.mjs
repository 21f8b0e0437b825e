// End-to-end test of the demo page in Debian's Chromium (headless, SwiftShader WebGL) with playwright-core:
// serve demo_web/ on a free 127.0.0.1 port, open the page, wait for a sample to reach `ready`, drag a
// slider, call setSteps, switch views, download the .glb and validate it, open files from disk (one made by
// the module, one from ../shared/models when present, one broken), check the console stayed clean, and save
// demo_web/screenshot.png. Prints one line per check and ends with "e2e: N passed, M failed".
// Usage: node demo_web/tests/e2e.mjs  (exit code 1 on any failure)
import fs from 'node:fs';
import os from 'node:os';
import net from 'node:net';
import path from 'node:path';
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const demo = path.resolve(here, '..');
const require = createRequire(path.join(demo, 'package.json'));
const { chromium } = require('playwright-core');
const validator = require('gltf-validator');
const modelsDir = path.resolve(demo, '../../shared/models');
const realModel = path.join(modelsDir, 'scopia_japanese_style_screen.glb');

let passed = 0, failed = 0;
function check(name, ok, detail = '') {
  if (ok) passed++; else failed++;
  console.log(`${ok ? 'ok' : 'not ok'} - ${name}${detail ? ` (${detail})` : ''}`);
}
async function attempt(name, fn) {
  try {
    const detail = await fn();
    check(name, true, typeof detail === 'string' ? detail : '');
  } catch (e) {
    check(name, false, e && e.message ? e.message.split('\n')[0] : String(e));
  }
}
function assert(cond, message) { if (!cond) throw new Error(message); }

function freePort() {
  return new Promise((resolve, reject) => {
    const srv = net.createServer();
    srv.once('error', reject);
    srv.listen(0, '127.0.0.1', () => { const { port } = srv.address(); srv.close(() => resolve(port)); });
  });
}

async function waitForServer(url, ms) {
  const end = Date.now() + ms;
  while (Date.now() < end) {
    try { if ((await fetch(url)).ok) return; } catch { /* not yet */ }
    await new Promise((r) => setTimeout(r, 100));
  }
  throw new Error(`the static server did not answer at ${url}`);
}

const port = await freePort();
const server = spawn('python3', ['-m', 'http.server', String(port), '--bind', '127.0.0.1'],
                     { cwd: demo, stdio: 'ignore' });
const base = `http://127.0.0.1:${port}/`;
const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'restitch-e2e-'));
let context;
try {
  await waitForServer(base, 15000);
  context = await chromium.launchPersistentContext(userDataDir, {
    executablePath: '/usr/bin/chromium',
    headless: true,
    acceptDownloads: true,
    viewport: { width: 1280, height: 800 },
    args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-quic',
           '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
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
    const { loadRestitch } = await import('../src/restitch.js');
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

  await attempt('the console has no errors', async () => {
    assert(consoleErrors.length === 0, consoleErrors.slice(0, 3).join(' | '));
  });
} catch (e) {
  check('the end-to-end run completed', false, e && e.message ? e.message.split('\n')[0] : String(e));
} finally {
  if (context) await context.close().catch(() => {});
  server.kill();
  fs.rmSync(userDataDir, { recursive: true, force: true });
}
console.log(`e2e: ${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
