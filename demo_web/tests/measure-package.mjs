// Measures the npm package as installed: its size (the tarball, each file, each file gzipped as a server
// would send it), how long `init()` takes to load the module (node: a fresh process per run; Chromium: a fresh
// profile per run, so nothing is cached), and what a slider costs with restitch/three in Chromium: the first
// resize after analyze() and the later moves (steps 1, 2, 3, 2, 1, -1, 0 along the first principal offset,
// median), for every bundled sample and every model in ../shared/models. Not a test (it takes minutes).
// Usage: node demo_web/tests/measure-package.mjs [--tarball T.tgz] [--embedded DIR] [--runs N]
//   --tarball: measure this tarball (default: scripts/pack-npm.sh packs one).
//   --embedded DIR: also measure a build linked with -sSINGLE_FILE=1 (DIR/restitch_web.mjs with the .wasm
//   inside, base64): its size and start time, installed in place of dist/.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import zlib from 'node:zlib';
import { spawnSync } from 'node:child_process';
import { serve, launch } from './browser.mjs';
import { pack, install, root, runOk } from './consumer.mjs';

const args = process.argv.slice(2);
const option = (name) => { const i = args.indexOf(name); return i < 0 ? null : args[i + 1]; };
const runs = Number(option('--runs') || 5);
const embedded = option('--embedded');
const modelsDir = path.resolve(root, '../shared/models');
const median = (xs) => { const s = xs.slice().sort((a, b) => a - b); return s[s.length >> 1]; };
const mb = (n) => `${(n / 1e6).toFixed(2)} MB`;

const work = fs.mkdtempSync(path.join(os.tmpdir(), 'restitch-measure-npm-'));
const tarball = option('--tarball') || pack(path.join(work, 'pack'));
const installs = { beside: install(tarball, path.join(work, 'beside')) };
if (embedded) {
  installs.embedded = install(tarball, path.join(work, 'embedded'));
  const dist = path.join(installs.embedded, 'node_modules/restitch/dist');
  fs.rmSync(path.join(dist, 'restitch_web.wasm'));
  fs.copyFileSync(path.join(embedded, 'restitch_web.mjs'), path.join(dist, 'restitch_web.mjs'));
}

console.log(`tarball ${path.basename(tarball)}: ${mb(fs.statSync(tarball).size)}`);
for (const [name, dir] of Object.entries(installs)) {
  const pkg = path.join(dir, 'node_modules/restitch');
  for (const f of ['dist/restitch_web.mjs', 'dist/restitch_web.wasm', 'cli/restitch.cjs', 'cli/restitch.wasm', 'index.js', 'three.js']) {
    const file = path.join(pkg, f);
    if (!fs.existsSync(file)) continue;
    const bytes = fs.readFileSync(file);
    console.log(`${name}: ${f} ${mb(bytes.length)}, gzipped ${mb(zlib.gzipSync(bytes, { level: 9 }).length)}`);
  }
}

// init() in node: a fresh process per run.
for (const [name, dir] of Object.entries(installs)) {
  const times = [];
  for (let i = 0; i < runs; ++i) {
    const r = spawnSync(process.execPath, ['--input-type=module', '-e',
      "const t = performance.now(); const { init } = await import('restitch'); const r = await init(); r.sample('fence'); console.log(performance.now() - t);"],
    { cwd: dir, encoding: 'utf8' });
    if (r.status !== 0) throw new Error(r.stderr);
    times.push(Number(r.stdout.trim()));
  }
  console.log(`${name}: init() in node ${median(times).toFixed(0)} ms (median of ${runs}, ${times.map((t) => t.toFixed(0)).join(' ')})`);
}

// init() in Chromium: import + compile + instantiate, from a fresh profile each time.
const page = `<!doctype html><meta charset="utf-8"><link rel="icon" href="data:,">
<script type="importmap">{"imports": {"three": "./node_modules/three/build/three.module.js",
  "three/addons/": "./node_modules/three/examples/jsm/", "restitch": "./node_modules/restitch/index.js",
  "restitch/three": "./node_modules/restitch/three.js"}}</script>
<script type="module">
const t0 = performance.now();
const { init } = await import('restitch');
await init();
window.startMs = performance.now() - t0;
</script>`;
for (const [name, dir] of Object.entries(installs)) {
  fs.writeFileSync(path.join(dir, 'start.html'), page);
  const server = await serve(dir);
  const times = [];
  try {
    for (let i = 0; i < runs; ++i) {
      const context = await launch();
      const p = context.pages()[0] || await context.newPage();
      await p.goto(server.base + 'start.html');
      await p.waitForFunction(() => window.startMs !== undefined, null, { timeout: 60000 });
      times.push(await p.evaluate(() => window.startMs));
      await context.close();
    }
  } finally {
    server.close();
  }
  console.log(`${name}: init() in Chromium ${median(times).toFixed(0)} ms (median of ${runs}, ${times.map((t) => t.toFixed(0)).join(' ')})`);
}

// A slider with restitch/three in Chromium.
const dir = installs.beside;
fs.mkdirSync(path.join(dir, 'in'), { recursive: true });
const bin = path.join(dir, 'node_modules/.bin/restitch');
const inputs = runOk(bin, ['sample', '--list']).trim().split('\n').map((l) => l.split('\t')[0]);
for (const s of inputs) runOk(bin, ['sample', s, '-o', path.join(dir, 'in', `${s}.glb`)]);
const shared = fs.existsSync(modelsDir) ? fs.readdirSync(modelsDir).filter((f) => f.endsWith('.glb')).sort() : [];
for (const f of shared) fs.copyFileSync(path.join(modelsDir, f), path.join(dir, 'in', f));
fs.writeFileSync(path.join(dir, 'slider.html'), page.replace(/<script type="module">[\s\S]*<\/script>/, `<script type="module">
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { analyze, release } from 'restitch/three';
window.slide = async (url) => {
  const scene = (await new GLTFLoader().loadAsync(url)).scene;
  let t = performance.now();
  const r = await analyze(scene);
  const analyzeMs = performance.now() - t;
  if (r.principalOffsets.length === 0) { release(scene); return { analyzeMs, none: true }; }
  const moves = [1, 2, 3, 2, 1, -1, 0].map((s) => {
    t = performance.now();
    try { r.resize({ steps: [s] }); } catch (e) { return null; }
    return performance.now() - t;
  });
  release(scene);
  return { analyzeMs, moves };
};
window.ready = true;
</script>`));
const server = await serve(dir);
const context = await launch();
try {
  const p = context.pages()[0] || await context.newPage();
  await p.goto(server.base + 'slider.html');
  await p.waitForFunction(() => window.ready, null, { timeout: 60000 });
  for (const f of [...inputs.map((s) => `${s}.glb`), ...shared]) {
    const r = await p.evaluate((url) => window.slide(url), `in/${f}`);
    if (r.none) { console.log(`slider ${f}: analyse ${r.analyzeMs.toFixed(0)} ms, no repeat`); continue; }
    const later = r.moves.slice(1).filter((x) => x !== null);
    console.log(`slider ${f}: analyse ${r.analyzeMs.toFixed(0)} ms, first move ${r.moves[0] === null ? 'refused' : r.moves[0].toFixed(0) + ' ms'}, ` +
                `later moves median ${later.length ? median(later).toFixed(0) : '-'} ms, max ${later.length ? Math.max(...later).toFixed(0) : '-'} ms`);
  }
} finally {
  await context.close();
  server.close();
  fs.rmSync(work, { recursive: true, force: true });
}
