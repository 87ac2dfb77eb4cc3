// The plots' scales (www/js/plot-scale.js), without a browser.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { energyWindow, pqWindow, surfaceLine, ticks } from '../../js/plot-scale.js';

test('ticks are round numbers covering the range', () => {
  assert.deepEqual(ticks(0, 1), [0, 0.5, 1]);
  assert.deepEqual(ticks(0, 10), [0, 5, 10]);
  assert.deepEqual(ticks(-3, 7), [0, 5]);
  assert.deepEqual(ticks(-3, 5), [-2, 0, 2, 4]);
  // an empty plot's range of round-off width: no tick like 1e-15
  assert.deepEqual(ticks(-1e-15, 1e-15), [0]);
  assert.deepEqual(ticks(0, 4e-16), [0]);
  assert.deepEqual(ticks(0.1, 0.3), [0.1, 0.15, 0.2, 0.25, 0.3]);
  assert.deepEqual(ticks(5, 5), [5]);
  for (const [lo, hi] of [[0, 1], [-1e5, 3e5], [0.001, 0.0042]]) {
    const t = ticks(lo, hi);
    assert.ok(t.length >= 2 && t.length <= 8, `${lo}..${hi}: ${t}`);
    assert.ok(t[0] >= lo && t.at(-1) <= hi * (1 + 1e-9), `${lo}..${hi}: ${t}`);
  }
});

test('the energy window holds every series and zero', () => {
  const s = [{ time: 0, a: 2, b: -1 }, { time: 0.5, a: 5, b: 0 }];
  const { xr, yr } = energyWindow(s, ['a', 'b']);
  assert.deepEqual(xr, [0, 0.5]);
  assert.ok(Math.abs(yr[0] - -1.3) < 1e-12 && Math.abs(yr[1] - 5.3) < 1e-12, String(yr));
});

const cone = { kind: 'drucker_prager', slope: 1.2, intercept: 0, apex_p: 0, label: 'Drucker–Prager cone' };
const cohesive = { ...cone, intercept: 600, apex_p: -500 };
const cylinder = { kind: 'von_mises', slope: 0, intercept: 5000, apex_p: -1e300, label: 'von Mises: q = σ_y' };
const none = { kind: 'none', slope: 0, intercept: 0, apex_p: -1e300, label: 'elastic: no yield surface' };

test('the p–q window is in kPa for kilopascal stresses and holds the surface', () => {
  const w = pqWindow([[2000, 1000], [4000, 4500]], cone);
  assert.equal(w.unit, 'kPa');
  assert.equal(w.k, 1e-3);
  assert.ok(Math.abs(w.pMax - 4.6) < 1e-12 && w.pMin === 0);
  assert.ok(Math.abs(w.qMax - 1.15 * 1.2 * 4) < 1e-12, 'the cone at the largest p');
  const line = surfaceLine(cone, w);
  assert.deepEqual(line[0], [0, 0]);
  assert.ok(Math.abs(line[1][1] - 1.2 * w.pMax) < 1e-12);
  // von Mises: q = σ_y at every pressure, drawn across the window.
  const v = pqWindow([[100, 200]], cylinder);
  assert.ok(Math.abs(v.qMax - 5.75) < 1e-12);
  assert.deepEqual(surfaceLine(cylinder, v).map(([, q]) => q), [5, 5]);
  assert.equal(surfaceLine(none, pqWindow([[1, 1]], none)), null);
});

test('small stresses stay in pascals; a cohesive cone shows its apex in tension', () => {
  const w = pqWindow([[50, 20]], { ...cone, intercept: 0 });
  assert.equal(w.unit, 'Pa');
  assert.ok(Math.abs(w.pMax - 57.5) < 1e-9 && Math.abs(w.qMax - 69) < 1e-9, JSON.stringify(w));
  const c = pqWindow([[3000, 2000]], cohesive);
  assert.ok(c.pMin < -0.5 && Math.abs(c.pMin - 1.15 * -0.5) < 1e-12, `${c.pMin}`);
  assert.deepEqual(surfaceLine(cohesive, c)[0].map((x) => +x.toFixed(9)), [-0.5, 0]);
});

test('a pyramid draws its compression meridian and, inside it, its extension meridian from the apex', () => {
  const pyramid = { kind: 'mohr_coulomb', slope: 1.2, intercept: 600, apex_p: -500, lower: [0.9, 450], label: 'Mohr–Coulomb' };
  const w = pqWindow([[3000, 2000]], pyramid);
  assert.ok(Math.abs(w.pMin - 1.15 * -0.5) < 1e-12, `${w.pMin}`);
  const outer = surfaceLine(pyramid, w);
  const inner = surfaceLine(pyramid, w, true);
  assert.deepEqual(inner[0].map((x) => +x.toFixed(9)), [-0.5, 0]);
  assert.ok(inner[1][1] < outer[1][1]);
  assert.equal(surfaceLine(cohesive, w, true), null);
});
