// Renders the README's before/after pictures with the demo page in Debian's Chromium (headless, SwiftShader
// WebGL) through playwright-core: the `bookshelf` sample as generated (4 x 4 compartments) and the same
// resized by steps [2, 1, 0] along its principal offsets, both in the "cells by label" view, from one camera
// (the one the page picks for the resized model), on a 640 x 480 page with the overlays hidden, so the
// pictures are the canvas alone and compare directly. Writes demo_web/before.png and demo_web/after.png.
// Not a test: run it by hand after a change that alters the pictures.
// Usage: node demo_web/tests/render-readme.mjs [--view labels|shaded|seams] [--before-view VIEW] [--zoom 0.78]
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { serve, launch } from './browser.mjs';

const here = path.dirname(fileURLToPath(import.meta.url));
const demo = path.resolve(here, '..');
const arg = (name, fallback) => {
  const i = process.argv.indexOf(name);
  return i > 0 && process.argv[i + 1] ? process.argv[i + 1] : fallback;
};
const view = arg('--view', 'labels');
const beforeView = arg('--before-view', view);
const steps = [2, 1, 0];
const zoom = Number(arg('--zoom', '0.78'));  // camera distance relative to the page's framing

const server = await serve(demo);
let context;
let code = 0;
try {
  context = await launch({ viewport: { width: 640, height: 480 }, deviceScaleFactor: 1 });
  const page = context.pages()[0] || await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  for (let i = 0; i < 100; ++i) {
    try { await page.goto(`${server.base}index.html?sample=bookshelf`); break; } catch { await new Promise((r) => setTimeout(r, 100)); }
  }
  await page.waitForFunction(() => ['ready', 'error'].includes(document.body.dataset.status), null,
                             { timeout: 120000, polling: 100 });
  const status = await page.evaluate(() => document.body.dataset.status);
  if (status !== 'ready') throw new Error(`the page did not get ready: ${await page.textContent('#error')}`);
  // The canvas alone: hide the DOM overlays and the drawn ones (principal offset arrows, histogram inset).
  await page.addStyleTag({ content: '#toolbar, #figures, #progress, #histogram-label, #drop-hint, .lil-gui { display: none !important; }' });
  await page.evaluate(() => window.restitchDemo.setOverlays({ offsets: false, histogram: false }));

  await page.evaluate((s) => window.restitchDemo.setSteps(s), steps);
  // The camera the page picks for the resized model frames both; move in a little (the page leaves room to
  // orbit), keeping the view direction.
  const picked = await page.evaluate(() => window.restitchDemo.getCamera());
  const camera = { target: picked.target, position: picked.position.map((x, k) => picked.target[k] + zoom * (x - picked.target[k])) };
  const shoot = async (s, v, file) => {
    const r = await page.evaluate((st) => window.restitchDemo.setSteps(st), s);
    await page.evaluate(([cam, vw]) => { window.restitchDemo.setView(vw); window.restitchDemo.setCamera(cam); }, [camera, v]);
    await page.evaluate(() => new Promise((res) => requestAnimationFrame(() => requestAnimationFrame(res))));
    const out = path.join(demo, file);
    await page.screenshot({ path: out, clip: { x: 0, y: 0, width: 640, height: 480 } });
    const report = await page.evaluate(() => window.restitchDemo.report);
    console.log(`${file}: steps [${s}] (${report.cells_out.join(' x ')} cells, ${r.triangles} triangles, ` +
                `${report.labels} labels), view ${v}, ${fs.statSync(out).size} bytes`);
  };
  await shoot([0, 0, 0], beforeView, 'before.png');
  await shoot(steps, view, 'after.png');
  if (errors.length) throw new Error(`page errors: ${errors.join(' | ')}`);
} catch (e) {
  console.error(`render-readme: ${e && e.message ? e.message : e}`);
  code = 1;
} finally {
  if (context) await context.close().catch(() => {});
  server.close();
}
process.exit(code);
