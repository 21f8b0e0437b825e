// Measures the demo in Debian's Chromium: analysis time in the worker and the time from a resize request
// to the view showing it (window.restitchDemo.setSteps), for every bundled sample and every model in
// ../shared/models. Not part of run.sh (it takes minutes); prints one line per model.
// Usage: node demo_web/tests/measure.mjs [PATTERN]   (the static server must be free to start)
import fs from 'node:fs';
import os from 'node:os';
import net from 'node:net';
import path from 'node:path';
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const demo = path.resolve(here, '..');
const { chromium } = createRequire(path.join(demo, 'package.json'))('playwright-core');
const modelsDir = path.resolve(demo, '../../shared/models');
const pattern = new RegExp(process.argv[2] || '.');

const port = await new Promise((resolve) => {
  const srv = net.createServer().listen(0, '127.0.0.1', () => { const p = srv.address().port; srv.close(() => resolve(p)); });
});
const server = spawn('python3', ['-m', 'http.server', String(port), '--bind', '127.0.0.1'], { cwd: demo, stdio: 'ignore' });
const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'restitch-measure-'));
const context = await chromium.launchPersistentContext(userDataDir, {
  executablePath: '/usr/bin/chromium', headless: true, viewport: { width: 1280, height: 800 },
  args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-quic',
         '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'],
});
const median = (xs) => { const s = xs.slice().sort((a, b) => a - b); return s[s.length >> 1]; };
try {
  const page = context.pages()[0] || await context.newPage();
  for (let i = 0; i < 100; ++i) {
    try { await page.goto(`http://127.0.0.1:${port}/index.html`); break; } catch { await new Promise((r) => setTimeout(r, 100)); }
  }
  const ready = () => page.waitForFunction(() => ['ready', 'error'].includes(document.body.dataset.status), null,
                                           { timeout: 600000, polling: 50 });
  await ready();
  const names = ['bookshelf', 'facade', 'facade_sheared', 'fence', 'pin_header'].map((n) => ({ sample: n }));
  const files = fs.existsSync(modelsDir) ? fs.readdirSync(modelsDir).filter((f) => f.endsWith('.glb')).map((f) => ({ file: path.join(modelsDir, f) })) : [];
  for (const m of [...names, ...files]) {
    const label = m.sample || path.basename(m.file);
    if (!pattern.test(label)) continue;
    const t0 = Date.now();
    if (m.sample) await page.evaluate((n) => window.restitchDemo.loadSample(n), m.sample);  // resolves when analysed
    else await page.setInputFiles('#file', m.file);
    if (m.file) await page.waitForFunction(() => document.body.dataset.status !== 'ready', null, { timeout: 5000 }).catch(() => {});
    await ready();
    const wall = Date.now() - t0;
    const a = await page.evaluate(() => window.restitchDemo.analysis);
    const st = await page.evaluate(() => document.body.dataset.status);
    if (st !== 'ready') {
      console.log(`${label}: ${st}: ${await page.textContent('#error')} (analysis ${a ? a.timings_ms.total.toFixed(0) : '-'} ms)`);
      continue;
    }
    const first = [], later = [];
    for (let axis = 0; axis < a.principal_offsets.length; ++axis) {
      for (const k of [1, 2, 3, 2, 1, -1, 0]) {
        const steps = [0, 0, 0];
        steps[axis] = k;
        const r = await page.evaluate((s) => window.restitchDemo.setSteps(s).then((x) => x.ms, (e) => -1), steps);
        (k === 1 && first.length === axis ? first : later).push(r);
      }
    }
    console.log(`${label}: analysis ${a.timings_ms.total.toFixed(0)} ms in the worker (${(wall / 1000).toFixed(1)} s to ready), ` +
                `${a.principal_offsets.length} principal; resize ms first step per axis ${first.map((x) => x.toFixed(0)).join('/')}, ` +
                `then median ${median(later).toFixed(0)}, max ${Math.max(...later).toFixed(0)}`);
  }
} finally {
  await context.close();
  server.kill();
  fs.rmSync(userDataDir, { recursive: true, force: true });
}
