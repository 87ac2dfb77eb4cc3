// The link's format (www/js/hash.js), without a browser: `node --test www/tests/unit/`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { formatDrop, formatHash, formatPour, parseDrop, parsePour, readHash } from '../../js/hash.js';

const NAMES = ['gravity', 'cfl', 'drucker_prager.friction_angle', 'elastic.youngs_modulus'];

test('a hash written is read back: view, quality, parameters in order, Clear and drops', () => {
  const view = { scene: 'sandbox', dim: '2', colour: 'speed', size: 0.25 };
  const session = {
    quality: 'balanced',
    params: [['drucker_prager.friction_angle', 25], ['gravity', 9.81], ['elastic.youngs_modulus', 123456789]],
    cleared: true,
    drops: [
      { t: 0.0412, object: 'ball', material: 'elastic', size: 0.25, centre: [0.8, 0.55, 0.5], velocity: [0, 0, 0], applied_at: 0.04123 },
      { t: 1.5, object: 'box', material: 'von_mises', size: 0.1, centre: [1.2, 0.4], velocity: [0, -2.5] },
    ],
  };
  const hash = formatHash(view, session);
  assert.equal(hash, '#scene=sandbox&dim=2&colour=speed&size=0.25&quality=balanced&drucker_prager.friction_angle=25&gravity=9.81' +
    '&elastic.youngs_modulus=123457000&cleared=1&drop=0.0412:ball:elastic:0.25:0.8,0.55,0.5&drop=1.5:box:von_mises:0.1:1.2,0.4:0,-2.5');
  const back = readHash(hash, NAMES);
  assert.deepEqual(back.errors, []);
  assert.deepEqual(back.view, { scene: 'sandbox', dim: '2', colour: 'speed', size: '0.25' });
  assert.deepEqual(back.session.params, [['drucker_prager.friction_angle', 25], ['gravity', 9.81], ['elastic.youngs_modulus', 123457000]]);
  assert.equal(back.session.cleared, true);
  assert.equal(back.session.quality, 'balanced');
  assert.equal('quality' in readHash('#scene=sandbox', NAMES).session, false, 'no quality named: the page keeps its own');
  const { applied_at, ...first } = session.drops[0];
  assert.ok(applied_at > 0);
  assert.deepEqual(back.session.drops, [first, session.drops[1]]);
});

test('malformed and unknown entries are named, never thrown', () => {
  const { session, errors } = readHash('#gravity=abc&warp=9&cfl=0.3&drop=ball:oops&drop=0:ball:elastic:0.2:0.5,x&drop=-1:ball:elastic:0.2:0.5,0.5', NAMES);
  assert.deepEqual(session.params, [['cfl', 0.3]]);
  assert.deepEqual(session.drops, []);
  assert.equal(errors.length, 5);
  assert.match(errors[0], /^gravity=abc: not a number/);
  assert.match(errors[1], /^warp=9: not a setting/);
  assert.match(errors[2], /^drop=ball:oops: 2 fields, expected TIME:OBJECT/);
  assert.match(errors[3], /centre “x” is not a number/);
  assert.match(errors[4], /time -1 is negative/);
});

test('a drop entry: the velocity is left out when zero, numbers in their shortest form', () => {
  const d = parseDrop('0.5:bunny:drucker_prager:0.3:1,0.5,0.25');
  assert.deepEqual(d, { t: 0.5, object: 'bunny', material: 'drucker_prager', size: 0.3, centre: [1, 0.5, 0.25], velocity: [0, 0, 0] });
  assert.equal(formatDrop(d), '0.5:bunny:drucker_prager:0.3:1,0.5,0.25');
  assert.equal(formatDrop({ ...d, velocity: [0, -1e-7, 0] }), '0.5:bunny:drucker_prager:0.3:1,0.5,0.25:0,-1e-7,0');
  assert.throws(() => parseDrop('0:ball:elastic:0.2:0.5,0.5:1,2,3'), /the centre has 2 components, the velocity 3/);
});

test('a lesson link: the lesson, and parameters of one body of its scene', () => {
  const hash = formatHash({ lesson: 'friction_angle', colour: 'body' },
    { params: [['bodies[1].drucker_prager.friction_angle', 30]], drops: [] });
  assert.equal(hash, '#lesson=friction_angle&colour=body&bodies%5B1%5D.drucker_prager.friction_angle=30');
  const back = readHash(hash, NAMES);
  assert.deepEqual(back.errors, []);
  assert.deepEqual(back.view, { lesson: 'friction_angle', colour: 'body' });
  assert.deepEqual(back.session.params, [['bodies[1].drucker_prager.friction_angle', 30]]);
  // Only material parameters belong to a body, and only known ones.
  const bad = readHash('#bodies[0].gravity=3&bodies[0].drucker_prager.colour=2&bodies[x].elastic.youngs_modulus=1', NAMES);
  assert.equal(bad.session.params.length, 0);
  assert.equal(bad.errors.length, 3, bad.errors.join('; '));
});

test('sleeping in the link: sleep=0 when off, nothing when on (the default), anything else refused', () => {
  assert.equal(formatHash({ scene: 'sandbox', sleep: '0' }, {}), '#scene=sandbox&sleep=0');
  assert.equal(formatHash({ scene: 'sandbox' }, {}), '#scene=sandbox');
  assert.deepEqual(readHash('#scene=sandbox&sleep=0', NAMES).view, { scene: 'sandbox', sleep: '0' });
  assert.deepEqual(readHash('#scene=sandbox&sleep=1', NAMES).view, { scene: 'sandbox', sleep: '1' });
  const bad = readHash('#scene=sandbox&sleep=off', NAMES);
  assert.deepEqual(bad.view, { scene: 'sandbox' });
  assert.match(bad.errors[0], /^sleep=off: 0 \(material at rest is stepped\) or 1/);
});

test('view entries outside the page\'s menus are named with what is allowed, the rest of the link kept', () => {
  const choices = { object: ['bunny', 'ball', 'box'], material: ['elastic', 'von_mises', 'drucker_prager'], quality: ['live', 'balanced', 'fine'] };
  const { view, session, errors } = readHash('#scene=column_collapse&dim=7&colour=rainbow&time=5&size=-1&object=cat&material=elastic&quality=ultra&gravity=5', NAMES, choices);
  assert.deepEqual(view, { scene: 'column_collapse', material: 'elastic' });
  assert.deepEqual(session.params, [['gravity', 5]]);
  assert.equal('quality' in session, false, 'an unknown level: the page keeps its own');
  assert.deepEqual(errors.map((e) => e.split(':')[0]), ['dim=7', 'colour=rainbow', 'time=5', 'size=-1', 'object=cat', 'quality=ultra']);
  assert.match(errors[0], /not one of 2, 3/);
  assert.match(errors[5], /not one of live, balanced, fine/);
  assert.deepEqual(readHash('#quality=balanced', NAMES, choices).session.quality, 'balanced');
  // Numbers beyond a double's range are not numbers (the solver would get null).
  const huge = readHash('#gravity=1e999&size=1e999&drop=0:ball:elastic:0.2:1e999,0.5', NAMES, choices);
  assert.deepEqual([huge.session.params, huge.session.drops, huge.view], [[], [], {}]);
  assert.equal(huge.errors.length, 3);
});

test('pours in the link: time, material, rate, duration and spout, read back as written, after the drops', () => {
  const session = {
    params: [],
    drops: [{ t: 0.5, object: 'ball', material: 'elastic', size: 0.25, centre: [0.8, 0.55], velocity: [0, 0] }],
    pours: [
      { t: 1.25, material: 'drucker_prager', rate: 0.03, duration: 2.0004, spout: [1, 0.4], applied_at: 1.25012 },
      { t: 3.5, material: 'mohr_coulomb', rate: 0.0015, duration: 0.041666666666666664, spout: [0.075, 0.475] },
    ],
  };
  const hash = formatHash({ scene: 'sandbox', dim: '2' }, session);
  assert.equal(hash, '#scene=sandbox&dim=2&drop=0.5:ball:elastic:0.25:0.8,0.55' +
    '&pour=1.25:drucker_prager:0.03:2.0004:1,0.4&pour=3.5:mohr_coulomb:0.0015:0.041666666666666664:0.075,0.475');
  const back = readHash(hash, NAMES);
  assert.deepEqual(back.errors, []);
  const { applied_at, ...first } = session.pours[0];
  assert.ok(applied_at > 0);
  assert.deepEqual(back.session.pours, [first, session.pours[1]], 'every figure exactly, the duration to the last digit');
  assert.equal(back.session.drops.length, 1);
  const p = parsePour('0:drucker_prager:0.00236:1:1,0.4,0.5');
  assert.deepEqual(p, { t: 0, material: 'drucker_prager', rate: 0.00236, duration: 1, spout: [1, 0.4, 0.5] });
  assert.equal(formatPour(p), '0:drucker_prager:0.00236:1:1,0.4,0.5');
  assert.deepEqual(readHash('#scene=sandbox', NAMES).session.pours, [], 'no pour');
});

test('a malformed pour entry is named with what is expected, the rest of the link kept', () => {
  const { session, errors } = readHash('#gravity=5&pour=1:sand:0.1&pour=x:drucker_prager:0.1:1:1,0.4' +
    '&pour=1:drucker_prager:0.1:0:1,0.4&pour=1:drucker_prager:0.1:1:1&pour=-1:drucker_prager:0.1:1:1,0.4&pour=1:Sand!:0.1:1:1,0.4', NAMES);
  assert.deepEqual(session.params, [['gravity', 5]]);
  assert.deepEqual(session.pours, []);
  assert.equal(errors.length, 6, errors.join('; '));
  assert.match(errors[0], /^pour=1:sand:0.1: 3 fields, expected TIME:MATERIAL:RATE:DURATION:X,Y\[,Z\]/);
  assert.match(errors[1], /time “x” is not a number/);
  assert.match(errors[2], /duration 0 is not positive/);
  assert.match(errors[3], /the spout needs 2 or 3 components, not 1/);
  assert.match(errors[4], /time -1 is negative/);
  assert.match(errors[5], /material “Sand!” is not a name/);
  assert.throws(() => parsePour('1:drucker_prager:abc:1:1,0.4'), /rate “abc” is not a number/);
});
