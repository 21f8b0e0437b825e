// Test of the npm package as a user gets it: scripts/pack-npm.sh packs it, `npm install` puts the tarball (and
// three, packed from demo_web/node_modules) in an empty folder elsewhere, and everything below runs from there:
//   - node: `import 'restitch'` opens, analyses and resizes; the API's .glb equals the tool's; errors are
//     RestitchErrors with the library's code; arrays in, arrays out;
//   - `npx restitch`: scripts/golden.sh run with the installed tool and with the native one
//     (`--threads 1`) over every sample and ../shared/models (when present) gives identical files;
//   - TypeScript: a consumer that uses every export type-checks (`tsc --noEmit`), and one that misuses them
//     does not;
//   - three.js in Chromium: a loaded glTF scene resized by restitch/three has the size and triangle count the
//     tool reports, its materials (the same objects) and UV sets, and per material the tool's area, centroid
//     and mean UVs; prints the milliseconds per slider move. The API in a module worker.
// Native tool: RESTITCH_CLI, else build/native/restitch or build/dev/restitch. Build folder of the
// WebAssembly files: RESTITCH_WEB_BUILD (as scripts/pack-npm.sh). Ends with "package: N passed, M failed".
// Usage: node demo_web/tests/package.mjs   (exit code 1 on any failure)
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { spawnSync } from 'node:child_process';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { serve, launch } from './browser.mjs';
import { assert, attempt as attemptLines, check, finish } from './checks.mjs';
import { pack, install, root, runOk } from './consumer.mjs';

const demo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const modelsDir = path.resolve(root, '../shared/models');
const attempt = (name, fn) => attemptLines(name, fn, 3);  // a failure's first three lines

function run(cmd, args, options = {}) {
  const r = spawnSync(cmd, args, { encoding: 'buffer', maxBuffer: 1 << 28, ...options });
  if (r.error) throw r.error;
  return r;
}

const native = [process.env.RESTITCH_CLI, path.join(root, 'build/native/restitch'), path.join(root, 'build/dev/restitch')]
  .find((p) => p && fs.existsSync(p));
const work = fs.mkdtempSync(path.join(os.tmpdir(), 'restitch-npm-'));
const consumer = path.join(work, 'consumer');
let context, server;
try {
  // ---- pack and install ----------------------------------------------------------------------------------------
  let tarball;
  await attempt('scripts/pack-npm.sh writes the tarball', () => {
    tarball = pack(path.join(work, 'pack'));
    return `${path.basename(tarball)}, ${(fs.statSync(tarball).size / 1e6).toFixed(2)} MB`;
  });
  await attempt('npm install of the tarball (and three) in an empty folder', () => {
    install(tarball, consumer);
    const installed = path.join(consumer, 'node_modules/restitch');
    for (const f of ['index.js', 'index.d.ts', 'three.js', 'three.d.ts', 'dist/restitch_web.wasm', 'cli/restitch.wasm', 'LICENSE', 'README.md']) {
      assert(fs.existsSync(path.join(installed, f)), `the package has no ${f}`);
    }
    assert(!fs.existsSync(path.join(installed, 'node_modules')), 'the package installed dependencies of its own');
  });
  const pkg = (f) => pathToFileURL(path.join(consumer, 'node_modules/restitch', f)).href;
  const bin = path.join(consumer, 'node_modules/.bin/restitch');

  // ---- node ----------------------------------------------------------------------------------------------------
  const { init, RestitchError } = await import(pkg('index.js'));
  const restitch = await init();
  const expectedVersion = fs.readFileSync(path.join(root, 'CMakeLists.txt'), 'utf8').match(/project\(restitch VERSION ([0-9.]+)/)[1];
  await attempt('init() loads the module under plain node and reports the project version', () => {
    assert(restitch.version === `restitch ${expectedVersion}`, restitch.version);
    assert(restitch.policies().descriptors.length > 0, 'no descriptors');
    return restitch.version;
  });
  fs.mkdirSync(path.join(consumer, 'in'));
  const samples = restitch.samples().map((s) => s.name);
  for (const s of samples) runOk(bin, ['sample', s, '-o', path.join(consumer, 'in', `${s}.glb`)]);
  await attempt('the API resizes a model opened from bytes; its .glb is the tool\'s, byte for byte', () => {
    const input = path.join(consumer, 'in', 'bookshelf.glb');
    const model = restitch.open(fs.readFileSync(input));
    const analysis = model.analyze();
    assert(model.principalOffsets.length === 2, `principal offsets: ${JSON.stringify(analysis.principal_offsets)}`);
    assert(model.prepare() > 0, 'prepare() took no time');  // warms the caches; the bytes below must not change
    const result = model.resize({ steps: [0, 2] });
    const api = result.glb();
    runOk(bin, ['resize', input, '-o', path.join(consumer, 'cli.glb'), '--steps', '0,2', '--json', path.join(consumer, 'cli.json')]);
    const cli = fs.readFileSync(path.join(consumer, 'cli.glb'));
    assert(Buffer.compare(Buffer.from(api), cli) === 0, `API ${api.length} bytes, tool ${cli.length} bytes`);
    const report = JSON.parse(fs.readFileSync(path.join(consumer, 'cli.json'), 'utf8'));
    assert(JSON.stringify(report.size_out) === JSON.stringify(result.report.size_out), 'size_out differs');
    assert(result.mesh.indices.length / 3 === report.output.triangles, 'triangle count differs');
    model.delete();
    return `${api.length} bytes`;
  });
  await attempt('resize by size gives the nearest whole repeats, and exact scales to the size', () => {
    const model = restitch.sample('fence');
    model.analyze();
    const [ox, oy, oz] = model.principalOffsets[0];
    const axis = [ox, oy, oz].map(Math.abs).indexOf(Math.max(...[ox, oy, oz].map(Math.abs)));
    const pitch = Math.abs([ox, oy, oz][axis]);
    const sizeIn = model.info.bbox_max.map((v, k) => v - model.info.bbox_min[k]);
    const want = [0, 0, 0];
    want[axis] = sizeIn[axis] + 2.3 * pitch;  // nearest: +2 repeats
    const near = model.resize({ size: want });
    assert(Math.abs(near.report.size_out[axis] - (sizeIn[axis] + 2 * pitch)) < 1e-4 * pitch, `nearest ${near.report.size_out[axis]}`);
    const exact = model.resize({ size: want, exact: true });
    assert(Math.abs(exact.report.size_out[axis] - want[axis]) < 1e-5 * want[axis], `exact ${exact.report.size_out[axis]} for ${want[axis]}`);
    let stale = null;
    try { near.glb(); } catch (e) { stale = e; }
    assert(stale instanceof RestitchError, 'an older result gave bytes after a later resize');
    model.delete();
  });
  await attempt('failures are RestitchErrors with the library\'s code', () => {
    const codeOf = (fn) => { try { fn(); return 'no error'; } catch (e) { return e instanceof RestitchError ? e.code : `not a RestitchError: ${e}`; } };
    assert(codeOf(() => restitch.open(new Uint8Array([1, 2, 3, 4]))) === 'parse_error', 'garbage bytes');
    assert(codeOf(() => restitch.open('shelf.glb')) === 'invalid_argument', 'a path instead of bytes');
    assert(codeOf(() => restitch.sample('no such sample')) === 'invalid_argument', 'an unknown sample');
    const model = restitch.sample('bookshelf');
    assert(codeOf(() => model.analyze({ descriptor: 'nope' })) === 'invalid_argument', 'an unknown descriptor');
    assert(codeOf(() => model.resize({ steps: [1.5] })) === 'invalid_argument', 'fractional steps');
    assert(codeOf(() => model.resize({ steps: [1], size: [1, 0, 0] })) === 'invalid_argument', 'steps and size');
    assert(codeOf(() => model.resize({ size: [-1, 0, 0] })) === 'invalid_argument', 'a negative size');
    assert(codeOf(() => restitch.fromArrays({ positions: new Float32Array(9), indices: new Uint32Array([0, 1, 3]) })) === 'invalid_argument', 'an index past the end');
    model.delete();
    assert(codeOf(() => model.resize({ steps: [1] })) === 'invalid_argument', 'a deleted model');
  });
  await attempt('arrays in and out: a model given as arrays analyses and resizes as the same model from glTF', () => {
    const model = restitch.open(fs.readFileSync(path.join(consumer, 'in', 'bookshelf.glb')));
    const m = model.mesh();
    const arrays = {
      positions: m.positions, indices: m.indices, normals: m.normals, uvs: m.uvSets,
      groups: m.groups.map((g) => ({ start: g.start, count: g.count, material: g.material, name: g.name })),
    };
    const copy = restitch.fromArrays(arrays);
    assert(copy.info.triangles === model.info.triangles && copy.info.vertices === model.info.vertices, 'counts differ');
    const a = model.analyze(), b = copy.analyze();
    assert(JSON.stringify(a.principal_offsets) === JSON.stringify(b.principal_offsets), 'principal offsets differ');
    const ra = model.resize({ steps: [1, 1] }), rb = copy.resize({ steps: [1, 1] });
    assert(JSON.stringify(ra.report.size_out) === JSON.stringify(rb.report.size_out), 'sizes differ');
    assert(ra.mesh.indices.length === rb.mesh.indices.length, 'triangle counts differ');
    assert(rb.mesh.groups.map((g) => g.group).join() === m.groups.map((g, i) => i).join(), 'groups not kept in order');
    assert(rb.mesh.uvSets.length === m.uvSets.length, 'uv sets lost');
    model.delete(); copy.delete();
  });

  // ---- npx restitch ---------------------------------------------------------------------------------------------
  await attempt('`npx restitch resize` works from the installed package', () => {
    const r = run('npx', ['--offline', 'restitch', 'resize', 'in/fence.glb', '-o', 'npx.glb', '--steps', '2'], { cwd: consumer });
    assert(r.status === 0, `exit ${r.status}: ${r.stderr.toString().slice(-300)}`);
    assert(/wrote npx\.glb/.test(r.stdout.toString()), r.stdout.toString().slice(0, 300));
    const bad = run('npx', ['--offline', 'restitch', 'resize', 'in/missing.glb', '-o', 'x.glb', '--steps', '2'], { cwd: consumer });
    assert(bad.status !== 0 && /missing\.glb/.test(bad.stderr.toString()), `a missing input: exit ${bad.status}`);
    assert(!fs.existsSync(path.join(consumer, 'x.glb')), 'a file was written for a missing input');
  });
  await attempt('npx restitch gives the native tool\'s bytes (--threads 1) on every sample and shared model', () => {
    assert(native, 'no native restitch tool: build it (build/native) or set RESTITCH_CLI');
    const wrap = (name, cmd) => {
      const file = path.join(work, name);
      fs.writeFileSync(file, `#!/bin/sh\ncase "$1" in analyze|resize) exec ${cmd} "$@" --threads 1;; *) exec ${cmd} "$@";; esac\n`);
      fs.chmodSync(file, 0o755);
      return file;
    };
    const golden = path.join(root, 'scripts/golden.sh');
    const env = { ...process.env, RESTITCH_JOBS: process.env.RESTITCH_JOBS || '2' };
    runOk('bash', [golden, wrap('native.sh', native), path.join(work, 'g-native')], { env });
    runOk('bash', [golden, wrap('npx.sh', bin), path.join(work, 'g-npx')], { env });
    // Models and messages byte for byte. Reports: every field equal, numbers to 1e-6 relative: Eigen
    // vectorizes sums with SSE2 natively and not under WebAssembly, so a printed sum may differ in its
    // last digits (docs/building.md); the models written are the same bytes.
    const a = path.join(work, 'g-native'), b = path.join(work, 'g-npx');
    const names = fs.readdirSync(a).filter((f) => f !== 'in').sort();
    assert(JSON.stringify(names) === JSON.stringify(fs.readdirSync(b).filter((f) => f !== 'in').sort()), 'different files written');
    const close = (x, y, where) => {
      if (typeof x === 'number' && typeof y === 'number') {
        if (Math.abs(x - y) > 1e-6 * Math.max(1, Math.abs(x), Math.abs(y))) throw new Error(`${where}: ${x} vs ${y}`);
      } else if (x && y && typeof x === 'object' && typeof y === 'object') {
        const keys = Object.keys(x);
        if (JSON.stringify(keys) !== JSON.stringify(Object.keys(y))) throw new Error(`${where}: fields differ`);
        for (const k of keys) close(x[k], y[k], `${where}.${k}`);
      } else if (x !== y) throw new Error(`${where}: ${JSON.stringify(x)} vs ${JSON.stringify(y)}`);
    };
    let glbs = 0, digits = 0;
    for (const f of names) {
      const x = fs.readFileSync(path.join(a, f)), y = fs.readFileSync(path.join(b, f));
      if (Buffer.compare(x, y) === 0) { glbs += f.endsWith('.glb'); continue; }
      assert(f.endsWith('.json'), `${f} differs`);
      close(JSON.parse(x.toString()), JSON.parse(y.toString()), f);
      ++digits;
    }
    assert(glbs > 20, `only ${glbs} models written`);
    return `${glbs} models identical, ${names.length - glbs} reports and messages (${digits} reports with last digits apart)${fs.existsSync(modelsDir) ? ', shared models included' : ''}`;
  });

  // ---- TypeScript -----------------------------------------------------------------------------------------------
  const tsc = path.join(demo, 'node_modules/typescript/bin/tsc');
  const tsconfig = { compilerOptions: { strict: true, noEmit: true, module: 'node16', moduleResolution: 'node16', target: 'es2022', lib: ['es2022', 'dom'], typeRoots: [path.join(demo, 'node_modules/@types')], types: [] } };
  const typeCheck = (source) => {
    const dir = fs.mkdtempSync(path.join(consumer, 'ts-'));
    fs.writeFileSync(path.join(dir, 'main.ts'), source);
    fs.writeFileSync(path.join(dir, 'tsconfig.json'), JSON.stringify({ ...tsconfig, files: ['main.ts'] }));
    // @types/three from the demo's devDependencies, where the consumer's own install would put it.
    fs.mkdirSync(path.join(consumer, 'node_modules/@types'), { recursive: true });
    const link = path.join(consumer, 'node_modules/@types/three');
    if (!fs.existsSync(link)) fs.symlinkSync(path.join(demo, 'node_modules/@types/three'), link);
    return run(process.execPath, [tsc, '-p', dir]);
  };
  await attempt('the typings type-check a TypeScript consumer of both entries (tsc --noEmit, strict)', () => {
    const r = typeCheck(`
import { init, RestitchError, type Analysis, type Report, type Result } from 'restitch';
import { analyze, resize, release, type Resizable } from 'restitch/three';
import { Mesh, BufferGeometry, MeshStandardMaterial, Object3D } from 'three';
const restitch = await init();
const model = restitch.sample('bookshelf', { columns: 3 });
const a: Analysis = model.analyze({ descriptor: 'shot', onProgress: (stage: string, f: number) => {} });
const first: [number, number, number] = a.principal_offsets[0];
const r: Result = model.resize({ steps: [2, 0], pivot: 'center' });
const report: Report = r.report;
const tris: number = report.output.triangles + r.mesh.indices.length;
const bytes: Uint8Array = r.glb();
try { restitch.open(bytes); } catch (e) { if (e instanceof RestitchError) console.log(e.code); }
model.delete();
const mesh = new Mesh(new BufferGeometry(), new MeshStandardMaterial());
const resizable: Resizable<Mesh> = await analyze(mesh);
const rep: Report = resizable.resize({ size: [1.8, 0, 0], exact: true });
const copy: Mesh = resizable.resize({ steps: 1, into: 'new' }).object;
const rep2: Report = await resize(new Object3D(), { steps: [1] });
release(mesh);
`);
    assert(r.status === 0, r.stdout.toString().slice(0, 600));
  });
  await attempt('the typings reject a misuse (steps as a string, a wrong field, an unknown export)', () => {
    for (const [what, source] of [
      ['steps as a string', `import { init } from 'restitch'; const m = (await init()).sample('x'); m.resize({ steps: 'two' });`],
      ['a misspelt report field', `import { init } from 'restitch'; const r = (await init()).sample('x').resize({ steps: 1 }); const n: number = r.report.size_outt[0];`],
      ['an unknown export', `import { resizeEverything } from 'restitch/three';`],
    ]) {
      const r = typeCheck(source);
      assert(r.status !== 0, `tsc accepted ${what}`);
    }
  });

  // ---- three.js in Chromium -------------------------------------------------------------------------------------
  fs.writeFileSync(path.join(consumer, 'index.html'), `<!doctype html><meta charset="utf-8"><title>restitch/three</title><link rel="icon" href="data:,">
<script type="importmap">{"imports": {"three": "./node_modules/three/build/three.module.js",
  "three/addons/": "./node_modules/three/examples/jsm/", "restitch": "./node_modules/restitch/index.js",
  "restitch/three": "./node_modules/restitch/three.js"}}</script>
<script type="module">
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { analyze, resize, release } from 'restitch/three';
const stats = (object) => {
  object.updateMatrixWorld(true);
  let triangles = 0; const materials = []; const uvs = []; const meshes = [];
  object.traverse((o) => { if (o.isMesh) {
    const g = o.geometry; triangles += (g.index ? g.index.count : g.attributes.position.count) / 3;
    materials.push(...(Array.isArray(o.material) ? o.material : [o.material])); meshes.push(o);
    uvs.push(['uv', 'uv1'].filter((n) => g.attributes[n]).join('+'));
  } });
  const box = new THREE.Box3().setFromObject(object);
  return { triangles, materials, uvs, meshes, size: box.getSize(new THREE.Vector3()).toArray() };
};
// Per material: the area, the area-weighted centroid and mean of each uv set: what a resize must give
// whatever the node layout and vertex order.
const moments = (object) => {
  object.updateMatrixWorld(true);
  const out = {};
  const a = new THREE.Vector3(), b = new THREE.Vector3(), c = new THREE.Vector3();
  object.traverse((o) => { if (!o.isMesh) return;
    const g = o.geometry, mats = Array.isArray(o.material) ? o.material : [o.material];
    const ranges = g.groups.length && Array.isArray(o.material) ? g.groups : [{ start: 0, count: g.index ? g.index.count : g.attributes.position.count, materialIndex: 0 }];
    for (const r of ranges) {
      const m = (out[mats[r.materialIndex].name] ??= { area: 0, centroid: [0, 0, 0], uv: [0, 0, 0, 0] });
      for (let q = r.start; q + 2 < r.start + r.count; q += 3) {
        const i = [0, 1, 2].map((k) => (g.index ? g.index.getX(q + k) : q + k));
        a.fromBufferAttribute(g.attributes.position, i[0]).applyMatrix4(o.matrixWorld);
        b.fromBufferAttribute(g.attributes.position, i[1]).applyMatrix4(o.matrixWorld);
        c.fromBufferAttribute(g.attributes.position, i[2]).applyMatrix4(o.matrixWorld);
        const area = new THREE.Triangle(a, b, c).getArea();
        m.area += area;
        for (let k = 0; k < 3; ++k) m.centroid[k] += area * (a.getComponent(k) + b.getComponent(k) + c.getComponent(k)) / 3;
        ['uv', 'uv1'].forEach((n, s) => { const uv = g.attributes[n]; if (!uv) return;
          for (const v of i) { m.uv[2 * s] += area * uv.getX(v) / 3; m.uv[2 * s + 1] += area * uv.getY(v) / 3; } });
      }
    }
  });
  return out;
};
window.runCase = async (url, steps, into, cliUrl) => {
  const cli = moments((await new GLTFLoader().loadAsync(cliUrl)).scene);
  const gltf = await new GLTFLoader().loadAsync(url);
  const scene = gltf.scene;
  const before = stats(scene);
  const resizable = await analyze(scene);
  const out = into === 'new' ? resizable.resize({ steps, into: 'new' }) : { object: scene, report: resizable.resize({ steps }) };
  const after = stats(out.object);
  const mine = moments(out.object);
  const names = Object.keys(cli).sort();
  let momentsOk = JSON.stringify(names) === JSON.stringify(Object.keys(mine).sort()) ? '' : 'materials ' + names + ' vs ' + Object.keys(mine).sort();
  const scale = Math.max(...after.size, 1e-9);
  for (const n of names) {
    if (momentsOk || !mine[n]) break;
    const x = cli[n], y = mine[n], A = Math.max(x.area, 1e-12);
    const far = Math.abs(x.area - y.area) > 1e-4 * A || x.centroid.some((v, k) => Math.abs(v - y.centroid[k]) > 1e-4 * A * scale) ||
      x.uv.some((v, k) => Math.abs(v - y.uv[k]) > 1e-4 * A * Math.max(1, Math.abs(v / A)));
    if (far) momentsOk = n + ': area ' + x.area + ' vs ' + y.area + ', centroid ' + x.centroid + ' vs ' + y.centroid + ', uv ' + x.uv + ' vs ' + y.uv;
  }
  const sameMaterials = after.materials.length === before.materials.length && after.materials.every((m, i) => m === before.materials[i]);
  const untouched = into === 'new' ? stats(scene).triangles === before.triangles : true;
  resizable.restore();
  const restored = stats(scene);
  const restoredOk = restored.triangles === before.triangles && restored.size.every((v, k) => Math.abs(v - before.size[k]) < 1e-6);
  // A slider: resizes after the first one, each from the cached analysis.
  const moves = 8; const t0 = performance.now();
  for (let i = 1; i <= moves; ++i) resizable.resize({ steps: steps.map((s) => (s ? 1 + (i % 3) : 0)) });
  const msPerMove = (performance.now() - t0) / moves;
  release(scene);
  return { triangles: after.triangles, size: after.size, sameMaterials, momentsOk, untouched, restoredOk, uvsBefore: before.uvs, uvsAfter: after.uvs,
           report: { triangles: out.report.output.triangles, size_out: out.report.size_out }, msPerMove };
};
window.geometryCase = async (url) => {
  const gltf = await new GLTFLoader().loadAsync(url);
  let mesh = null; gltf.scene.traverse((o) => { if (o.isMesh && !mesh) mesh = o; });
  const geometry = mesh.geometry.clone();
  const count = geometry.index.count;
  const r = await analyze(geometry);
  const report = r.resize({ steps: [1] });
  const grown = geometry.index.count;
  r.dispose();
  return { count, grown, restored: geometry.index.count, reportTriangles: report.output.triangles };
};
document.body.dataset.ready = '1';
</script>`);
  server = await serve(consumer);
  const base = server.base;
  context = await launch();
  const page = context.pages()[0] || await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  await page.goto(base + 'index.html');
  await page.waitForFunction(() => document.body && document.body.dataset.ready === '1', null, { timeout: 30000 });
  const cases = [['bookshelf', [0, 2], 'self'], ['fence', [2], 'new'], ['pin_header', [-1], 'self']];
  if (fs.existsSync(modelsDir)) {
    const shared = fs.readdirSync(modelsDir).filter((f) => f.endsWith('.glb')).sort()[0];
    fs.copyFileSync(path.join(modelsDir, shared), path.join(consumer, 'in', shared));
    cases.push([shared.replace(/\.glb$/, ''), [2], 'self']);
  }
  const slider = [];
  for (const [name, steps, into] of cases) {
    await attempt(`restitch/three resizes the glTF scene of ${name} by ${steps} (${into === 'new' ? 'into a copy' : 'in place'}) as the tool does`, async () => {
      const file = path.join(consumer, 'in', `${name}.glb`);
      assert(fs.existsSync(file), `no ${file}`);
      const outFile = path.join(work, `${name}.cli.glb`), jsonFile = path.join(work, `${name}.cli.json`);
      runOk(bin, ['resize', file, '-o', outFile, '--steps', steps.join(','), '--json', jsonFile]);
      const cli = JSON.parse(fs.readFileSync(jsonFile, 'utf8'));
      fs.copyFileSync(outFile, path.join(consumer, 'in', `${name}.cli.glb`));
      const got = await page.evaluate(([url, s, i, c]) => window.runCase(url, s, i, c), [`in/${name}.glb`, steps, into, `in/${name}.cli.glb`]);
      assert(got.report.triangles === cli.output.triangles, `the helper's report says ${got.report.triangles} triangles, the tool ${cli.output.triangles}`);
      assert(got.triangles === cli.output.triangles, `the scene has ${got.triangles} triangles, the tool wrote ${cli.output.triangles}`);
      const tol = 1e-4 * Math.hypot(...cli.size_out);
      assert(got.size.every((v, k) => Math.abs(v - cli.size_out[k]) <= tol), `scene size ${got.size.map((v) => v.toFixed(4))} vs ${cli.size_out.map((v) => v.toFixed(4))}`);
      assert(got.sameMaterials, 'the meshes do not keep their material objects');
      assert(!got.momentsOk, `per material, the tool's result and the helper's differ: ${got.momentsOk}`);
      assert(JSON.stringify(got.uvsAfter) === JSON.stringify(got.uvsBefore), `uv sets ${got.uvsBefore} became ${got.uvsAfter}`);
      assert(got.untouched, 'into: new changed the original');
      assert(got.restoredOk, 'restore() did not give the original back');
      slider.push(`${name} ${got.msPerMove.toFixed(1)} ms`);
      return `${got.triangles} triangles, ${got.msPerMove.toFixed(1)} ms per slider move`;
    });
  }
  await attempt('the API runs in a module worker too (resize of the fence sample, answered by postMessage)', async () => {
    fs.writeFileSync(path.join(consumer, 'worker.mjs'), `
import { init } from './node_modules/restitch/index.js';  // import maps do not reach workers: a path
const restitch = await init();
const model = restitch.sample('fence');
model.analyze();
const result = model.resize({ steps: [1] });
postMessage({ triangles: result.report.output.triangles, glb: result.glb().length });
model.delete();`);
    const got = await page.evaluate(() => new Promise((resolve, reject) => {
      const w = new Worker('./worker.mjs', { type: 'module' });
      w.onmessage = (e) => { resolve(e.data); w.terminate(); };
      w.onerror = (e) => reject(new Error(e.message || 'worker error'));
    }));
    runOk(bin, ['resize', path.join(consumer, 'in', 'fence.glb'), '-o', path.join(work, 'fence1.glb'), '--steps', '1', '--json', path.join(work, 'fence1.json')]);
    const cli = JSON.parse(fs.readFileSync(path.join(work, 'fence1.json'), 'utf8'));
    assert(got.triangles === cli.output.triangles && got.glb === fs.statSync(path.join(work, 'fence1.glb')).size,
           `worker: ${JSON.stringify(got)}, tool: ${cli.output.triangles} triangles`);
  });
  await attempt('restitch/three resizes a bare BufferGeometry in place and restores it', async () => {
    const got = await page.evaluate(() => window.geometryCase('in/fence.glb'));
    assert(got.grown > got.count && got.grown === got.reportTriangles * 3, JSON.stringify(got));
    assert(got.restored === got.count, `restored ${got.restored} of ${got.count}`);
  });
  check('the page logged no error', errors.length === 0, errors.slice(0, 3).join(' | '));
  console.log(`package: slider move after the first (Chromium, headless): ${slider.join(', ')}`);
} catch (e) {
  check('the package test ran to the end', false, e && e.stack ? e.stack.split('\n').slice(0, 3).join(' | ') : String(e));
} finally {
  if (context) await context.close();
  if (server) server.close();
  fs.rmSync(work, { recursive: true, force: true });
}
finish('package');
