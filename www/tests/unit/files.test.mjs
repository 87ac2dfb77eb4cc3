// The naming and matching of scene files, recordings and lessons (www/js/files.js,
// www/js/record.js, www/js/lessons.js), without a browser.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { baseName, fileStem, matchAssets, sceneFileOf } from '../../js/files.js';
import { captionText, videoType, VIDEO_TYPES } from '../../js/record.js';
import { bodyParam, lessonSpec } from '../../js/lessons.js';
import { paramTable } from '../../js/params.js';

test('files are named after the scene and the simulated time', () => {
  assert.equal(fileStem('bunny on a sand ball (3D)', 1.254), 'bunny-on-a-sand-ball-3d-t1.25s');
  assert.equal(fileStem('sand columns at 20° and 40° (2D)', 0, 2.3), 'sand-columns-at-20-and-40-2d-t0.00-2.30s');
  assert.equal(fileStem('Élan: café', 3), 'elan-cafe-t3.00s', 'accents folded, punctuation dropped');
  assert.equal(fileStem('', NaN), 'scene-t0.00s', 'no name, no time');
  assert.equal(fileStem('x'.repeat(80), 1).length, 48 + '-t1.00s'.length, 'long names cut');
  assert.equal(captionText('sandbox', 1.23456), 'sandbox · t = 1.235 s');
});

test('the scene file among the files dropped, and the files it references by name', () => {
  const files = [{ name: 'demo.json' }, { name: 'bunny.obj' }, { name: 'notes.txt' }];
  assert.equal(sceneFileOf(files).name, 'demo.json');
  assert.throws(() => sceneFileOf([{ name: 'a.obj' }]), /no scene file \(\.json\) among a\.obj/);
  assert.throws(() => sceneFileOf([{ name: 'a.json' }, { name: 'b.JSON' }]), /one scene file at a time, not a\.json and b\.JSON/);
  assert.equal(baseName('../meshes/bunny.obj'), 'bunny.obj');
  assert.equal(baseName('C:\\scenes\\x.txt'), 'x.txt');
  const { found, missing } = matchAssets(['../scenes/bunny.obj', 'outlines/heap.txt', 'notes.txt'], files);
  assert.deepEqual(found.map(([p, f]) => [p, f.name]), [['../scenes/bunny.obj', 'bunny.obj'], ['notes.txt', 'notes.txt']]);
  assert.deepEqual(missing, ['outlines/heap.txt']);
});

test('the recorder takes the first WebM format the browser supports', () => {
  assert.equal(videoType(() => true), VIDEO_TYPES[0]);
  assert.equal(videoType((t) => t === 'video/webm'), 'video/webm');
  assert.equal(videoType(() => false), '', 'none: the page says it cannot record');
  assert.ok(VIDEO_TYPES.every((t) => t.startsWith('video/webm')));
});

test('a lesson\'s sliders: the table\'s spec, labelled with the body for one body\'s parameter', () => {
  const table = paramTable({
    params: [
      { name: 'gravity', label: 'Gravity', unit: 'm/s²', min: 0, max: 30 },
      { name: 'drucker_prager.friction_angle', model: 'drucker_prager', label: 'Friction angle', unit: '°', min: 0, max: 60 },
    ],
    models: [], objects: [],
  });
  const scene = { bodies: [{ name: 'sand at 20°' }, { name: '' }] };
  assert.deepEqual(bodyParam('bodies[1].drucker_prager.friction_angle'), { body: 1, name: 'drucker_prager.friction_angle' });
  assert.equal(bodyParam('drucker_prager.friction_angle'), null);
  assert.equal(bodyParam('bodies[0].gravity'), null, 'a body has material parameters only');
  assert.equal(lessonSpec('gravity', table, scene).label, 'Gravity');
  const one = lessonSpec('bodies[0].drucker_prager.friction_angle', table, scene);
  assert.equal(one.name, 'bodies[0].drucker_prager.friction_angle');
  assert.equal(one.label, 'Friction angle: sand at 20°');
  assert.equal(one.max, 60);
  assert.equal(lessonSpec('bodies[1].drucker_prager.friction_angle', table, scene).label, 'Friction angle: body 2');
  assert.equal(lessonSpec('von_mises.yield_stress', table, scene), null);
  assert.equal(table.spec('bodies[3].drucker_prager.friction_angle').label, 'Friction angle', 'the table looks one body\'s parameter up by its own');
});
