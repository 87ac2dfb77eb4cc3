// The Pour tool in a real headless Chromium (Debian's package, driven by playwright-core): in
// 2D and 3D, a press held on the floor pours sand from a spout above it until it is released,
// and the sand heaps under the point pressed (in 2D with the plane-strain line against it); the
// link records the pour and a page opened from it pours the same particles. The rate's control names its range and refuses bad values with
// the solver's message; Reset, another quality level and Clear end a pour held; the P key picks the tool; one finger
// held on a touch screen pours, a second one neither pours nor pinches. Served by
// `cargo xtask test` (MPM_URL); screenshots go to MPM_OUT (default target/e2e).
//
//   MPM_URL=http://127.0.0.1:8080/ node --test www/tests/pour.test.mjs
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import { join } from 'node:path';
import { launch, launchBrowser, openPage } from './browser.mjs';
import { screenOf } from './view.mjs';

const URL_ROOT = process.env.MPM_URL || 'http://127.0.0.1:8080/';
const OUT = process.env.MPM_OUT || 'target/e2e';
mkdirSync(OUT, { recursive: true });

let browser, touchBrowser;
before(async () => { browser = await launch(); });
after(async () => {
  await browser?.close();
  await touchBrowser?.close();
});

/// Opens the page with `hash` (see `openPage`).
const open = (hash = '') => openPage(browser.context, URL_ROOT + hash);

/// A small elastic ball in a corner, dropped at the start: the box is not empty, so time runs
/// before a pour (an empty box stands still).
const BALL = { 2: 'drop=0:ball:elastic:0.1:0.15,0.3', 3: 'drop=0:ball:elastic:0.1:0.15,0.3,0.15' };

/// The page's figures: particles, bodies, simulated time, whether a pour runs, the link.
const now = (page) => page.evaluate(() => ({
  particles: mpm.sim.particles,
  bodies: mpm.sim.bodies,
  time: mpm.simTime,
  pouring: mpm.sim.pouring,
  hash: location.hash,
  hint: document.getElementById('hint').textContent,
  toast: document.getElementById('toast').textContent,
  camera: [mpm.camera.yaw, mpm.camera.pitch, mpm.camera.zoom2d, mpm.camera.zoom3d],
}));

/// The `pour=` entries of a link: {t, material, rate, duration, spout}.
function pours(hash) {
  return [...hash.matchAll(/pour=([^&]+)/g)].map(([, e]) => {
    const [t, material, rate, duration, spout] = e.split(':');
    return { t: +t, material, rate: +rate, duration: +duration, spout: spout.split(',').map(Number) };
  });
}

/// Where the particles of body `body` are in the frame shown (world coordinates, m; the view
/// colours by body).
const particlesOf = (page, body) => page.evaluate((body) => {
  if (mpm.view.colour !== 'body') throw new Error(`the view colours by ${mpm.view.colour}, not by body`);
  const f = mpm.frame, dim = mpm.domain.length, out = [];
  for (let i = 0; i < f.count; i++) {
    if (f.values[i] === body) out.push(Array.from(f.positions.subarray(i * f.stride, i * f.stride + dim)));
  }
  return out;
}, body);

/// Waits until the simulated time passes `t` (s).
const until = (page, t) => page.waitForFunction((t) => mpm.simTime > t, t, { timeout: 120_000 });

for (const dim of [2, 3]) {
  test(`${dim}D: a press held on the floor pours for as long as it is held, the sand heaps under it; the link replays the pour to the same particles`, async () => {
    const { page, errors } = await open(`#scene=sandbox&dim=${dim}&${BALL[dim]}`);
    // The tool, its rate control (with units, its range and a tooltip) and its hint.
    await page.click('#tool-pour');
    assert.equal(await page.getAttribute('#tool-pour', 'aria-pressed'), 'true');
    assert.equal(await page.getAttribute('#tool-drop', 'aria-pressed'), 'false');
    assert.equal(await page.isVisible('#pour-params'), true, 'the rate shows with the Pour tool');
    assert.equal(await page.isVisible('#objects'), false, 'the objects do not');
    assert.equal(await page.textContent('#drop-title'), 'Pour');
    const rates = await page.evaluate(() => mpm.session.pourRates());
    const unit = dim === 3 ? 'm³/s' : 'm²/s';
    assert.equal(rates.unit, unit);
    const rate = page.locator('[data-param="pour.rate"]');
    assert.equal(await rate.getAttribute('aria-label'), `Pour rate (${unit})`);
    const tip = await page.locator('.param:has([data-param="pour.rate"])').getAttribute('title');
    assert.match(tip, /volume of sand the spout lets out per second/);
    assert.match(tip, /leaves it at 0\.3 m\/s/);
    const range = await page.textContent('#pour-range');
    assert.ok(range.includes(`${rates.allowed[0]} to ${rates.allowed[1]} ${unit}`), range);
    assert.match(await page.textContent('#hint'), /Press and hold .* to pour sand/);
    assert.equal(await page.evaluate(() => mpm.rate), rates.default);

    // A solid is refused with the solver's message naming the field.
    await page.click('#materials button[data-id="elastic"]');
    const [x, y] = await screenOf(page, 1.0, dim === 3 ? 0 : 0.1, 0.5);
    await page.mouse.move(x, y);
    await page.mouse.down();
    await page.waitForFunction(() => /material = elastic: must be a granular model/.test(document.getElementById('toast').textContent),
      null, { timeout: 10_000 });
    await page.mouse.up();
    assert.equal((await now(page)).pouring, false);
    assert.equal(pours((await now(page)).hash).length, 0, 'nothing in the link');
    await page.click('#materials button[data-id="drucker_prager"]');

    // Press and hold: the pour starts, the hint says so, the view does not turn.
    const before = await now(page);
    // the link's writes counted (browsers refuse a page that rewrites its address too often)
    await page.evaluate(() => {
      const write = history.replaceState.bind(history);
      window.hashWrites = 0;
      history.replaceState = (...a) => { window.hashWrites++; return write(...a); };
    });
    const wall0 = Date.now();
    await page.mouse.move(x, y);
    await page.mouse.down();
    await page.waitForFunction(() => mpm.sim.pouring && /^Pouring .* \(release to stop\)/.test(document.getElementById('hint').textContent),
      null, { timeout: 10_000 });
    const start = pours((await now(page)).hash)[0];
    assert.ok(start && start.material === 'drucker_prager' && start.rate === rates.default, JSON.stringify(start));
    assert.ok(Math.abs(start.spout[0] - 1.0) < 0.02 && Math.abs(start.spout[1] - rates.height) < 1e-9, JSON.stringify(start));
    if (dim === 3) assert.ok(Math.abs(start.spout[2] - 0.5) < 0.02, `over the point pressed: ${JSON.stringify(start)}`);
    await page.mouse.move(x + 40, y - 25, { steps: 4 }); // dragged while held: still pouring, no orbit
    await until(page, start.t + 0.4);
    const mid = await now(page);
    assert.ok(mid.pouring && mid.particles > before.particles, `the count rises: ${before.particles} → ${mid.particles}`);
    assert.deepEqual(mid.camera, before.camera, 'a press held does not turn the view');
    // the link follows the pour while it runs, with the time it has poured so far
    await page.waitForFunction((t) => {
      const m = location.hash.match(/pour=[^:]+:[^:]+:[^:]+:([^:]+):/);
      return m && Number(m[1]) > t;
    }, 0.3, { timeout: 10_000 });
    const running = (await now(page)).hash; // a link copied while it pours
    await page.screenshot({ path: join(OUT, `pour-${dim}d.png`) });
    await until(page, start.t + 1.5);
    await page.mouse.up();
    const [writes, held] = [await page.evaluate(() => window.hashWrites), (Date.now() - wall0) / 1000];
    assert.ok(writes >= 3 && writes <= 2 * held + 4, `the link follows the pour at most twice a second: ${writes} writes in ${held} s`);

    // Released: the pour stops, the count stops rising, the link has how long it poured.
    await page.waitForFunction(() => !mpm.sim.pouring && !/^Pouring/.test(document.getElementById('hint').textContent),
      null, { timeout: 10_000 });
    const stopped = await now(page);
    const [pour] = pours(stopped.hash);
    assert.ok(pour.duration >= 1.5, `held for at least 1.5 s of simulated time: ${pour.duration}`);
    assert.ok(stopped.particles > mid.particles, `${mid.particles} → ${stopped.particles}`);
    await until(page, stopped.time + 1.0);
    const later = await now(page);
    assert.equal(later.particles, stopped.particles, 'nothing pours after the release');
    assert.equal(later.hash, stopped.hash);
    // The volume poured is the rate times the time held, within a few layers.
    const { h, ppc } = await page.evaluate(() => ({ h: mpm.cellSize, ppc: mpm.session.quality.particles_per_cell }));
    assert.equal(later.bodies, 2, 'the ball and the pour');
    const poured = later.particles - before.particles;
    const volume = poured * (h / ppc) ** dim;
    assert.ok(Math.abs(volume - pour.rate * pour.duration) < 0.05 * pour.rate * pour.duration,
      `${poured} particles, ${volume} against ${pour.rate} × ${pour.duration}`);

    // The sand lies in a heap on the floor under the point pressed: centred on it, highest
    // near it and lower away from it, none far from it.
    const sand = await particlesOf(page, 1);
    assert.equal(sand.length, poured);
    const off = (p) => Math.hypot(p[0] - 1.0, dim === 3 ? p[2] - 0.5 : 0); // from the spout's axis
    const mean = (a) => a.reduce((s, v) => s + v, 0) / a.length;
    const centre = [mean(sand.map((p) => p[0])), dim === 3 ? mean(sand.map((p) => p[2])) : 0.5];
    assert.ok(Math.hypot(centre[0] - 1.0, centre[1] - 0.5) < 0.03, `the heap is centred under the point: ${centre}`);
    assert.ok(sand.every((p) => off(p) < 0.6), `none far from it: ${Math.max(...sand.map(off))} m`);
    assert.ok(sand.every((p) => p[1] < rates.height - 2 * h), 'none left in the air');
    const top = (lo, hi) => Math.max(0, ...sand.filter((p) => off(p) >= lo && off(p) < hi).map((p) => p[1]));
    const [peak, flank] = [top(0, 0.08), top(0.2, 0.3)];
    assert.ok(peak > 2 * h && peak > flank + h, `a heap, highest at the axis: ${peak} m, ${flank} m at 0.2–0.3 m`);
    // Poured, it stands at its angle of repose: the overlay draws the line at the core's
    // angle of repose against it (in 3D on the radial profile), named, and no collapse note.
    const marks = await page.evaluate(() => ({ labels: mpm.overlay.labels, poured: mpm.frame.measures.map((d) => d.poured) }));
    assert.deepEqual(marks.poured, [true], 'the sand poured says so');
    assert.ok(marks.labels.some((l) => l.kind === 'law' && /^angle of repose [\d.]+°, Drucker–Prager$/.test(l.text)), JSON.stringify(marks.labels));
    assert.ok(!marks.labels.some((l) => l.kind === 'note'), JSON.stringify(marks.labels));
    assert.deepEqual(errors, [], 'no page error');
    await page.close();

    // The link opened again pours the same particles.
    const again = await open(later.hash);
    await until(again.page, pour.t + pour.duration + 0.3);
    const replayed = await now(again.page);
    assert.equal(replayed.particles, later.particles, 'the link replays the pour to the same count');
    assert.equal(replayed.pouring, false, 'a replayed pour is not held');
    assert.deepEqual(pours(replayed.hash), [pour], 'and records the same pour');
    assert.deepEqual(again.errors, [], 'no page error');
    await again.page.close();

    // A link copied while it poured pours what had poured by then.
    const [part] = pours(running);
    const early = await open(running);
    await until(early.page, part.t + part.duration + 0.3);
    const partial = await now(early.page);
    assert.deepEqual(pours(partial.hash), [part]);
    assert.ok(partial.particles > before.particles && partial.particles < later.particles,
      `part of the pour: ${before.particles} < ${partial.particles} < ${later.particles}`);
    assert.ok(!/Ignored/.test(partial.toast), partial.toast);
    assert.deepEqual(early.errors, [], 'no page error');
    await early.page.close();
  });
}

test('the rate: typed values outside its range, or not numbers, are refused naming the field and the range; one inside it pours', async () => {
  const { page, errors } = await open(`#scene=sandbox&dim=2&${BALL[2]}`);
  await page.keyboard.press('p');
  assert.equal(await page.getAttribute('#tool-pour', 'aria-pressed'), 'true', 'P picks the Pour tool');
  const { allowed, default: q0 } = await page.evaluate(() => mpm.session.pourRates());
  const box = page.locator('[data-param-value="pour.rate"]');
  const error = page.locator('.param:has([data-param="pour.rate"]) .error');
  // what was typed, and the value the message names
  for (const [typed, read] of [['abc', 'NaN'], ['5', '5'], ['-0.01', '-0.01'], ['0', '0'], ['1e9', '1000000000'], ['', 'NaN']]) {
    await box.fill(typed);
    await box.press('Enter');
    await page.waitForFunction((read) => document.querySelector('.param:has([data-param="pour.rate"]) .error').textContent
      .startsWith(`rate = ${read}: `), read, { timeout: 10_000 });
    const msg = await error.textContent();
    assert.ok(msg.includes(`must be in [${allowed[0]}, ${allowed[1]}] (m²/s)`), `${typed}: ${msg}`);
    assert.equal(await page.evaluate(() => mpm.rate), q0, `${typed}: the rate is kept`);
    await box.press('Escape');
    assert.equal(await box.inputValue(), String(q0), 'Escape shows the rate in use again');
  }
  // A rate beyond the slider's end but allowed is taken, and the pour runs at it.
  const q = 0.2;
  assert.ok(q > (await page.evaluate(() => mpm.session.pourRates().offered[1])) && q < allowed[1]);
  await box.fill(String(q));
  await box.press('Enter');
  await page.waitForFunction((q) => mpm.rate === q, q, { timeout: 10_000 });
  assert.equal(await error.textContent(), '');
  const [x, y] = await screenOf(page, 0.6, 0.1, 0);
  await page.mouse.move(x, y);
  await page.mouse.down();
  await page.waitForFunction(() => mpm.sim.pouring, null, { timeout: 10_000 });
  const t0 = await page.evaluate(() => mpm.simTime);
  await until(page, t0 + 0.3);
  await page.mouse.up();
  await page.waitForFunction(() => !mpm.sim.pouring, null, { timeout: 10_000 });
  const [pour] = pours(await page.evaluate(() => location.hash));
  assert.equal(pour.rate, q);
  assert.ok(Math.abs(pour.spout[0] - 0.6) < 0.02, JSON.stringify(pour));
  // The keys: D back to Drop (the objects show again), P to Pour.
  await page.keyboard.press('d');
  assert.equal(await page.getAttribute('#tool-drop', 'aria-pressed'), 'true');
  assert.equal(await page.isVisible('#objects'), true);
  assert.equal(await page.isVisible('#pour-params'), false);
  assert.deepEqual(errors, [], 'no page error');
  await page.close();
});

test('Reset, another quality level and Clear end a pour held: it pours no more, and the next press pours again', async () => {
  const { page, errors } = await open(`#scene=sandbox&dim=3&${BALL[3]}`);
  await page.click('#tool-pour');
  const [x, y] = await screenOf(page, 1.0, 0, 0.5);
  const ends = [
    // Reset and Clear forget the pour: it leaves the link
    ['Reset', () => page.keyboard.press('r'), 0],
    // another level samples the scene again with the session so far: the pour as far as it ran
    ['Balanced', () => page.selectOption('#quality', 'balanced'), 1],
    ['Clear', () => page.locator('#clear').dispatchEvent('click'), 0],
  ];
  for (const [what, end, kept] of ends) {
    await page.mouse.move(x, y);
    await page.mouse.down();
    await page.waitForFunction(() => mpm.sim.pouring && /^Pouring/.test(document.getElementById('hint').textContent), null, { timeout: 10_000 });
    const t0 = await page.evaluate(() => mpm.simTime);
    await until(page, t0 + 0.2);
    await end(); // the button still held
    await page.waitForFunction((kept) => !mpm.sim.pouring && location.hash.split('pour=').length - 1 === kept, kept, { timeout: 30_000 });
    assert.match(await page.textContent('#hint'), /^Press and hold/, `${what}: the hint says what the tool does again`);
    if (kept) {
      // the scene starts over and pours again for as long as the pour ran, no longer
      const [p] = pours((await now(page)).hash);
      await until(page, p.t + p.duration + 0.2);
    }
    const after = await now(page);
    // (Reset empties the sandbox, the ball's drop forgotten: its time stands still unless a
    // pour runs, so the wait is in wall-clock time.)
    await page.waitForTimeout(1500);
    const later = await now(page);
    assert.equal(later.particles, after.particles, `${what}: nothing more pours though the button is held`);
    assert.equal(later.hash, after.hash, `${what}: the link stands`);
    await page.mouse.up();
    await page.waitForTimeout(200);
    assert.equal((await now(page)).pouring, false);
    assert.equal((await now(page)).hash, after.hash, `${what}: the release changes nothing`);
  }
  assert.ok(await page.textContent('#pour-range'), 'the rate control is there after the new level');
  // After the Clear the box is empty; the next press pours into it (time runs while it pours).
  assert.equal((await now(page)).particles, 0);
  await page.mouse.move(x, y);
  await page.mouse.down();
  await page.waitForFunction(() => mpm.sim.pouring && mpm.sim.particles > 0, null, { timeout: 30_000 });
  await page.mouse.up();
  await page.waitForFunction(() => !mpm.sim.pouring && /cleared=1/.test(location.hash) && /pour=0:/.test(location.hash), null, { timeout: 10_000 });
  assert.deepEqual(errors, [], 'no page error');
  await page.close();
});

test('touch, 390×844: one finger held pours and its hint shows; a second finger neither pours nor pinches; lifting it stops', async () => {
  touchBrowser ??= await launchBrowser();
  const context = await touchBrowser.newContext({ viewport: { width: 390, height: 844 }, hasTouch: true, isMobile: true, deviceScaleFactor: 2 });
  const { page, errors } = await openPage(context, `${URL_ROOT}#scene=sandbox&dim=2&${BALL[2]}`);
  await page.tap('#tool-pour');
  assert.equal(await page.evaluate(() => document.documentElement.scrollWidth), 390, 'the tools fit: no sideways scrolling');
  await page.evaluate(() => window.scrollTo(0, 0));
  const [x, y] = await screenOf(page, 1.2, 0.1, 0);
  const cdp = await context.newCDPSession(page);
  const before = await now(page);
  await cdp.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: [{ x, y, id: 0 }] });
  await page.waitForFunction(() => mpm.sim.pouring, null, { timeout: 10_000 });
  assert.ok(await page.isVisible('#hint'), 'the hint shows while it pours, on a phone too');
  assert.match(await page.textContent('#hint'), /^Pouring .* \(release to stop\)/);
  // a second finger comes and moves apart from the first: no second pour, no zoom
  await cdp.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: [{ x, y, id: 0 }, { x: x - 30, y, id: 1 }] });
  for (let k = 1; k <= 6; k++) {
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchMove', touchPoints: [{ x, y, id: 0 }, { x: x - 30 - 15 * k, y, id: 1 }] });
  }
  // (CDP's touchEnd lifts the fingers it lists)
  await cdp.send('Input.dispatchTouchEvent', { type: 'touchEnd', touchPoints: [{ x: x - 120, y, id: 1 }] });
  const t0 = await page.evaluate(() => mpm.simTime);
  await until(page, t0 + 0.5);
  const held = await now(page);
  assert.ok(held.pouring && held.particles > before.particles, `still pouring: ${before.particles} → ${held.particles}`);
  assert.deepEqual(held.camera, before.camera, 'no zoom, no turn');
  assert.equal(pours(held.hash).length, 1, 'one pour');
  await cdp.send('Input.dispatchTouchEvent', { type: 'touchEnd', touchPoints: [] });
  await cdp.detach();
  await page.waitForFunction(() => !mpm.sim.pouring, null, { timeout: 10_000 });
  const stopped = await now(page);
  await until(page, stopped.time + 0.5);
  assert.equal((await now(page)).particles, stopped.particles, 'lifted: nothing more pours');
  const [pour] = pours(stopped.hash);
  assert.ok(Math.abs(pour.spout[0] - 1.2) < 0.02, JSON.stringify(pour));
  await page.screenshot({ path: join(OUT, 'pour-touch-390.png') });
  assert.deepEqual(errors, [], 'no page error');
  await context.close();
});

test('the first view: the bunny lands on a sand heap built under its angle of repose, which stands with the line against it; built steeper (φ lowered) the heap collapses', async () => {
  const built = Math.atan(0.2 / 0.39) * 180 / Math.PI;
  const mean = (d) => {
    const f = d.heap.flanks.filter(Boolean).map((x) => x.angle);
    return f.reduce((s, v) => s + v, 0) / f.length;
  };
  const read = (page) => page.evaluate(() => ({ d: mpm.frame.measures[0], labels: mpm.overlay.labels, scene: mpm.sim.scene.name }));
  // as it opens, at φ = 35°: the heap takes the bunny and stands as built, the line drawn
  let { page, errors } = await open('');
  await until(page, 2.5);
  let r = await read(page);
  assert.match(r.scene, /sand heap \(3D\)/);
  const figures = `flank ${mean(r.d).toFixed(1)}° (built ${built.toFixed(1)}°, angle of repose ${r.d.repose_angle}°)`;
  assert.ok(r.d.heaped && Math.abs(mean(r.d) - built) <= 3, figures);
  assert.ok(r.labels.some((l) => l.kind === 'law' && /^angle of repose 33\.0°, Drucker–Prager$/.test(l.text)), JSON.stringify(r.labels));
  assert.ok(!r.labels.some((l) => l.kind === 'note'), JSON.stringify(r.labels));
  await page.screenshot({ path: join(OUT, 'first-view.png') });
  assert.deepEqual(errors, [], 'no page error');
  await page.close();
  // at φ = 20° the same heap stands steeper than its angle of repose: it fails as a whole, a
  // collapse (2D: the note over it, no line), and rests under that angle
  ({ page, errors } = await open('#scene=bunny_on_sand_heap&dim=2&drucker_prager.friction_angle=20'));
  await until(page, 3.5);
  r = await read(page);
  assert.ok(!r.d.heaped && mean(r.d) <= r.d.repose_angle + 1, `flank ${mean(r.d).toFixed(1)}°, angle of repose ${r.d.repose_angle}°`);
  assert.ok(r.labels.some((l) => l.kind === 'note' && /^a collapse/.test(l.text)), JSON.stringify(r.labels));
  assert.ok(!r.labels.some((l) => l.kind === 'law'), JSON.stringify(r.labels));
  assert.deepEqual(errors, [], 'no page error');
  await page.close();
});
