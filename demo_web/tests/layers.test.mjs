// Node tests of the page's seam drawing (src/layers.js): seam faces lie where the seams' planes lie.
// Run: node --test demo_web/tests/layers.test.mjs (tests/run.sh runs it with the other node tests).
import test from 'node:test';
import assert from 'node:assert/strict';
import { seamFaces } from '../src/layers.js';

// Three output cells along x (unit cube cells), labels 0 | 1 | 1: one seam, between cells 0 and 1.
function result(planeOffsets) {
  return {
    report: { cells_out: [3, 1, 1], seams: [], seam_tolerance: 1, plane_offsets: planeOffsets },
    cell_labels: [0, 1, 1],
    grid: { axes: [[1, 0, 0], [0, 1, 0], [0, 0, 1]], origin: [0, 0, 0] },
  };
}

const xs = (quads) => [...new Set(quads.filter((_, i) => i % 3 === 0))];

test('a seam on its cell plane is drawn there', () => {
  const { quads, badQuads } = seamFaces(result([[], [], []]));
  assert.deepEqual(xs(quads), [1]);
  assert.equal(badQuads.length, 0);
  assert.deepEqual(xs(seamFaces(result(undefined)).quads), [1], 'a report without plane_offsets');
});

test('a seam moved off its cell plane (report.plane_offsets, docs/method.md 2.9) is drawn where it lies', () => {
  const { quads, lines } = seamFaces(result([[0, 0.3125, 0, 0], [], []]));
  assert.deepEqual(xs(quads), [1.3125]);
  assert.deepEqual(xs(lines), [1.3125]);
});
