// The npm package as a user gets it, for the package's test and its measurements:
//   pack(outDir)            scripts/pack-npm.sh -> the tarball's path
//   install(tarball, dir)   an empty project in `dir` with the tarball and three (packed from
//                           demo_web/node_modules, so nothing is downloaded) installed by npm
import fs from 'node:fs';
import path from 'node:path';
import { spawnSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';

const demo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
export const root = path.resolve(demo, '..');

// Runs a command; throws with its exit code and the end of its standard error unless it succeeds.
export function runOk(cmd, args, options = {}) {
  const r = spawnSync(cmd, args, { encoding: 'buffer', maxBuffer: 1 << 28, ...options });
  if (r.error) throw r.error;
  if (r.status !== 0) throw new Error(`${cmd} ${args.join(' ')}: exit ${r.status}: ${(r.stderr || '').toString().slice(-400)}`);
  return r.stdout ? r.stdout.toString() : '';
}

export function pack(outDir) {
  const out = runOk('bash', [path.join(root, 'scripts/pack-npm.sh'), outDir], { stdio: ['ignore', 'pipe', 'inherit'] });
  const tarball = out.trim().split('\n').pop();
  if (!fs.existsSync(tarball) || !/restitch-\d+\.\d+\.\d+\.tgz$/.test(tarball)) throw new Error(`no tarball: ${out}`);
  return tarball;
}

export function install(tarball, dir) {
  fs.mkdirSync(dir, { recursive: true });
  fs.writeFileSync(path.join(dir, 'package.json'), JSON.stringify({ name: 'consumer', private: true, type: 'module' }));
  const three = runOk('npm', ['pack', path.join(demo, 'node_modules/three'), '--pack-destination', dir, '--loglevel=error'], { cwd: dir })
    .trim().split('\n').pop();
  runOk('npm', ['install', '--offline', '--no-audit', '--no-fund', '--loglevel=error', tarball, path.join(dir, three)], { cwd: dir });
  return dir;
}
