// What the measuring overlay (www/js/overlay.js) writes against each deposit, on a stand-in
// canvas without a browser: the law line's name against a heap poured or released by lifted
// walls, the collapse note against any other, every label whole on the view and clear of the
// others.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { Overlay, COLLAPSE_NOTE } from '../../js/overlay.js';
import { atRepose } from '../../js/measure-view.js';

globalThis.window ??= { devicePixelRatio: 1 };

/// A canvas of `w`×`h` CSS pixels whose context draws nothing and measures text at 7 px a
/// character (near the page's 600 13px system-ui).
function canvas(w, h) {
  const ctx = new Proxy({ measureText: (t) => ({ width: 7 * t.length }) }, {
    get: (o, k) => (k in o ? o[k] : () => {}),
  });
  return { clientWidth: w, clientHeight: h, width: w, height: h, getContext: () => ctx };
}

/// A side view of the 2 m wide sandbox filling `w` pixels (3D: seen from the front).
const camera = (w, h) => {
  const scale = (w - 40) / 2;
  return { project: (x, y) => [20 + x * scale, h - 20 - y * scale], yaw: 0 };
};

/// A sand deposit with two flanks rising `rise` m over `run` m each side of `x`, made as the
/// core says it was (`poured`, `held`, `heaped`).
const heap = ({ x = 1.0, run = 0.15, rise = 0.09, poured = false, held = false, heaped = false, model = 'drucker_prager' } = {}) => ({
  body: 0,
  name: 'sand',
  spacing: 0.005,
  axis: [0, 0],
  heap: {
    height: rise,
    flanks: [
      { angle: 31.0, from: [x - run - 0.02, 0.005], to: [x - 0.02, rise] },
      { angle: 32.0, from: [x + run + 0.02, 0.005], to: [x + 0.02, rise] },
    ],
  },
  runout: null,
  poured,
  held,
  heaped,
  model,
  friction_angle: 35,
  repose_angle: 33.0,
  column: null,
});

const drawn = (measures, { w = 1200, h = 500, dim = 2, laws = true } = {}) => {
  const o = new Overlay(canvas(w, h));
  o.draw({ camera: camera(w, h), dim, measures, show: { readouts: true, laws } });
  return o.labels;
};

/// The labels that overlap one another or leave the `w`×`h` view.
function clashes(labels, w, h) {
  const out = [];
  labels.forEach((l, i) => {
    const b = l.box;
    if (b.x < 0 || b.y < 0 || b.x + b.w > w || b.y + b.h > h) out.push(`“${l.text}” cut off`);
    for (const o of labels.slice(0, i)) {
      const c = o.box;
      if (b.x < c.x + c.w && c.x < b.x + b.w && b.y < c.y + c.h && c.y < b.y + b.h) out.push(`“${l.text}” over “${o.text}”`);
    }
  });
  return out;
}

const kinds = (labels, kind) => labels.filter((l) => l.kind === kind).map((l) => l.text);

test('a heap stands at its angle of repose when it was poured or released by lifted walls, or under it when built at rest; any other deposit collapsed', () => {
  assert.equal(atRepose(heap({ poured: true })), true);
  assert.equal(atRepose(heap({ held: true })), true);
  assert.equal(atRepose(heap({ heaped: true })), true);
  assert.equal(atRepose(heap()), false);
  assert.equal(atRepose({ heap: { flanks: [] } }), false, 'a deposit that does not say: a collapse');
});

test('2D: a poured heap gets the law line named, no note; a collapse the note, no law line', () => {
  const poured = drawn([heap({ poured: true })]);
  assert.deepEqual(kinds(poured, 'angle'), ['31.0°', '32.0°']);
  assert.deepEqual(kinds(poured, 'law'), ['angle of repose 33.0°, Drucker–Prager']);
  assert.deepEqual(kinds(poured, 'note'), []);
  const mc = drawn([heap({ held: true, model: 'mohr_coulomb' })]);
  assert.deepEqual(kinds(mc, 'law'), ['angle of repose 33.0°, Mohr–Coulomb (Davis)'], 'released by lifted walls: the line too');
  assert.deepEqual(kinds(drawn([heap({ heaped: true })]), 'law'), ['angle of repose 33.0°, Drucker–Prager'], 'built at rest: the line too');
  // the line's name on the side of its flank away from the heap's axis, clear of the top
  const [law] = poured.filter((l) => l.kind === 'law');
  const axis = camera(1200, 500).project(1.0, 0)[0];
  assert.ok(law.box.x + law.box.w <= axis - 0.02 * 580, JSON.stringify(law));
  const dropped = drawn([heap({ run: 0.5 })]);
  assert.deepEqual(kinds(dropped, 'angle'), ['31.0°', '32.0°'], 'its flanks are still read');
  assert.deepEqual(kinds(dropped, 'law'), []);
  assert.deepEqual(kinds(dropped, 'note'), [COLLAPSE_NOTE[0]]);
  assert.match(COLLAPSE_NOTE[0], /collapse.*momentum.*below the angle of repose.*pour/);
  // above the heap's top, centred on it
  const [note] = dropped.filter((l) => l.kind === 'note');
  const top = camera(1200, 500).project(1.0, 0.09);
  assert.ok(note.y < top[1] && Math.abs(note.box.x + note.box.w / 2 - top[0]) < 2, JSON.stringify(note));
  assert.deepEqual(clashes(dropped, 1200, 500), []);
});

test('3D: the line on the radial profile of a poured cone; no note over a collapse, whose axis may carry a body', () => {
  assert.deepEqual(kinds(drawn([heap({ poured: true })], { dim: 3 }), 'law'), ['angle of repose 33.0°, Drucker–Prager']);
  assert.deepEqual(kinds(drawn([heap({ poured: true })], { dim: 3 }), 'note'), []);
  assert.deepEqual(kinds(drawn([heap()], { dim: 3 }), 'law'), []);
  assert.deepEqual(kinds(drawn([heap({ run: 0.5 })], { dim: 3 }), 'note'), []);
});

test('no note or line with the readouts\' laws off, or on a deposit with no flank fitted', () => {
  assert.deepEqual(drawn([heap()], { laws: false }).filter((l) => l.kind !== 'angle'), []);
  const flat = heap();
  flat.heap.flanks = [null, null];
  assert.deepEqual(drawn([flat]), []);
});

test('the note is whole on a phone\'s view and clear of the flank angles, however low or narrow the heap', () => {
  for (const w of [360, 760, 1200]) {
    const shown = kinds(drawn([heap()], { w }), 'note');
    assert.equal(shown.length, 1, `${w} px`);
    assert.ok(7 * shown[0].length + 8 <= w, `${w} px: “${shown[0]}” fits`);
  }
  // the whole note over a heap as wide; over a narrow one, or on a phone, a shorter one
  assert.equal(kinds(drawn([heap({ run: 0.5 })], { w: 1200 }), 'note')[0], COLLAPSE_NOTE[0]);
  assert.equal(kinds(drawn([heap({ run: 0.5 })], { w: 360 }), 'note')[0], COLLAPSE_NOTE[2]);
  for (const note of COLLAPSE_NOTE) assert.match(note, /^a collapse.*pour to measure/, 'every form names the act that measures it');
  const narrow = kinds(drawn([heap({ run: 0.1 })], { w: 1200 }), 'note')[0];
  assert.equal(narrow, COLLAPSE_NOTE[1], 'the pour still named over a narrow heap');
  // A flat deposit puts the note's first place on its angles: it moves clear of them.
  const flat = drawn([heap({ rise: 0.006 })]);
  const [note] = flat.filter((l) => l.kind === 'note');
  const top = camera(1200, 500).project(1.0, 0.006);
  assert.ok(note.y < top[1] - 24 - 8, `moved up: ${JSON.stringify(note)}`);
  // a heap alone anywhere, and beside a poured one
  for (const w of [360, 760, 1200]) {
    for (const run of [0.01, 0.05, 0.3]) {
      for (const rise of [0.001, 0.01, 0.05, 0.2]) {
        for (const x of [0.1, 0.5, 1.0, 1.9]) {
          assert.deepEqual(clashes(drawn([heap({ x, run, rise })], { w }), w, 500), [], `${w} px, x ${x}, run ${run}, rise ${rise}`);
        }
        const two = [heap({ x: 0.5, run, rise }), { ...heap({ x: 1.5, run, rise, poured: true }), body: 1 }];
        assert.deepEqual(clashes(drawn(two, { w }), w, 500), [], `${w} px, two heaps, run ${run}, rise ${rise}`);
      }
    }
  }
});
