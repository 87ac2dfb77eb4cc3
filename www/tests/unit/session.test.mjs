// The page's side of the simulation (www/js/session.js) against a stand-in for the worker:
// commands and their answers, and the frames' buffers going back and forth.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { Session } from '../../js/session.js';

/// A session whose messages to the worker are recorded.
function session() {
  const s = new Session();
  s.sent = [];
  s.send = (m, transfer = []) => s.sent.push({ ...m, transfer });
  s.transfer = true;
  return s;
}

/// A frame as the worker sends it, with buffers of its own.
function frame(seq, count = 3) {
  const positions = new Float32Array(new ArrayBuffer(64), 0, 4 * count);
  const values = new Float32Array(new ArrayBuffer(64), 0, count);
  return { type: 'frame', seq, positions, values, stride: 4, count, time: seq / 100, report: { refused: [] } };
}

test('a command resolves with its answer, or rejects with the solver\'s message; the state comes with it', async () => {
  const s = session();
  const a = s.request('setQuality', { quality: 'fine' });
  const b = s.request('setQuality', { quality: 'ultra' });
  assert.deepEqual(s.sent.map((m) => [m.id, m.cmd, m.args.quality]), [[0, 'setQuality', 'fine'], [1, 'setQuality', 'ultra']]);
  s.receive({ type: 'reply', id: 1, error: 'quality = ultra: must be one of live, balanced, fine' });
  s.receive({ type: 'reply', id: 0, result: [], state: { particles: 12, quality: { quality: 'fine' } } });
  assert.deepEqual(await a, []);
  await assert.rejects(b, /quality = ultra: must be one of/);
  assert.equal(s.quality.quality, 'fine');
  // A command whose answer is '' or the message: a refused drop is not an exception.
  const drop = s.dropAt('ball', 'elastic', [0.5, 0.5], 0, 9);
  const ok = s.clear();
  s.receive({ type: 'reply', id: 2, error: 'size = 9: must be in [0.02, 0.38] (m)' });
  s.receive({ type: 'reply', id: 3, result: undefined });
  assert.equal(await drop, 'size = 9: must be in [0.02, 0.38] (m)');
  assert.equal(await ok, '');
});

test('frames: the newest is drawn, the buffers of those replaced go back to the worker, each once', () => {
  const s = session();
  assert.deepEqual(s.take(), { frame: null, fresh: false });
  const [f1, f2, f3] = [frame(1), frame(2), frame(3)];
  s.receive(f1);
  let t = s.take();
  assert.equal(t.frame, f1);
  assert.ok(t.fresh);
  assert.deepEqual(s.sent.at(-1).args.buffers, [], 'nothing drawn before: nothing to give back');
  assert.deepEqual(s.take(), { frame: f1, fresh: false }, 'no news: the same frame again');
  // Two frames arrive before the next draw: the first is never drawn and goes back at once.
  s.receive(f2);
  s.receive(f3);
  const back = s.sent.at(-1);
  assert.equal(back.cmd, 'drawn');
  assert.deepEqual(back.args.buffers, [f2.positions.buffer, f2.values.buffer]);
  assert.deepEqual(back.transfer, back.args.buffers, 'transferred, not copied');
  // Not wanted yet (the page draws at most so often): kept for later.
  assert.deepEqual(s.take(0, false), { frame: f1, fresh: false });
  t = s.take();
  assert.equal(t.frame, f3);
  assert.deepEqual(s.sent.at(-1).args.buffers, [f1.positions.buffer, f1.values.buffer], 'the frame drawn before goes back');
  const returned = s.sent.filter((m) => m.cmd === 'drawn').flatMap((m) => m.args.buffers);
  assert.equal(new Set(returned).size, returned.length, 'no buffer given back twice');
  assert.ok(!returned.includes(f3.positions.buffer), 'the frame on screen is kept');
});

test('on the page\'s own thread frames are read in place: nothing goes back', () => {
  const s = session();
  s.transfer = false;
  s.receive(frame(1));
  s.take();
  s.receive(frame(2));
  s.receive(frame(3));
  s.take();
  assert.deepEqual(s.sent, []);
});

test('a start (load, Clear, Reset, quality) drops every frame of the simulation before it: drawn, waiting or late', async () => {
  const s = session();
  const old = (seq) => ({ ...frame(seq), generation: 1 });
  const [drawn, waiting, late] = [old(1), old(2), old(3)];
  s.receive({ type: 'reply', id: 99, result: {}, generation: 1 });
  s.receive(drawn);
  s.take();
  s.receive(waiting);
  // A lesson loads: its reply comes after every frame of the scene before it.
  const load = s.load({ text: '{}' }, {}, '2');
  s.receive({ type: 'reply', id: 0, result: { rejected: [], refused: [] }, generation: 2 });
  await load;
  assert.equal(s.generation, 2);
  assert.deepEqual(s.take(), { frame: null, fresh: false }, 'nothing of the scene before is shown, plotted or measured');
  s.receive(late); // cannot come after the reply from one worker, but a stale frame is never taken
  assert.deepEqual(s.take(), { frame: null, fresh: false });
  const back = s.sent.filter((m) => m.cmd === 'drawn').flatMap((m) => m.args.buffers);
  for (const f of [drawn, waiting, late]) assert.ok(back.includes(f.positions.buffer) && back.includes(f.values.buffer), `frame ${f.seq}'s buffers go back`);
  const fresh = { ...frame(4), generation: 2 };
  s.receive(fresh);
  assert.equal(s.take().frame, fresh, 'the new start\'s frames are drawn');
});
