// Renders OUT_DIR/manifest.json (written by scripts/contact-sheet.sh) into OUT_DIR/contact-sheet.png and
// OUT_DIR/contact-sheet-small.png with sheet.html in headless Chromium (SwiftShader WebGL) through
// playwright-core. No HTTP server: the page's requests to http://sheet.invalid/ are answered from disk
// (the page, three.js from NODE_MODULES, the models from OUT_DIR). Each PNG is written under a temporary
// name and renamed, so a failed run leaves no half-written picture; any failure exits non-zero.
// Usage: node scripts/contact-sheet/render.mjs NODE_MODULES OUT_DIR [--cell PX] [--only NAME_PART] [--prefix NAME]
// (--cell, --only and --prefix, to look closer at some rows: bigger cells, the rows whose model name
// contains one of the comma-separated NAME_PARTs, written as OUT_DIR/NAME.png and OUT_DIR/NAME-small.png.)
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';

const arg = (name, fallback) => {
  const i = process.argv.indexOf(name);
  return i > 0 && process.argv[i + 1] ? process.argv[i + 1] : fallback;
};
const [nodeModules, outDir] = process.argv.slice(2, 4).map((p) => p && !p.startsWith('--') && path.resolve(p));
const options = { cell: Number(arg('--cell', '300')), only: arg('--only', '') };
const prefix = arg('--prefix', 'contact-sheet');
if (!nodeModules || !outDir) {
  console.error('usage: node render.mjs NODE_MODULES OUT_DIR');
  process.exit(2);
}
const here = path.dirname(fileURLToPath(import.meta.url));
const { chromium } = createRequire(import.meta.url)(path.join(nodeModules, 'playwright-core'));
const manifest = JSON.parse(fs.readFileSync(path.join(outDir, 'manifest.json'), 'utf8'));

// URL path prefix -> folder it is served from.
const roots = [['/three/', path.join(nodeModules, 'three')], ['/files/', outDir], ['/', here]];
const types = { '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.glb': 'model/gltf-binary', '.json': 'application/json' };
const serve = async (route) => {
  const url = new URL(route.request().url());
  const p = decodeURIComponent(url.pathname);
  const [prefix, dir] = roots.find(([pre]) => p.startsWith(pre));
  const file = path.resolve(dir, p.slice(prefix.length));
  if (!file.startsWith(dir + path.sep) || !fs.existsSync(file) || !fs.statSync(file).isFile()) {
    await route.fulfill({ status: 404, body: `not found: ${p}` });
    return;
  }
  await route.fulfill({ status: 200, path: file, headers: { 'content-type': types[path.extname(file)] || 'application/octet-stream' } });
};

const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'restitch-sheet-'));
let context;
let code = 0;
const written = [];
try {
  context = await chromium.launchPersistentContext(userDataDir, {
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium', headless: true,
    viewport: { width: 800, height: 600 }, deviceScaleFactor: 1,
    args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-quic',
           '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  await context.route('http://sheet.invalid/**', serve);
  const page = context.pages()[0] || await context.newPage();
  const errors = [];
  const fail = (m) => { errors.push(m); console.error(`page: ${m}`); };
  page.on('pageerror', (e) => fail(e.message));
  page.on('console', (m) => { if (m.type() === 'error') fail(m.text()); });
  page.on('requestfailed', (r) => fail(`${r.url()}: ${r.failure() && r.failure().errorText}`));
  const response = await page.goto('http://sheet.invalid/sheet.html');
  if (!response || !response.ok()) throw new Error(`sheet.html: ${response ? response.status() : 'no response'}`);
  await page.waitForFunction(() => typeof window.renderSheet === 'function', null, { timeout: 60000, polling: 100 });
  const t0 = Date.now();
  page.setDefaultTimeout(0);
  const result = await page.evaluate(([m, o]) => window.renderSheet(m, o), [manifest, options]);
  if (errors.length) throw new Error(`page errors: ${errors.join(' | ')}`);
  for (const [key, name] of [['full', `${prefix}.png`], ['small', `${prefix}-small.png`]]) {
    const png = Buffer.from(result[key].replace(/^data:image\/png;base64,/, ''), 'base64');
    if (png.length < 1000 || png.readUInt32BE(0) !== 0x89504e47) throw new Error(`${name}: the page returned no PNG`);
    const target = path.join(outDir, name);
    const tmp = `${target}.tmp-${process.pid}`;
    written.push(tmp);
    fs.writeFileSync(tmp, png);
    fs.renameSync(tmp, target);
    console.log(`${target}: ${result[`${key}Size`].join(' x ')} px, ${png.length} bytes`);
  }
  for (const line of result.log) console.log(line);
  console.log(`rendered ${manifest.rows.length} rows in ${((Date.now() - t0) / 1000).toFixed(1)} s`);
} catch (e) {
  console.error(`contact-sheet render: ${e && e.message ? e.message : e}`);
  code = 1;
} finally {
  if (context) await context.close().catch(() => {});
  fs.rmSync(userDataDir, { recursive: true, force: true });
  for (const tmp of written) fs.rmSync(tmp, { force: true });
}
process.exit(code);
