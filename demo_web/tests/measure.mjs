// Measures the demo in Debian's Chromium: analysis time in the worker and the time from a resize request
// to the view showing it (window.restitchDemo.setSteps), for every bundled sample and every model in
// ../shared/models, with the page's default policies. Not part of run.sh (it takes minutes); prints one
// line per model: the analysis's wall time in the worker and its slowest stages; per principal offset the
// first resize, asked one second after the page is ready (a user looking at the analysis: the worker prepares
// the Retargeter's caches meanwhile, src/worker.js), and then the later moves (steps 2, 3, 2, 1, -1, 0),
// each from the request to the view showing the result; the retarget's own stages (energy/solve/stitch,
// median over the later moves, from the report).
// Usage: node demo_web/tests/measure.mjs [PATTERN] [QUERY] [--native RESTITCH] [--json FILE]
//   e.g. `fence matcher=brute_force` (QUERY: the page's URL parameters, to pick other policies).
//   --native: also analyses each model with that native `restitch` binary, one thread and the page's policies
//   (`analyze --threads 1` with the same descriptor, matcher and detector), run after the page's work on that
//   model (its resizes too) so the two never share the cores, and prints page / native over the sum of the analysis stages (the same stages, timed
//   the same way on both sides). --json: writes every figure to FILE.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { spawnSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';
import { serve, launch } from './browser.mjs';

const here = path.dirname(fileURLToPath(import.meta.url));
const demo = path.resolve(here, '..');
const modelsDir = path.resolve(demo, '../../shared/models');
const args = process.argv.slice(2);
const option = (name) => { const i = args.indexOf(name); if (i < 0) return null; const v = args[i + 1]; args.splice(i, 2); return v; };
const nativeBin = option('--native');
const jsonOut = option('--json');
const pattern = new RegExp(args[0] || '.');
const query = args[1] ? `?${args[1]}` : '';
const figures = [];
const stageSum = (timings) => Object.values(timings || {}).reduce((x, y) => x + y, 0);

// The native analysis of one model with the page's policies on one thread: the sum of its stages (ms).
function nativeAnalysis(m, policies) {
  const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'restitch-native-'));
  try {
    let file = m.file;
    if (m.sample) {
      file = path.join(tmp, `${m.sample}.glb`);
      const g = spawnSync(nativeBin, ['sample', m.sample, '-o', file], { stdio: 'ignore' });
      if (g.status !== 0) return null;
    }
    const r = spawnSync(nativeBin, ['analyze', file, '--threads', '1', '--descriptor', policies.descriptor,
                                    '--matcher', policies.matcher, '--detector', policies.detector, '--json', '-'],
                        { encoding: 'utf8', maxBuffer: 1 << 28 });
    if (r.status !== 0 && r.status !== 4) return null;  // 4: no repetition, still timed
    return stageSum(JSON.parse(r.stdout).timings_ms);
  } catch {
    return null;
  } finally {
    fs.rmSync(tmp, { recursive: true, force: true });
  }
}

const server = await serve(demo);
const context = await launch();
const median = (xs) => { const s = xs.slice().sort((a, b) => a - b); return s[s.length >> 1]; };
try {
  const page = context.pages()[0] || await context.newPage();
  for (let i = 0; i < 100; ++i) {
    try { await page.goto(`${server.base}index.html${query}`); break; } catch { await new Promise((r) => setTimeout(r, 100)); }
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
    const ms = await page.evaluate(() => window.restitchDemo.analysisMs);
    const st = await page.evaluate(() => document.body.dataset.status);
    const stages = a ? Object.entries(a.timings_ms).sort((x, y) => y[1] - x[1]).slice(0, 3)
                         .map(([k, v]) => `${k} ${v.toFixed(0)}`).join(', ') : '';
    const policies = a ? { descriptor: a.descriptor, matcher: a.matcher, detector: a.detector } : null;
    // The native run goes after the page's work on this model (its resizes too), so the two never overlap.
    const compare = () => {
      const native = nativeBin && policies ? nativeAnalysis(m, policies) : null;
      Object.assign(record, { native_stages_ms: native, page_over_native: native && pageStages ? pageStages / native : null });
      return native && pageStages ? ` (stages ${pageStages.toFixed(0)} ms; native ${native.toFixed(0)} ms: ${(pageStages / native).toFixed(2)}x)` : '';
    };
    const pageStages = a ? stageSum(a.timings_ms) : null;
    const shown = await page.evaluate(() => window.restitchDemo.result);  // the input, before any resize
    const record = { model: label, triangles: shown ? shown.triangles : null, policies, page_analysis_ms: ms,
                     page_stages_ms: pageStages };
    figures.push(record);
    if (st !== 'ready') {
      console.log(`${label}: ${st}: ${await page.textContent('#error')} (analysis ${ms ? ms.toFixed(0) : '-'} ms: ${stages})${compare()}`);
      continue;
    }
    await page.waitForTimeout(1000);  // the user looks at the analysis before moving a slider
    const first = [], later = [], parts = { energy: [], solve: [], stitch: [] };
    let failures = 0;
    for (let axis = 0; axis < a.principal_offsets.length; ++axis) {
      for (const k of [1, 2, 3, 2, 1, -1, 0]) {
        const steps = [0, 0, 0];
        steps[axis] = k;
        const r = await page.evaluate((s) => window.restitchDemo.setSteps(s).then((x) => x.ms, () => -1), steps);
        if (r < 0) { ++failures; continue; }
        if (k === 1 && first.length === axis) { first.push(r); continue; }
        later.push(r);
        const rep = await page.evaluate(() => window.restitchDemo.report.timings_ms);
        if (k !== 0) for (const p of Object.keys(parts)) parts[p].push(rep[p] || 0);
      }
    }
    const f0 = (x) => (x === undefined ? '-' : x.toFixed(0));
    const f1 = (x) => (x === undefined ? '-' : x.toFixed(1));
    Object.assign(record, { first_resize_ms: first, later_median_ms: median(later), later_max_ms: Math.max(...later) });
    const ratio = compare();
    console.log(`${label}: ${a.descriptor}/${a.matcher} analysis ${ms.toFixed(0)} ms in the worker (${stages}; ${(wall / 1000).toFixed(1)} s to ready)${ratio}, ` +
                `${a.features} features, ${a.principal_offsets.length} principal, cells ${a.lattice_cells.join('x')}; ` +
                `resize ms: first ${first.map(f0).join('/')}, later median ${f0(median(later))}, max ${f0(Math.max(...later))}` +
                ` (median energy ${f1(median(parts.energy))}, solve ${f1(median(parts.solve))}, stitch ${f1(median(parts.stitch))})` +
                `${failures ? `; ${failures} resizes failed` : ''}`);
  }
  if (jsonOut) fs.writeFileSync(jsonOut, JSON.stringify({ query, native: nativeBin, models: figures }, null, 1));
} finally {
  await context.close();
  server.close();
}
