// peaks.js - words for the analysis's dominant offsets and candidate repeats; no DOM, no three.js.
//
//   candidateLabel(candidate, units, longest) -> '(2.54, 0, 0) mm, 2.54 long, 2 copies, pair'
//   peakExplanation(analysis, i, units) -> {title, tests: [[name, 'value op threshold', 'passed' | 'FAILED']],
//                                          notes: [...], candidate}   why dominant offset i is (not) principal
//   withOffset(promoted, offset) -> the offsets to promote when `offset` is clicked
//   lengthFormat(x, longest)      a model-unit length, three decimals below the model's leading digit
// `analysis` has the fields of `restitch analyze --json` (model units): dominant_offsets[i].tests
// [{name, value, threshold, at_most, passed}], rejected_by, divisor, promoted, significant; candidates
// [{offset, copies, reason, dominant}]. `longest` is the model's longest side (for the number of decimals).

export const fmt = (x, d = 3) => (Number.isFinite(x) ? Number(x.toPrecision(d)).toString() : '–');
const norm = (v) => Math.hypot(v[0], v[1], v[2]);

export function lengthFormat(x, longest) {
  const decimals = Math.min(8, Math.max(0, 3 - Math.floor(Math.log10(longest))));
  const s = x.toFixed(decimals);
  return /^-0\.?0*$/.test(s) ? s.slice(1) : s;
}

const vecFormat = (v, longest) => `(${v.map((x) => lengthFormat(x, longest)).join(', ')})`;

export function candidateLabel(c, units, longest) {
  return `${vecFormat(c.offset, longest)} ${units}, ${lengthFormat(norm(c.offset), longest)} long, ` +
         `${c.copies} copies, ${c.reason}`;
}

export function peakExplanation(analysis, i, units, longest) {
  const d = analysis.dominant_offsets[i];
  const candidate = (analysis.candidates || []).findIndex((c) => c.dominant === i);
  const title = `dominant offset ${i + 1}: ${vecFormat(d.offset, longest)} ${units}, ${d.votes} votes`;
  const tests = (d.tests || []).map((t) =>
    [t.name, `${fmt(t.value, 4)} ${t.at_most ? '≤' : '≥'} ${fmt(t.threshold, 4)}`, t.passed ? 'passed' : 'FAILED']);
  const notes = [];
  const vertices = candidate >= 0 && analysis.candidates[candidate].reason === 'vertices';
  notes.push(vertices ? 'a repeat of the vertices along an axis the matching found nothing on (no votes)' +
      (d.rejected_by ? `, no pattern on the surface (${d.rejected_by})` : '')
    : d.rejected_by ? `rejected by ${d.rejected_by}`
    : d.significant ? 'significant: passed every test'
    : 'a repeat of the vertices along an axis the matching found nothing on (no votes)');
  if (d.divisor > 1) notes.push(`divisor ${d.divisor}: the peak spans ${d.divisor} periods, this is one`);
  else notes.push('divisor 1');
  notes.push(d.promoted ? 'promoted: made principal on request' : 'not promoted');
  if (candidate >= 0) {
    const c = analysis.candidates[candidate];
    notes.push(`candidate ${candidate + 1} (${c.reason}, ${c.copies} copies): click to resize along it`);
  }
  return { title, tests, notes, candidate };
}

// The offsets promoted so far, less those within 60 degrees of `offset` (the library refuses closer ones: the
// click switches between them), then `offset`; the last three.
export function withOffset(promoted, offset) {
  const cos = (a, b) => Math.abs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (norm(a) * norm(b) || 1);
  return [...promoted.filter((v) => cos(v, offset) < 0.5), offset].slice(-3);
}
