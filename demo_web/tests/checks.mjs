// The checks of the scripts that print TAP-like lines (e2e.mjs, package.mjs):
//   check(name, ok, detail)   prints "ok - name (detail)" or "not ok - ..." and counts it
//   await attempt(name, fn)   runs fn: passed unless it throws (its message, first lines, is the detail;
//                             a string it returns is the detail of a pass)
//   assert(cond, message)     throws message unless cond
//   finish(prefix)            prints "PREFIX: N passed, M failed" and exits 1 on any failure
let passed = 0, failed = 0;

export function check(name, ok, detail = '') {
  if (ok) passed++; else failed++;
  console.log(`${ok ? 'ok' : 'not ok'} - ${name}${detail ? ` (${detail})` : ''}`);
}

export async function attempt(name, fn, lines = 1) {
  try {
    const detail = await fn();
    check(name, true, typeof detail === 'string' ? detail : '');
  } catch (e) {
    check(name, false, e && e.message ? e.message.split('\n').slice(0, lines).join(' | ') : String(e));
  }
}

export function assert(cond, message) { if (!cond) throw new Error(message); }

export function finish(prefix) {
  console.log(`${prefix}: ${passed} passed, ${failed} failed`);
  process.exit(failed ? 1 : 0);
}
