// Measuring on the page, in headless Chromium (Debian's package through playwright-core): the
// HUD in its strip never covers the drawn scene at a laptop's, a tablet's and a phone's size;
// the friction-angle lesson asks before it runs, its angle readout agrees with the core's
// measure of the same frame, and its question is answered by that readout; the column
// collapse shows the experiments' markers naming their source (and a scene without a column
// none); the hand tool reads a length and an angle; an inspected particle gets its Mohr
// circles (one in plane strain, three in 3D) with the Mohr–Coulomb envelope, a Mohr–Coulomb
// particle with its own envelope and no cone. Served by
// `cargo xtask test` (MPM_URL).
//
//   MPM_URL=http://127.0.0.1:8080/ node --test www/tests/measure.test.mjs
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import { join } from 'node:path';
import { launch, launchBrowser, openPage } from './browser.mjs';
import { screenOf } from './view.mjs';

const URL_ROOT = process.env.MPM_URL || 'http://127.0.0.1:8080/';
const OUT = process.env.MPM_OUT || 'target/e2e';
mkdirSync(OUT, { recursive: true });

let browser, plain;
before(async () => { browser = await launch(); });
after(async () => {
  await browser?.close();
  await plain?.close();
});

const open = (hash = '') => openPage(browser.context, URL_ROOT + hash);

const rectOf = (page, selector) => page.evaluate((s) => {
  const r = document.querySelector(s)?.getBoundingClientRect();
  return r && r.width > 0 && r.height > 0 ? { x: r.x, y: r.y, width: r.width, height: r.height } : null;
}, selector);

const overlap = (a, b) => Math.max(0, Math.min(a.x + a.width, b.x + b.width) - Math.max(a.x, b.x)) *
  Math.max(0, Math.min(a.y + a.height, b.y + b.height) - Math.max(a.y, b.y));

/// The page rectangle of the drawn scene: the domain's box as projected on the view.
const sceneBounds = (page) => page.evaluate(() => {
  const c = document.getElementById('view');
  const r = c.getBoundingClientRect();
  mpm.camera.matrices(c.clientWidth, c.clientHeight);
  const [W, H, D] = mpm.domain;
  const corners = [];
  for (const x of [0, W]) for (const y of [0, H]) for (const z of D ? [0, D] : [0]) corners.push(mpm.camera.project(x, y, z));
  const xs = corners.filter(Boolean).map((p) => r.left + p[0]), ys = corners.filter(Boolean).map((p) => r.top + p[1]);
  const x0 = Math.max(r.left, Math.min(...xs)), x1 = Math.min(r.right, Math.max(...xs));
  const y0 = Math.max(r.top, Math.min(...ys)), y1 = Math.min(r.bottom, Math.max(...ys));
  return { x: x0, y: y0, width: x1 - x0, height: y1 - y0 };
});

const LAYOUTS = [
  { width: 1366, height: 768 },
  { width: 1280, height: 800 },
  { width: 768, height: 1024, touch: true },
  { width: 390, height: 844, touch: true },
];

for (const l of LAYOUTS) {
  test(`${l.width}×${l.height}${l.touch ? ' (touch)' : ''}: the HUD shows the class's figures and never covers the drawn scene`, async () => {
    plain ??= await launchBrowser();
    const context = await plain.newContext({ viewport: { width: l.width, height: l.height }, hasTouch: !!l.touch, isMobile: !!l.touch });
    for (const hash of ['#lesson=friction_angle', '#scene=column_collapse&dim=3']) {
      const { page, errors } = await openPage(context, URL_ROOT + hash);
      await page.waitForFunction(() => document.querySelector('[data-hud="quality"]'), null, { timeout: 20_000 });
      const keys = await page.$$eval('#hud [data-hud]', (els) => els.map((e) => e.dataset.hud));
      assert.deepEqual(keys, ['time', 'speed', 'quality'], `${hash}: the class's figures by default`);
      assert.match(await page.textContent('[data-hud="quality"]'), /run-out [+−][\d.]+ %.*against experiments/);
      for (const details of [false, true]) {
        if (details) {
          await page.click('#hud-details');
          await page.waitForFunction(() => document.querySelector('[data-hud="fps"]'), null, { timeout: 10_000 });
        }
        await page.evaluate(() => window.scrollTo(0, 0));
        await page.waitForTimeout(150);
        const hud = await rectOf(page, '.hud-bar');
        const scene = await sceneBounds(page);
        assert.ok(hud && scene.width > 50 && scene.height > 50, `${hash}: ${JSON.stringify({ hud, scene })}`);
        assert.equal(overlap(hud, scene), 0, `${hash}, details ${details}: the HUD ${JSON.stringify(hud)} covers the scene ${JSON.stringify(scene)}`);
      }
      if (hash.includes('lesson')) await page.screenshot({ path: join(OUT, `hud-${l.width}x${l.height}.png`) });
      assert.deepEqual(errors, []);
      await page.close();
    }
    await context.close();
  });
}

test('the friction-angle lesson asks first, runs on Play, its angle readouts are the core\'s measure of the frame, and the question is answered by them', async () => {
  const { page, errors } = await open('#lesson=friction_angle');
  await page.waitForFunction(() => mpm.lesson?.id === 'friction_angle', null, { timeout: 30_000 });
  // Asked before the first Play: paused at the start, the choices shown.
  assert.equal(await page.isVisible('#lesson-question'), true);
  assert.equal(await page.evaluate(() => mpm.playing), false, 'waits for Play');
  assert.ok((await page.evaluate(() => mpm.simTime)) < 0.05, 'nothing ran yet');
  const choices = await page.$$eval('#lesson-question [data-choice]', (els) => els.map((e) => e.textContent));
  assert.ok(choices.length >= 2, `${choices}`);
  await page.click('#lesson-question [data-choice="3"]');
  assert.equal(await page.getAttribute('#lesson-question [data-choice="3"]', 'aria-pressed'), 'true');
  await page.click('#play');
  const duration = await page.evaluate(() => mpm.lesson.duration);
  await page.waitForFunction((d) => mpm.simTime > d && mpm.lessonPanel.answer, duration, { timeout: 120_000 });
  await page.click('#play'); // pause
  await page.waitForTimeout(300);
  // The readouts drawn for the frame shown, against the core's measure of that frame's
  // particles (heapMeasure, the same mpm::measure, in a wasm instance of the page's own).
  const check = await page.evaluate(async () => {
    await new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)));
    const f = mpm.frame;
    const wasm = await import(new URL('www/pkg/mpm.js', location.href).href);
    await wasm.default();
    const q = mpm.session.quality;
    const spacing = q.cell_size / q.particles_per_cell;
    const out = [];
    for (const body of [0, 1]) {
      const xy = [];
      for (let i = 0; i < f.count; i++) if (f.values[i] === body) xy.push(f.positions[i * f.stride], f.positions[i * f.stride + 1]);
      out.push(JSON.parse(wasm.heapMeasure(new Float64Array(xy), spacing, q.cell_size, mpm.domain[0])));
    }
    return {
      core: out.map((h) => h.flanks.filter(Boolean).map((x) => x.angle)),
      framed: f.measures.map((d) => d.heap.flanks.filter(Boolean).map((x) => x.angle)),
      drawn: mpm.overlay.labels.filter((l) => l.kind === 'angle').map((l) => parseFloat(l.text)),
      laws: mpm.overlay.labels.filter((l) => l.kind === 'law').map((l) => l.text),
      answer: mpm.lessonPanel.answer,
      verdict: document.getElementById('lesson-verdict').textContent,
      marked: [...document.querySelectorAll('#lesson-question [data-choice].answer')].map((e) => Number(e.dataset.choice)),
    };
  });
  const core = check.core.flat();
  assert.ok(core.length >= 2, `each heap has a fitted flank: ${JSON.stringify(check)}`);
  assert.equal(check.drawn.length, core.length, `one readout per flank: ${JSON.stringify(check)}`);
  check.drawn.forEach((a, i) => assert.ok(Math.abs(a - core[i]) < 1, `readout ${a}° against the core's ${core[i]}°`));
  assert.ok(check.laws.some((t) => /φ_ps/.test(t)), `the plane-strain line on the heaps: ${check.laws}`);
  // Answered with the readouts: the 40° heap's mean flank less the 20° heap's.
  const mean = (a) => a.reduce((s, x) => s + x, 0) / a.length;
  assert.ok(check.answer.value > 0, `the 40° heap stands steeper: ${JSON.stringify(check.answer)}`);
  assert.deepEqual(check.marked, [check.answer.index]);
  assert.match(check.verdict, /measured on the view: [\d.]+°/);
  assert.ok(Math.abs(check.answer.value - (mean(check.framed[1]) - mean(check.framed[0]))) < 2,
    'the answer is the difference of the readouts (of its frame)');
  await page.screenshot({ path: join(OUT, 'friction-answered.png') });
  assert.deepEqual(errors, []);
  await page.close();
});

test('law markers: Lube et al. on the column collapses (plane and axisymmetric), none on a scene without a column', async () => {
  for (const [hash, source] of [['#lesson=column_collapse', /Lube et al\. \(2005\)/], ['#scene=column_collapse&dim=3', /Lube et al\. \(2004\)/]]) {
    const { page, errors } = await open(hash);
    if (hash.includes('lesson')) {
      await page.waitForFunction(() => mpm.lesson?.id === 'column_collapse', null, { timeout: 30_000 });
      await page.click('#play');
    }
    await page.waitForFunction(() => mpm.simTime > 0.6, null, { timeout: 120_000 });
    const labels = await page.evaluate(() => mpm.overlay.labels);
    const laws = labels.filter((l) => l.kind === 'law').map((l) => l.text);
    assert.ok(laws.some((t) => source.test(t) && /run-out/.test(t)), `${hash}: ${laws}`);
    assert.ok(laws.some((t) => /final height/.test(t)), `${hash}: ${laws}`);
    assert.ok(labels.some((l) => l.kind === 'runout'), `${hash}: the run-out ruler: ${JSON.stringify(labels)}`);
    const law = await page.evaluate(() => mpm.frame.measures[0].column.law);
    assert.ok(Math.abs(law.aspect_ratio - 2) < 0.15, `a = H0/L0 ≈ 2: ${JSON.stringify(law)}`);
    if (hash.includes('lesson')) assert.match(law.regime, /between/, 'a = 2 lies in the plane transition: the range is drawn');
    await page.screenshot({ path: join(OUT, `laws-${hash.includes('lesson') ? '2d' : '3d'}.png`) });
    assert.deepEqual(errors, []);
    await page.close();
  }
  const { page, errors } = await open('#scene=sandbox&dim=2&drop=0:box:von_mises:0.5:0.3,0.2');
  await page.waitForFunction(() => mpm.sim.bodies === 1 && mpm.simTime > 0.2, null, { timeout: 30_000 });
  assert.deepEqual(await page.evaluate(() => mpm.overlay.labels.filter((l) => l.kind === 'law')), [], 'no sand, no law');
  assert.deepEqual(errors, []);
  await page.close();
});

test('the hand tool measures a dragged length and angle with the core', async () => {
  const { page, errors } = await open('#scene=sandbox&dim=2&drop=0:box:von_mises:0.2:1.5,0.2');
  await page.click('#tool-measure');
  // The view holds its place while the HUD's figures change (the speed's words, the time).
  const place = () => page.evaluate(() => { const r = document.getElementById('view').getBoundingClientRect(); return [r.left, r.top, r.width, r.height]; });
  const before = await place();
  const [x0, y0] = await screenOf(page, 0.5, 0.2, 0);
  const [x1, y1] = await screenOf(page, 0.8, 0.5, 0);
  await page.mouse.move(x0, y0);
  await page.mouse.down();
  await page.mouse.move((x0 + x1) / 2, (y0 + y1) / 2, { steps: 3 });
  await page.mouse.move(x1, y1, { steps: 3 });
  await page.mouse.up();
  await page.waitForFunction(() => mpm.hand?.done && mpm.hand.measured, null, { timeout: 10_000 });
  const r = await page.evaluate(() => mpm.hand.reading);
  assert.deepEqual(await place(), before, 'the view stayed where the drag was aimed');
  assert.ok(Math.abs(r.length - 0.3 * Math.SQRT2) < 0.01, `length ${r.length}`);
  assert.ok(Math.abs(r.inclination - 45) < 1, `angle ${r.inclination}`);
  await page.waitForFunction(() => mpm.overlay.labels.some((l) => l.kind === 'hand'), null, { timeout: 5000 });
  assert.equal(await page.evaluate(() => mpm.sim.bodies), 1, 'a measuring drag drops nothing');
  assert.deepEqual(errors, []);
  await page.close();
});

test('an inspected sand particle gets its Mohr circles: one in plane strain, three in 3D, with the Mohr–Coulomb envelope', async () => {
  for (const [hash, dim] of [['#lesson=stress_path', 2], ['#scene=column_collapse&dim=3', 3]]) {
    const { page, errors } = await open(hash);
    if ((await page.getAttribute('#toggle-plots', 'aria-pressed')) === 'false') await page.click('#toggle-plots');
    if (dim === 3) {
      await page.evaluate(async () => mpm.setProbe(await mpm.session.pick([0.5, 0.05, 0.5])));
    }
    await page.waitForFunction(() => mpm.probeId !== null && mpm.mohrPlot.drawn, null, { timeout: 30_000 });
    const drawn = await page.evaluate(() => ({ ...mpm.mohrPlot.drawn, principal: mpm.mohrPlot.point.principal }));
    assert.equal(drawn.circles, dim === 2 ? 1 : 3, `${hash}: ${JSON.stringify(drawn)}`);
    assert.equal(drawn.envelope, true, 'sand: the Mohr–Coulomb envelope');
    assert.equal(drawn.cone, dim === 2 ? 'line' : 'circle', 'the cone\'s trace');
    assert.equal(drawn.principal.length, 3);
    assert.ok(await page.isVisible('#mohr'));
    if (dim === 2) await (await page.$('#mohr')).screenshot({ path: join(OUT, 'mohr-2d.png') });
    assert.deepEqual(errors, []);
    await page.close();
  }
});

test('an inspected Mohr–Coulomb particle gets its own envelope, at its friction angle, and no cone', async () => {
  const { page, errors } = await open('#lesson=mohr_coulomb');
  if ((await page.getAttribute('#toggle-plots', 'aria-pressed')) === 'false') await page.click('#toggle-plots');
  await page.evaluate(async () => mpm.setProbe(await mpm.session.pick([1.5, 0.05])));
  await page.waitForFunction(() => mpm.probeId !== null && mpm.mohrPlot.drawn, null, { timeout: 30_000 });
  const drawn = await page.evaluate(() => ({ ...mpm.mohrPlot.drawn, model: mpm.mohrPlot.point.model }));
  assert.equal(drawn.model, 'mohr_coulomb', JSON.stringify(drawn));
  assert.equal(drawn.envelope, true, 'the Mohr–Coulomb envelope');
  assert.equal(drawn.angle, 40, 'at the material\'s own φ');
  assert.equal(drawn.cone, null, 'no Drucker–Prager cone');
  assert.deepEqual(errors, []);
  await page.close();
});
