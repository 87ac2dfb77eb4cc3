// The rendering quality governor (www/js/quality.js) and the particle picker
// (www/js/pointer.js), without a browser.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { LEVELS, QualityGovernor, applyQuality } from '../../js/quality.js';
import { insideBox, nearestParticle } from '../../js/pointer.js';

test('slow frames lower the quality level by level, quick ones raise it after a while', () => {
  const g = new QualityGovernor(1000 / 30);
  let now = 0;
  const run = (otherMs, frames) => {
    const changes = [];
    for (let i = 0; i < frames; i++) {
      now += 33;
      const level = g.record(otherMs, now);
      if (level !== null) changes.push(level);
    }
    return changes;
  };
  assert.deepEqual(run(5, 100), [], 'quick frames at full quality: no change');
  assert.deepEqual(run(40, 400), [1, 2, 3, 4], 'each change waits for new samples and the hold time');
  assert.deepEqual(run(40, 100), [], 'nothing below the lowest level');
  const up = run(3, 400);
  assert.ok(up.length >= 1 && up[0] === 3, `raised again: ${up}`);
  assert.ok(now >= 6000);
  g.fixed = true;
  assert.deepEqual(run(40, 200), [], 'a fixed level stays');
  const renderer = { shadows: true, scale: 1 };
  assert.equal(applyQuality(renderer, LEVELS.length - 1), '½ resolution');
  assert.deepEqual(renderer, { shadows: false, scale: 0.5 }, 'only what the renderer has');
});

test('a click picks the nearest particle within reach, the nearest the eye among close ones', () => {
  // Three particles in 3D (stride 4), projected by dropping z as depth.
  const positions = new Float32Array([10, 10, 5, 0, 12, 10, 1, 0, 100, 100, 0, 0]);
  const project = (x, y, z) => [x, y, z];
  const view = { positions, stride: 4, count: 3 };
  assert.equal(nearestParticle(view, 3, project, 11, 10), 1, 'nearer the eye');
  assert.equal(nearestParticle(view, 3, project, 99, 101), 2);
  assert.equal(nearestParticle(view, 3, project, 50, 50), -1, 'out of reach');
  assert.ok(insideBox([0.5, 0, 0.5], [1, 1, 1]) && !insideBox([0.5, 0, 1.5], [1, 1, 1]) && !insideBox(null, [1, 1]));
  assert.ok(insideBox([0.5, 0.9], [2, 1]) && !insideBox([0.5, 1.1], [2, 1]));
});
