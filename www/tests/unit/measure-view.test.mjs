// The page's reading of the core's measures: words for the HUD, the answer to a lesson's
// question, Mohr circles and the readouts' arcs.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { accuracyNote, answerIndex, arcAngles, flankAngle, mohr, mohrWindow, questionValue, speedWords } from '../../js/measure-view.js';

test('the real-time factor in words', () => {
  assert.equal(speedWords(1.0, true, false), 'real time');
  assert.equal(speedWords(0.5, false, false), 'paused');
  assert.equal(speedWords(0.25, true, true), 'slow motion: 1 s takes 4.0 s');
  assert.match(speedWords(2, true, false), /faster/);
  // The words agree with the figure they are made of, for every ratio (a frame that fell
  // behind its budget near real time is not "slow motion: 1 s takes 0.98 s").
  for (let ratio = 0.05; ratio < 3; ratio *= 1.013) {
    const words = speedWords(ratio, true);
    const slow = /^slow motion: 1 s takes ([\d.]+) s$/.exec(words);
    const fast = /^faster than real time \(([\d.]+)×\)$/.exec(words);
    if (slow) {
      assert.ok(Number(slow[1]) > 1 && ratio < 1, `${ratio}: ${words}`);
      assert.ok(Math.abs(Number(slow[1]) * ratio - 1) < 0.05 * Number(slow[1]), `${ratio}: ${words}`);
    } else if (fast) assert.ok(Number(fast[1]) > 1 && Math.abs(Number(fast[1]) - ratio) <= 0.05, `${ratio}: ${words}`);
    else assert.ok(words === 'real time' && Math.abs(ratio - 1) <= 0.1, `${ratio}: ${words}`);
  }
  assert.match(accuracyNote('Live', { column_runout: -0.14, column_height: 0.021 }), /Live: column run-out −14 %, height \+2\.1 %/);
  // In 3D, the level's 3D sand figures, not the plane column's.
  assert.equal(accuracyNote('Live', { column_runout: -0.14, column_height: 0.021 }, { runout: -0.3637, farthest: -0.3841, flank: 23.9 }),
    'Live: 3D column run-out −36 % against experiments, flank 23.9°');
});

const deposit = (body, angles, runout, footprint = 0.1) => ({
  body,
  heap: { flanks: angles.map((a) => (a === null ? null : { angle: a })) },
  runout: { runout, footprint },
});

test('a question is answered by the measured value', () => {
  const q = {
    measure: { quantity: 'flank_angle', bodies: [1, 0] },
    choices: [{ range: [-90, -1] }, { range: [-1, 1] }, { range: [1, 10] }, { range: [10, 90] }],
  };
  const deposits = [deposit(0, [null, 12]), deposit(1, [27, null])];
  assert.equal(flankAngle(deposits[0]), 12);
  assert.equal(questionValue(q, deposits, 2), 15);
  assert.equal(answerIndex(q, 15), 3);
  assert.equal(answerIndex(q, 0.5), 1);
  assert.equal(answerIndex(q, 90), 3, 'the last range includes its end');
  assert.equal(answerIndex(q, 95), -1);
  assert.equal(questionValue(q, [deposits[0]], 2), null, 'a body not measured: no answer');
  const r = { measure: { quantity: 'runout_ratio', bodies: [0] }, choices: [] };
  assert.ok(Math.abs(questionValue(r, [deposit(0, [], [0.2, 0.3])], 2) - 3) < 1e-12, 'the farther side over L0');
});

test('Mohr circles: one in plane strain, three in 3D, with the envelopes', () => {
  const surface = { slope: 1.2, intercept: 0 };
  const mc = { friction_angle: 30, cohesion: 0, plane_strain_angle: 25 };
  const m2 = mohr({ principal: [300, 100, 200], p: 200, surface, mohr_coulomb: mc }, 2);
  assert.deepEqual(m2.circles, [{ centre: 200, radius: 100 }]);
  assert.deepEqual(m2.points, [200]);
  assert.equal(m2.cone.kind, 'line');
  assert.equal(m2.cone.angle, 25);
  const m3 = mohr({ principal: [300, 200, 100], p: 200, surface, mohr_coulomb: mc }, 3);
  assert.deepEqual(m3.circles.map((c) => [c.centre, c.radius]), [[200, 100], [250, 50], [150, 50]]);
  // the cone's circle in triaxial compression at p: q = 240, σ1 − σ3 = q
  assert.equal(m3.cone.radius, 120);
  assert.equal(m3.cone.centre, 240);
  assert.equal(mohr({ principal: [1, 0, 0], p: 0.3, surface }, 3).envelope, null, 'no envelope without sand');
  const w = mohrWindow(m3);
  assert.ok(w.sMin < 0 && w.sMax > 360 && w.tMax > 120);
  // Mohr–Coulomb: its own envelope at the true φ, and no cone
  const own = { friction_angle: 30, cohesion: 50 };
  for (const dim of [2, 3]) {
    const m = mohr({ principal: [300, 100, 200], p: 200, surface, mohr_coulomb: own }, dim);
    assert.deepEqual(m.envelope, { angle: 30, cohesion: 50, own: true });
    assert.equal(m.cone, null);
  }
  assert.equal(m2.envelope.own, false, 'Drucker–Prager: the envelope is not its yield surface');
});

test('a flank arc turns from the horizontal to the flank, the short way', () => {
  // foot at the left, top up-right on screen (y down): from −45° to 0
  const [a0, a1] = arcAngles([0, 0], [10, -10]);
  assert.ok(Math.abs(a0 + Math.PI / 4) < 1e-12 && Math.abs(a1) < 1e-12);
  // foot at the right, top up-left: between 180° and 225°, 45° wide
  const [b0, b1] = arcAngles([10, 0], [0, -10]);
  assert.ok(Math.abs(b1 - b0 - Math.PI / 4) < 1e-12, `${b0} ${b1}`);
});
