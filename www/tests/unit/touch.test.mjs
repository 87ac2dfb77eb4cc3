// The gestures on the view (www/js/touch.js), without a browser.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { Gestures, Hold } from '../../js/touch.js';

test('a press that does not move is a tap where it was released', () => {
  const g = new Gestures(6);
  g.down(1, 100, 100);
  assert.equal(g.move(1, 103, 102), null, 'within the slop: no orbit');
  assert.deepEqual(g.up(1, 103, 102), { tap: [103, 102] });
});

test('one pointer dragged orbits by its moves, and is no tap', () => {
  const g = new Gestures(6);
  g.down(1, 100, 100);
  assert.deepEqual(g.move(1, 110, 100), { orbit: [10, 0] }, 'the whole move once past the slop');
  assert.deepEqual(g.move(1, 112, 95), { orbit: [2, -5] });
  assert.ok(g.dragging);
  assert.equal(g.up(1, 112, 95), null);
  assert.ok(!g.dragging);
  // The next press starts afresh.
  g.down(2, 50, 50);
  assert.deepEqual(g.up(2, 50, 50), { tap: [50, 50] });
});

test('two pointers pinch: spreading zooms in (factor below 1) by the ratio of distances, no orbit, no tap', () => {
  const g = new Gestures(6);
  g.down(1, 100, 100);
  g.down(2, 200, 100);
  const a = g.move(2, 300, 100);
  assert.deepEqual(a, { zoom: 0.5 }, 'distance 100 → 200');
  assert.deepEqual(g.move(1, 200, 100), { zoom: 2 }, 'distance 200 → 100: out again');
  // The product of the factors is the ratio of the first distance to the last.
  const f = [g.move(1, 150, 100).zoom, g.move(2, 350, 100).zoom].reduce((x, y) => x * y, 1);
  assert.ok(Math.abs(f - 100 / 200) < 1e-12, String(f));
  assert.equal(g.up(1, 150, 100), null);
  // The finger left behind neither orbits at once by the jump nor taps when lifted.
  assert.equal(g.move(2, 350, 100), null);
  assert.deepEqual(g.move(2, 360, 100), { orbit: [10, 0] });
  assert.equal(g.up(2, 360, 100), null);
});

test('a cancelled pointer ends the gesture without a tap; unknown pointers are ignored', () => {
  const g = new Gestures(6);
  g.down(1, 10, 10);
  g.cancel(1);
  assert.equal(g.up(1, 10, 10), null);
  assert.equal(g.move(7, 1, 1), null);
  assert.equal(g.up(7, 1, 1), null);
});

test('a press held (the Pour tool) starts where it went down and stops on release, cancel or leaving the view', () => {
  const h = new Hold();
  assert.deepEqual(h.down(1, 40, 50), { start: [40, 50] });
  assert.ok(h.held);
  assert.equal(h.move(1, true), null, 'moving inside the view: still pouring, never an orbit');
  assert.equal(h.down(2, 90, 90), null, 'a second finger starts nothing');
  assert.equal(h.up(2), null, 'nor does its release stop the pour');
  assert.deepEqual(h.up(1), { stop: true });
  assert.ok(!h.held);
  assert.equal(h.up(1), null, 'stopped once');
  h.down(3, 0, 0);
  assert.deepEqual(h.move(3, false), { stop: true }, 'leaving the view stops it');
  assert.equal(h.cancel(3), null);
  h.down(4, 0, 0);
  assert.deepEqual(h.cancel(4), { stop: true });
  assert.equal(h.down(5, 1, 1, false), null, 'a pointer that is not primary starts nothing');
  assert.equal(h.cancel(null), null, 'nothing held: nothing to stop');
});
