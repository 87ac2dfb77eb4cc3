// Slider scaling and formatting (www/js/params.js), without a browser.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { boundedMax, format, formatTime, fromSlider, paramTable, ticks, toSlider } from '../../js/params.js';

// The shape of the solver's `parameterTable()` (src/params.rs).
const TABLE = {
  params: [
    { name: 'gravity', field: 'gravity', label: 'Gravity', unit: 'm/s²', min: 0, max: 30, step: 0.01, scale: 'linear', default: 9.81 },
    { name: 'drucker_prager.friction_angle', model: 'drucker_prager', field: 'friction_angle', unit: '°', min: 0, max: 60, step: 0.5, scale: 'linear', default: 35 },
    { name: 'drucker_prager.dilatancy_angle', model: 'drucker_prager', field: 'dilatancy_angle', unit: '°', min: 0, max: 60, step: 0.5, scale: 'linear', default: 0, at_most: 'friction_angle' },
    { name: 'drucker_prager.youngs_modulus', model: 'drucker_prager', field: 'youngs_modulus', unit: 'Pa', min: 1e3, max: 1e8, step: 0, scale: 'log', default: 3.5e5 },
  ],
  models: [{ id: 'drucker_prager', label: 'Sand', hint: 'granular' }],
  objects: [{ id: 'ball', label: 'Ball' }],
};

test('the table is looked up by name, by model and for the world', () => {
  const t = paramTable(JSON.stringify(TABLE));
  assert.deepEqual(t.world.map((p) => p.name), ['gravity']);
  assert.deepEqual(t.ofModel('drucker_prager').map((p) => p.field), ['friction_angle', 'dilatancy_angle', 'youngs_modulus']);
  assert.equal(t.spec('drucker_prager.friction_angle').default, 35);
  assert.equal(t.spec('nothing'), undefined);
  const psi = t.spec('drucker_prager.dilatancy_angle');
  assert.equal(boundedMax(psi, { 'drucker_prager.friction_angle': 25 }), 25);
  assert.equal(boundedMax(psi, { 'drucker_prager.friction_angle': 0 }), 0.5, 'a slider keeps some travel');
  assert.equal(boundedMax(t.spec('gravity'), {}), 30);
});

test('a linear slider moves one step per tick, both ways', () => {
  const phi = TABLE.params[1];
  assert.equal(ticks(phi), 120);
  for (const v of [0, 0.5, 17.5, 35, 60]) assert.equal(fromSlider(phi, toSlider(phi, v)), v);
  assert.equal(fromSlider(phi, 71), 35.5);
  assert.equal(fromSlider(phi, -3), 0, 'clamped');
  assert.equal(fromSlider(TABLE.params[0], 981), 9.81, 'no binary noise');
});

test('a log slider spans its decades in 200 ticks of three significant figures', () => {
  const e = TABLE.params[3];
  assert.equal(ticks(e), 200);
  assert.equal(fromSlider(e, 0), 1e3);
  assert.equal(fromSlider(e, 200), 1e8);
  assert.equal(fromSlider(e, 80), 1e5, 'two of five decades');
  let previous = 0;
  for (let i = 0; i <= 200; i++) {
    const v = fromSlider(e, i);
    assert.ok(v > previous, `tick ${i} changes the value`);
    assert.equal(v, +v.toPrecision(3));
    previous = v;
  }
  assert.ok(Math.abs(toSlider(e, 3.5e5) - 200 * Math.log10(350) / 5) < 1e-9);
});

test('values carry SI prefixes in pascals, durations their unit', () => {
  assert.equal(format(3.5e5, 'Pa'), '350 kPa');
  assert.equal(format(-2.5e9, 'Pa'), '-2.5 GPa');
  assert.equal(format(12.345, '°'), '12.3 °');
  assert.equal(format(1234.5), '1235');
  assert.equal(format(NaN, 'Pa'), 'NaN');
  assert.equal(formatTime(2), '2.00 s');
  assert.equal(formatTime(6.4e-4), '640 µs');
  assert.equal(formatTime(0.0123), '12.3 ms');
  assert.equal(formatTime(Infinity), '–');
});
