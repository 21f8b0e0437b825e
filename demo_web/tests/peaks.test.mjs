// Node tests of the words the page shows for dominant offsets and candidates (src/peaks.js): the hover
// explanation of a peak, the candidate labels, and which offsets a click promotes. No DOM, no WebAssembly.
// Run: node --test demo_web/tests/peaks.test.mjs (tests/run.sh runs it with the other node tests).
import test from 'node:test';
import assert from 'node:assert/strict';
import { candidateLabel, peakExplanation, withOffset } from '../src/peaks.js';

const test_ = (name, value, threshold, at_most = false) =>
  ({ name, value, threshold, at_most, passed: at_most ? value <= threshold : value >= threshold });
const analysis = {
  dominant_offsets: [
    { offset: [2.54, 0, 0], votes: 197, divisor: 1, promoted: false, significant: false, rejected_by: 'repeat',
      tests: [test_('votes', 197, 5), test_('double_drift', 0.0027, 0.25, true), test_('repeat', 0.1204, 0.25)] },
    { offset: [0, 0.8, 0], votes: 40, divisor: 2, promoted: true, significant: true, rejected_by: null,
      tests: [test_('votes', 40, 5)] },
  ],
  candidates: [{ offset: [2.54, 0, 0], copies: 2, reason: 'pair', dominant: 0 }],
};

test('a peak explains each test, the rejecting one, the divisor, the promotion and its candidate', () => {
  const e = peakExplanation(analysis, 0, 'mm', 11.5);
  assert.equal(e.title, 'dominant offset 1: (2.54, 0.00, 0.00) mm, 197 votes');
  assert.deepEqual(e.tests, [['votes', '197 ≥ 5', 'passed'], ['double_drift', '0.0027 ≤ 0.25', 'passed'],
                             ['repeat', '0.1204 ≥ 0.25', 'FAILED']]);
  assert.deepEqual(e.notes, ['rejected by repeat', 'divisor 1', 'not promoted',
                             'candidate 1 (pair, 2 copies): click to resize along it']);
  assert.equal(e.candidate, 0);
  const f = peakExplanation(analysis, 1, 'mm', 11.5);
  assert.equal(f.candidate, -1);
  assert.deepEqual(f.notes, ['significant: passed every test', 'divisor 2: the peak spans 2 periods, this is one',
                             'promoted: made principal on request']);
});

test('a repeat of the vertices (no votes, no test failed, not significant) says so', () => {
  const withVertices = {
    dominant_offsets: [{ offset: [0.15, 0, 0], votes: 0, divisor: 1, promoted: false, significant: false,
                         rejected_by: null, tests: [test_('vertex_lag', 174, 8), test_('vertex_copies', 2, 2)] }],
    candidates: [{ offset: [0.15, 0, 0], copies: 2, reason: 'vertices', dominant: 0 }],
  };
  const e = peakExplanation(withVertices, 0, 'm', 0.5);
  assert.deepEqual(e.notes, ['a repeat of the vertices along an axis the matching found nothing on (no votes)',
                             'divisor 1', 'not promoted', 'candidate 1 (vertices, 2 copies): click to resize along it']);
});

test('a repeat of the vertices that is no pattern on the surface names the pattern test it failed', () => {
  const twoRows = {
    dominant_offsets: [{ offset: [0, 0, 2.54], votes: 0, divisor: 1, promoted: false, significant: false,
                         rejected_by: 'pattern_double_drift',
                         tests: [test_('vertex_lag', 1664, 8), test_('vertex_structure', 1, 0.5)] }],
    candidates: [{ offset: [0, 0, 2.54], copies: 2, reason: 'vertices', dominant: 0 }],
  };
  const e = peakExplanation(twoRows, 0, 'mm', 60);
  assert.equal(e.notes[0], 'a repeat of the vertices along an axis the matching found nothing on (no votes), ' +
                           'no pattern on the surface (pattern_double_drift)');
});

test('a candidate reads offset, length, copies and reason', () => {
  assert.equal(candidateLabel(analysis.candidates[0], 'mm', 11.5), '(2.54, 0.00, 0.00) mm, 2.54 long, 2 copies, pair');
});

test('a click adds its offset to the promoted ones, replacing those within 60 degrees', () => {
  assert.deepEqual(withOffset([], [1, 0, 0]), [[1, 0, 0]]);
  assert.deepEqual(withOffset([[1, 0, 0]], [0, 1, 0]), [[1, 0, 0], [0, 1, 0]]);
  assert.deepEqual(withOffset([[1, 0, 0], [0, 1, 0]], [-2, 0.1, 0]), [[0, 1, 0], [-2, 0.1, 0]], 'parallel: switched');
  assert.deepEqual(withOffset([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [1, 1, 1]).length, 1, 'all within 60 degrees');
  assert.deepEqual(withOffset([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [1, -1, 1]), [[1, -1, 1]]);
});
