// What the browser tests and measurements share: a static server for a folder on a free 127.0.0.1 port
// (python3 -m http.server) and Debian's Chromium, headless with software WebGL (playwright-core).
//   const server = await serve(dir);            // server.base = 'http://127.0.0.1:PORT/'; server.close()
//   const context = await launch({ viewport });  // a persistent context in a fresh temporary profile
import fs from 'node:fs';
import os from 'node:os';
import net from 'node:net';
import path from 'node:path';
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';

const demo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const { chromium } = createRequire(path.join(demo, 'package.json'))('playwright-core');

export function freePort() {
  return new Promise((resolve, reject) => {
    const srv = net.createServer();
    srv.once('error', reject);
    srv.listen(0, '127.0.0.1', () => { const { port } = srv.address(); srv.close(() => resolve(port)); });
  });
}

// Serves `dir`; resolves once the server answers (15 s at most).
export async function serve(dir) {
  const port = await freePort();
  const child = spawn('python3', ['-m', 'http.server', String(port), '--bind', '127.0.0.1'], { cwd: dir, stdio: 'ignore' });
  const base = `http://127.0.0.1:${port}/`;
  const close = () => child.kill();
  for (const end = Date.now() + 15000; Date.now() < end;) {
    try { if ((await fetch(base)).ok) return { base, close }; } catch { /* not yet */ }
    await new Promise((r) => setTimeout(r, 100));
  }
  close();
  throw new Error(`the static server did not answer at ${base}`);
}

// Chromium with the flags every test uses; `options` go to launchPersistentContext (viewport, acceptDownloads...).
// The profile folder is removed when the context closes.
export async function launch(options = {}) {
  const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'restitch-chromium-'));
  const context = await chromium.launchPersistentContext(userDataDir, {
    executablePath: '/usr/bin/chromium', headless: true, viewport: { width: 1280, height: 800 }, ...options,
    args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-quic',
           '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  const close = context.close.bind(context);
  context.close = async (...a) => {
    await close(...a);
    fs.rmSync(userDataDir, { recursive: true, force: true, maxRetries: 5, retryDelay: 100 });
  };
  return context;
}
