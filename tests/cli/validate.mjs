// Runs the Khronos glTF-Validator on each file given; prints one line per file
// and exits 1 if any file has an error. Usage: node validate.mjs FILE...
import fs from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';
const here = path.dirname(new URL(import.meta.url).pathname);
const require = createRequire(path.join(here, '../../demo_web/package.json'));
let validator;
try { validator = require('gltf-validator'); } catch (e) {
  console.error('gltf-validator is not installed: run scripts/install-deps.sh (npm ci in demo_web)');
  process.exit(2);
}
let bad = 0;
for (const file of process.argv.slice(2)) {
  const bytes = new Uint8Array(fs.readFileSync(file));
  const report = await validator.validateBytes(bytes, {
    uri: file, maxIssues: 100,
    externalResourceFunction: (uri) => Promise.resolve(new Uint8Array(fs.readFileSync(path.resolve(path.dirname(file), decodeURIComponent(uri))))),
  });
  const errors = report.issues.messages.filter((m) => m.severity === 0);
  console.log(`${path.basename(file)}: ${report.issues.numErrors} errors, ${report.issues.numWarnings} warnings`);
  for (const m of errors.slice(0, 10)) console.log(`  ${m.code} ${m.pointer ?? ''}: ${m.message}`);
  if (report.issues.numErrors > 0) bad++;
}
process.exit(bad ? 1 : 0);
