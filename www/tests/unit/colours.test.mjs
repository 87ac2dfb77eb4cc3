// The colour legend's names (www/js/colours.js): no two entries read alike.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { bodyNames } from '../../js/colours.js';

test('a second bunny dropped is listed as bunny 2, a body without a name by its number', () => {
  assert.deepEqual(bodyNames([{ name: 'sand' }, { name: 'bunny' }, { name: 'bunny' }, { name: '' }, { name: 'bunny' }]),
    ['sand', 'bunny', 'bunny 2', 'body 4', 'bunny 3']);
  assert.deepEqual(bodyNames([]), []);
});
