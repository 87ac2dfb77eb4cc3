// The page in a classroom, in headless Chromium (Debian's package through playwright-core):
// every lesson opens from its link and runs; a saved scene opens again with its dropped body
// entering at its time; bad scene files get the solver's message naming the field, on the page;
// the recorder makes a WebM video and the snapshot a PNG of the view; on a phone and a tablet
// (touch, mobile viewports) the view stays visible and uncovered, a tap drops, a pinch zooms,
// and the plots never cover the view at any width. Served by `cargo xtask test` (MPM_URL).
//
//   MPM_URL=http://127.0.0.1:8080/ node --test www/tests/classroom.test.mjs
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { mkdirSync, readFileSync, readdirSync } from 'node:fs';
import { join } from 'node:path';
import { launch, launchBrowser, openPage } from './browser.mjs';
import { decodePng, pixelStats } from './png.mjs';
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

const open = (hash = '', init) => openPage(browser.context, URL_ROOT + hash, init);

/// Resolves after two animation frames: the layout after a change and a frame drawn on it.
const settled = (page) => page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));

/// Waits until the simulated time passes `t` + `dt`.
const advanced = (page, t, dt = 0.02) => page.waitForFunction(([t, dt]) => mpm.simTime > t + dt, [t, dt], { timeout: 60_000 });

/// The page's rectangle of element `selector` ({x, y, width, height}), or null if not shown.
const rectOf = (page, selector) => page.evaluate((s) => {
  const e = document.querySelector(s);
  const r = e?.getBoundingClientRect();
  return r && r.width > 0 && r.height > 0 ? { x: r.x, y: r.y, width: r.width, height: r.height } : null;
}, selector);

const overlap = (a, b) => Math.max(0, Math.min(a.x + a.width, b.x + b.width) - Math.max(a.x, b.x)) *
  Math.max(0, Math.min(a.y + a.height, b.y + b.height) - Math.max(a.y, b.y));

/// Checks that the view is on screen, at least `minShare` of the viewport's height, and that
/// no panel, lesson caption or header covers any of it; the element at its centre is itself.
async function assertViewUncovered(page, what, minShare = 0.35) {
  const view = await rectOf(page, '#view');
  const vp = page.viewportSize();
  assert.ok(view, `${what}: the view is shown`);
  assert.ok(view.x >= -1 && view.x + view.width <= vp.width + 1 && view.y >= 0 && view.y + view.height / 2 < vp.height,
    `${what}: the view ${JSON.stringify(view)} lies in the viewport ${vp.width}×${vp.height}`);
  assert.ok(view.height >= minShare * vp.height && view.width >= 0.5 * vp.width, `${what}: the view is large enough: ${JSON.stringify(view)}`);
  const centre = await page.evaluate(({ x, y, width, height }) => document.elementFromPoint(x + width / 2, y + height / 2)?.id, view);
  assert.equal(centre, 'view', `${what}: the element at the view's centre`);
  for (const s of ['header', '#lesson', '.panel.plots', '.panel.controls']) {
    const r = await rectOf(page, s);
    if (r) assert.equal(overlap(r, view), 0, `${what}: ${s} ${JSON.stringify(r)} covers the view ${JSON.stringify(view)}`);
  }
}

// --- lessons ---------------------------------------------------------------------------------

const ALL_LESSONS = readdirSync('lessons').filter((f) => f.endsWith('.json')).sort()
  .map((f) => ({ id: f.replace(/\.json$/, ''), ...JSON.parse(readFileSync(join('lessons', f), 'utf8')) }));
// The soil-lab lessons (`lab`) run in the Lab panel: www/tests/lab.test.mjs opens and answers them.
const LESSONS = ALL_LESSONS.filter((l) => !l.lab);

test('every lesson opens from its link, shows its caption and sliders in its view, and runs', async () => {
  const listed = await (await fetch(`${URL_ROOT}www/pkg/lessons.json`)).json();
  assert.deepEqual(listed.map((l) => l.id), ALL_LESSONS.map((l) => l.id), 'the build lists every lesson');
  assert.ok(LESSONS.length >= 5);
  for (const lesson of LESSONS) {
    const { page, errors } = await open(`#lesson=${lesson.id}`);
    const what = `lesson ${lesson.id}`;
    await page.waitForFunction((id) => mpm.lesson?.id === id, lesson.id, { timeout: 30_000 });
    assert.equal(await page.textContent('#lesson-title'), lesson.title, what);
    assert.equal(await page.textContent('#lesson-caption'), lesson.caption, what);
    assert.ok(await page.isVisible('#lesson-caption'), `${what}: the caption is shown`);
    const view = lesson.view;
    assert.equal(await page.evaluate(() => mpm.view.colour), view.colour ?? 'body', `${what}: its colours`);
    assert.equal(await page.getAttribute('#toggle-plots', 'aria-pressed'), String(view.plot !== 'none'), `${what}: its plot`);
    // Its sliders, showing the values of its scene.
    const sliders = await page.$$eval('#lesson-params [data-param]', (els) => els.map((e) => e.dataset.param));
    assert.deepEqual(sliders, view.params, `${what}: its sliders`);
    const values = await page.$$eval('#lesson-params [data-param-value]', (els) => els.map((e) => e.value));
    assert.ok(values.every((v) => v !== '' && v !== 'NaN'), `${what}: slider values ${values}`);
    if (view.inspect) await page.waitForFunction(() => mpm.probeId !== null, null, { timeout: 10_000 });
    // The scene is the lesson's and it runs.
    const scene = await page.evaluate(() => mpm.sim.scene);
    assert.equal(scene.dim, typeof lesson.scene === 'object' ? lesson.scene.dim : scene.dim);
    if (typeof lesson.scene === 'object') assert.equal(scene.bodies.length, lesson.scene.bodies.length, what);
    // Every lesson waits for Play: not a step before the reader starts it.
    await page.waitForTimeout(300);
    assert.deepEqual(await page.evaluate(() => [mpm.playing, mpm.simTime]), [false, 0], `${what}: opens paused`);
    await page.click('#play');
    const t0 = await page.evaluate(() => mpm.simTime);
    await advanced(page, t0, 0.05);
    const s = await page.evaluate(() => ({ failure: mpm.sim.failure, hash: location.hash }));
    assert.equal(s.failure, '', `${what}: no failure`);
    assert.match(s.hash, new RegExp(`^#lesson=${lesson.id}&`), `${what}: the link names the lesson`);
    assert.doesNotMatch(s.hash, /scene=/, `${what}: the link names no other scene`);
    if (lesson.id === LESSONS[0].id) await page.screenshot({ path: join(OUT, `lesson-${lesson.id}.png`) });
    await assertViewUncovered(page, what, 0.3);
    assert.deepEqual(errors, [], `${what}: no console error`);
    await page.close();
  }
});

test('the Lessons menu opens a lesson; its sliders set one body and go in the link; the caption closes', async () => {
  const { page, errors } = await open('#scene=www/test-scenes/drop_2d.json');
  const lesson = LESSONS.find((l) => l.id === 'friction_angle');
  await page.selectOption('#lessons', 'friction_angle');
  await page.waitForFunction(() => mpm.lesson?.id === 'friction_angle' && /^#lesson=friction_angle/.test(location.hash), null, { timeout: 30_000 });
  assert.equal(await page.inputValue('#scene'), 'lesson:friction_angle', 'the scene picker names the lesson');
  // The second column's friction angle, typed into the lesson's slider.
  const name = lesson.view.params[1];
  assert.equal(name, 'bodies[1].drucker_prager.friction_angle');
  await page.fill(`#lesson-params [data-param-value="${name}"]`, '30');
  await page.press(`#lesson-params [data-param-value="${name}"]`, 'Enter');
  await page.waitForFunction(() => mpm.sim.scene.bodies[1].material.drucker_prager.friction_angle === 30
    && /bodies\[1\]\.drucker_prager\.friction_angle=30/.test(decodeURIComponent(location.hash)), null, { timeout: 10_000 });
  const bodies = await page.evaluate(() => mpm.sim.scene.bodies.filter((b) => b.material.drucker_prager).map((b) => b.material.drucker_prager.friction_angle));
  assert.deepEqual(bodies, [20, 30], 'only that body changed (the lifted walls are elastic)');
  const hash = await page.evaluate(() => location.hash);
  assert.match(decodeURIComponent(hash), /bodies\[1\]\.drucker_prager\.friction_angle=30/);
  // The caption, beside the view, closes; the view stays as it was, the plots move up.
  const before = await rectOf(page, '#view');
  await page.click('#lesson-close');
  await page.waitForFunction(() => document.getElementById('lesson').hidden);
  await settled(page);
  const after = await rectOf(page, '#view');
  assert.ok(after.height >= before.height && after.width >= before.width, `the view kept its place: ${JSON.stringify([before, after])}`);
  assert.deepEqual(errors, []);
  await page.close();
  // The link opens the lesson with that body's angle.
  const again = await open(hash);
  await again.page.waitForFunction(() => mpm.lesson?.id === 'friction_angle', null, { timeout: 30_000 });
  assert.deepEqual(await again.page.evaluate(() => mpm.sim.scene.bodies.filter((b) => b.material.drucker_prager).map((b) => b.material.drucker_prager.friction_angle)), [20, 30]);
  assert.equal(await again.page.inputValue(`#lesson-params [data-param-value="${name}"]`), '30');
  // Another scene leaves the lesson.
  await again.page.selectOption('#scene', 'column_collapse');
  await again.page.waitForFunction(() => !mpm.lesson && document.getElementById('lesson').hidden && /scene=column_collapse/.test(location.hash), null, { timeout: 30_000 });
  assert.deepEqual(again.errors, []);
  await again.page.close();
});

const SCENES = readdirSync('scenes').filter((f) => f.endsWith('.json')).sort()
  .map((f) => ({ base: f.replace(/_[23]d\.json$/, ''), dim: JSON.parse(readFileSync(join('scenes', f), 'utf8')).dim }));

/// What a lesson just opened shows: whether it was judged, its plots' and notes' sources.
const lessonStart = (page) => page.evaluate(() => {
  const q = mpm.lessonPanel;
  return {
    id: mpm.lesson?.id, playing: mpm.playing, time: mpm.simTime, answer: q.answer,
    verdict: document.getElementById('lesson-verdict')?.textContent ?? null,
    marked: document.querySelectorAll('#lesson-question [data-choice].answer, #lesson-question [aria-pressed=true]').length,
    energyRef: mpm.energyPlot.ref?.time ?? null, energyTimes: mpm.energyPlot.samples.map((s) => s.time),
    dissipated: mpm.energyPlot.samples.map((s) => s.dissipated),
    probe: mpm.probeId, stressId: mpm.stressPlot.point?.id ?? null, mohrId: mpm.mohrPlot.point?.id ?? null,
    note: document.getElementById('pq-note').textContent,
    frameGeneration: mpm.frame?.generation ?? null, generation: mpm.session.generation,
  };
});

/// Asserts that lesson `lesson` just opened after `what` starts afresh: unjudged (paused at
/// its start, no choice marked, the prompt to predict) when it asks first; its energy plot from
/// its own start (dissipation from zero); the stress path and note of its own particle or none.
async function assertFreshLesson(page, lesson, what) {
  // the lesson's first frame drawn, and every message the host sent before it answers a
  // request made now (a frame of the scene before could only come before that answer, in order)
  await page.waitForFunction(() => mpm.frame && mpm.frame.generation === mpm.session.generation, null, { timeout: 30_000 });
  if (lesson.view.inspect) await page.waitForFunction(() => mpm.probeId !== null, null, { timeout: 10_000 });
  await page.evaluate(() => mpm.session.values([]));
  await settled(page);
  const s = await lessonStart(page);
  const at = `${lesson.id} after ${what}: ${JSON.stringify(s)}`;
  assert.equal(s.id, lesson.id, at);
  assert.ok(s.frameGeneration === null || s.frameGeneration === s.generation, `the frame shown is the lesson's: ${at}`);
  // every lesson waits for Play at its start
  assert.equal(s.playing, false, `waits for Play: ${at}`);
  assert.ok(s.time < 0.05, `at its start: ${at}`);
  if (lesson.question) {
    assert.equal(s.answer, null, `not judged: ${at}`);
    assert.equal(s.marked, 0, `no choice marked: ${at}`);
    assert.match(s.verdict, /^Predict first/, at);
  }
  if (s.energyRef !== null) assert.ok(s.energyRef < 0.5, `the energy plot counts from the lesson's start: ${at}`);
  assert.ok(s.energyTimes.every((t) => t >= 0 && t < 1), at);
  // (from zero: rounding leaves it within a few mJ of it; counted from the scene before, tens of J)
  assert.ok(s.dissipated.every((d) => d > -0.05), `dissipation counts from zero: ${at}`);
  if (lesson.view.inspect) {
    for (const id of [s.stressId, s.mohrId]) assert.ok(id === null || id === s.probe, `its own particle's plots: ${at}`);
    assert.ok(s.note === '' || s.note.startsWith(`particle #${s.probe} `), `its own particle's note: ${at}`);
  } else {
    assert.equal(s.probe, null, at);
    assert.equal(s.stressId, null, `no stress path: ${at}`);
    assert.equal(s.mohrId, null, `no Mohr circles: ${at}`);
    assert.equal(s.note, '', `no p–q note: ${at}`);
  }
}

test('a lesson opened from the menu after any shipped scene or lesson starts unjudged, with its own plots and notes', async () => {
  const { page, errors } = await open('#scene=sandbox&dim=2&drop=0:box:von_mises:0.2:0.5,0.2');
  // The column collapse judges itself at 1.5 s: the scene before it runs past that.
  const order = [...LESSONS].sort((a, b) => (b.id === 'column_collapse') - (a.id === 'column_collapse'));
  for (const scene of SCENES) {
    const what = `${scene.base} (${scene.dim}D)`;
    for (const [k, lesson] of order.entries()) {
      const g = await page.evaluate((h) => { location.hash = h; return mpm.session.generation; }, `#scene=${scene.base}&dim=${scene.dim}`);
      await page.waitForFunction((g) => mpm.session.generation > g && !mpm.lesson && mpm.frame?.generation === mpm.session.generation, g, { timeout: 30_000 });
      await page.evaluate(() => { if (!mpm.playing) mpm.setPlaying(true); });
      // an inspected particle of the scene, whose path and note must not carry over
      await page.evaluate(async () => mpm.setProbe(await mpm.session.pick(mpm.domain.map((x) => x / 2))));
      await page.waitForFunction((t) => mpm.simTime > t, k === 0 ? 1.6 : 0.2, { timeout: 120_000 });
      await page.selectOption('#lessons', lesson.id);
      await page.waitForFunction((id) => mpm.lesson?.id === id, lesson.id, { timeout: 30_000 });
      await assertFreshLesson(page, lesson, what);
    }
  }
  // Lesson after lesson, each run for a while first (a question's lesson with a choice made).
  let previous = LESSONS[LESSONS.length - 1];
  await page.selectOption('#lessons', previous.id);
  await page.waitForFunction((id) => mpm.lesson?.id === id, previous.id, { timeout: 30_000 });
  for (const lesson of LESSONS) {
    if (previous.question) await page.click('#lesson-question [data-choice="0"]');
    await page.click('#play');
    await page.waitForFunction(() => mpm.simTime > 0.3, null, { timeout: 60_000 });
    await page.selectOption('#lessons', lesson.id);
    await page.waitForFunction((id) => mpm.lesson?.id === id && mpm.simTime < 0.3, lesson.id, { timeout: 30_000 });
    await assertFreshLesson(page, lesson, `lesson ${previous.id}`);
    previous = lesson;
  }
  assert.deepEqual(errors, []);
  await page.close();
});

test('a lesson the solver refuses shows its message naming the field', async () => {
  const page = await browser.context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.route('**/lessons/pic_flip.json', async (route) => {
    const lesson = JSON.parse(readFileSync('lessons/pic_flip.json', 'utf8'));
    lesson.view.params[0] = 'von_mises.yield_stress';
    await route.fulfill({ contentType: 'application/json', body: JSON.stringify(lesson) });
  });
  await page.goto(`${URL_ROOT}#lesson=pic_flip`);
  await page.waitForSelector('#banners .banner.bad', { timeout: 60_000 });
  const msg = await page.textContent('#banners .banner.bad');
  assert.match(msg, /lessons\/pic_flip\.json: view\.params\[0\] = von_mises\.yield_stress: does not apply/, msg);
  assert.equal(await page.evaluate(() => mpm.lesson), null);
  assert.match(msg, /Showing the default scene/, msg);
  // The banner shows first; the default scene loads after it and then writes the link.
  await page.waitForFunction(() => /^#scene=bunny_on_sand_heap/.test(location.hash), null, { timeout: 30_000 })
    .catch(async () => assert.fail(`the default scene instead: ${await page.evaluate(() => location.hash)}`));
  assert.deepEqual(errors, []);
  await page.close();
});

// --- save and open ---------------------------------------------------------------------------

/// A scene file (name, text) to drop on the view, with `files` [{name, text}] alongside, as a
/// user's drag and drop does.
async function dropFiles(page, files) {
  await page.evaluate((files) => {
    const dt = new DataTransfer();
    for (const f of files) dt.items.add(new File([f.text], f.name, { type: f.name.endsWith('.json') ? 'application/json' : 'text/plain' }));
    const stage = document.querySelector('.stage');
    stage.dispatchEvent(new DragEvent('dragover', { dataTransfer: dt, bubbles: true, cancelable: true }));
    stage.dispatchEvent(new DragEvent('drop', { dataTransfer: dt, bubbles: true, cancelable: true }));
  }, files);
}

test('Save downloads the demo as a scene file; opened again, the dropped bunny enters at its time', async () => {
  // A ball of the link at 0 s, then a bunny dropped by a click.
  const { page, errors } = await open('#scene=sandbox&dim=3&drop=0:ball:elastic:0.2:0.5,0.3,0.5');
  await page.click('#objects button[data-id="bunny"]');
  await page.click('#materials button[data-id="elastic"]');
  await advanced(page, 0, 0.15);
  const [x2, y2] = await screenOf(page, 1.5, 0, 0.5);
  await page.mouse.click(x2, y2);
  await page.waitForFunction(() => mpm.sim.bodies === 2, null, { timeout: 10_000 });
  const dropT = await page.evaluate(() => mpm.drops[1].t);
  assert.ok(dropT > 0.1, `the second drop at ${dropT} s`);
  await advanced(page, dropT, 0.05);
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#save')]);
  const name = download.suggestedFilename();
  assert.match(name, /^sandbox-t\d+\.\d\ds\.json$/, 'named after the scene and the simulated time');
  const path = join(OUT, name);
  await download.saveAs(path);
  const saved = JSON.parse(readFileSync(path, 'utf8'));
  assert.equal(saved.bodies.length, 2);
  assert.equal(saved.bodies[0].appear_at, undefined, 'the first drop entered at 0 s');
  assert.ok(Math.abs(saved.bodies[1].appear_at - dropT) < 1e-9, `the second enters at its drop time: ${saved.bodies[1].appear_at}`);
  assert.ok('ball' in saved.bodies[0].shape);
  assert.ok(JSON.stringify(saved.bodies[1].shape).includes('bunny.obj'), 'the bunny is the shipped mesh');
  await page.close();

  // Opened from the file picker, without bunny.obj beside it: the shipped mesh is taken.
  const again = await open('#scene=column_collapse&dim=2');
  await again.page.setInputFiles('#open-file', path);
  await again.page.waitForFunction((n) => mpm.view.scene === `file:${n}`, name, { timeout: 30_000 });
  const opened = await again.page.evaluate(() => ({ scene: mpm.sim.scene, hash: location.hash, option: document.getElementById('scene').value }));
  assert.equal(opened.scene.dim, 3);
  assert.equal(opened.scene.bodies.length, 2, 'both bodies, the second still to come');
  assert.ok(Math.abs(opened.scene.bodies[1].appear_at - dropT) < 1e-9);
  assert.equal(opened.option, `file:${name}`, 'the scene picker names the file');
  // Before its time only the ball is there; after it, the bunny too.
  const first = await again.page.evaluate(() => mpm.particleCount);
  await again.page.waitForFunction((t) => mpm.simTime > t + 0.02, dropT, { timeout: 60_000 });
  const both = await again.page.evaluate(() => mpm.particleCount);
  assert.ok(both > 1.5 * first, `the bunny entered: ${first} → ${both} particles`);
  assert.deepEqual([...errors, ...again.errors], []);
  await again.page.close();
});

test('Open takes outlines dropped with the scene; bad files get the message naming the field, on the page', async () => {
  const { page, errors } = await open('#scene=www/test-scenes/drop_2d.json');
  const scene = {
    name: 'square on the floor (2D)', dim: 2, domain: { size: [1, 0.6] }, cell_size: 0.02,
    bodies: [{ name: 'square', shape: { polygon: { path: 'outlines/square.txt', translate: [0.5, 0.0] } },
      material: { elastic: { youngs_modulus: 1e5, poisson_ratio: 0.3, density: 1000 } } }],
  };
  const square = '# a square\n-0.1 0\n0.1 0\n0.1 0.2\n-0.1 0.2\n';
  const shown = async () => {
    await page.waitForSelector('#banners .banner.bad', { timeout: 10_000 });
    return page.textContent('#banners .banner.bad');
  };
  const before = await page.evaluate(() => mpm.sim.scene.name);

  // The outline missing: named, and the simulation goes on as it was.
  await dropFiles(page, [{ name: 'square.json', text: JSON.stringify(scene) }]);
  assert.match(await shown(), /Cannot open square\.json: it references outlines\/square\.txt/);
  assert.equal(await page.evaluate(() => mpm.sim.scene.name), before);

  // A field out of range: the solver's message, with the field's path and the allowed range.
  const bad = structuredClone(scene);
  bad.bodies[0].material.elastic.poisson_ratio = 0.7;
  await page.click('#banners .banner.bad button');
  await dropFiles(page, [{ name: 'bad.json', text: JSON.stringify(bad) }, { name: 'square.txt', text: square }]);
  const msg = await shown();
  assert.match(msg, /Cannot open bad\.json: bodies\[0\]\.material\.elastic\.poisson_ratio = 0\.7: must be in/, msg);
  assert.equal(await page.evaluate(() => mpm.sim.scene.name), before);
  await page.screenshot({ path: join(OUT, 'open-bad-file.png') });

  // Not a scene at all: the parser's message names where.
  await page.click('#banners .banner.bad button');
  await dropFiles(page, [{ name: 'typo.json', text: '{"dim": 2, "domain": {"size": [1, 1]}, "cell_size": 0.02, "bodys": []}' }]);
  assert.match(await shown(), /Cannot open typo\.json: .*bodys/);
  await page.click('#banners .banner.bad button');

  // With the outline alongside, it opens.
  await dropFiles(page, [{ name: 'square.json', text: JSON.stringify(scene) }, { name: 'square.txt', text: square }]);
  await page.waitForFunction(() => mpm.view.scene === 'file:square.json', null, { timeout: 30_000 });
  const s = await page.evaluate(() => ({ name: mpm.sim.scene.name, bodies: mpm.sim.bodies, particles: mpm.sim.particles, banner: document.querySelector('#banners .banner.bad') }));
  assert.equal(s.name, scene.name);
  assert.ok(s.bodies === 1 && s.particles > 100, JSON.stringify(s));
  assert.equal(s.banner, null, 'no error shown');
  const t = await page.evaluate(() => mpm.simTime);
  await advanced(page, t);
  assert.deepEqual(errors, []);
  await page.close();
});

// --- recording -------------------------------------------------------------------------------

/// An init script that records the type and size of every blob given a URL (downloads).
function watchBlobs() {
  const make = URL.createObjectURL;
  window.blobs = [];
  URL.createObjectURL = (b) => {
    if (b instanceof Blob) window.blobs.push({ type: b.type, size: b.size });
    return make.call(URL, b);
  };
}

test('Record makes a WebM video of the view and Snapshot a PNG of its size, named after the scene and time', async () => {
  const { page, errors } = await open('#scene=www/test-scenes/drop_2d.json', watchBlobs);
  await page.evaluate(() => { mpm.fixedQuality = true; }); // the canvas keeps its resolution
  await page.click('#record');
  assert.equal(await page.getAttribute('#record', 'aria-pressed'), 'true');
  const t0 = await page.evaluate(() => mpm.simTime);
  await advanced(page, t0, 0.3);
  // some frames filmed
  const f0 = await page.evaluate(() => mpm.stats.frames);
  await page.waitForFunction((f0) => mpm.stats.frames > f0 + 10, f0, { timeout: 30_000 });
  const [video] = await Promise.all([page.waitForEvent('download', { timeout: 20_000 }), page.click('#record')]);
  assert.match(video.suggestedFilename(), /^test-sand-block-jelly-box-and-plastic-ball-2d-t\d+\.\d\d-\d+\.\d\ds\.webm$/);
  const path = join(OUT, 'recording.webm');
  await video.saveAs(path);
  const bytes = readFileSync(path);
  assert.ok(bytes.length > 2000, `a non-empty video: ${bytes.length} bytes`);
  assert.equal(bytes.readUInt32BE(0), 0x1a45dfa3, 'a Matroska/WebM (EBML) file');
  assert.ok(bytes.includes(Buffer.from('webm')), 'its doctype is webm');
  const blob = await page.evaluate(() => window.blobs.at(-1));
  assert.equal(blob.type, 'video/webm');
  assert.equal(blob.size, bytes.length);

  const [shot] = await Promise.all([page.waitForEvent('download', { timeout: 20_000 }), page.click('#snapshot')]);
  assert.match(shot.suggestedFilename(), /^test-sand-block-jelly-box-and-plastic-ball-2d-t\d+\.\d\ds\.png$/);
  const pngPath = join(OUT, 'snapshot.png');
  await shot.saveAs(pngPath);
  const png = decodePng(readFileSync(pngPath));
  const size = await page.evaluate(() => [document.getElementById('view').width, document.getElementById('view').height]);
  assert.deepEqual([png.width, png.height], size, 'the canvas\' size');
  const px = pixelStats(png);
  assert.ok(px.variance > 50 && px.colours > 10, `the particles are in it: ${JSON.stringify(px)}`);
  assert.equal((await page.evaluate(() => window.blobs.at(-1))).type, 'image/png');
  assert.deepEqual(errors, []);
  await page.close();
});

// --- touch and small screens -----------------------------------------------------------------

/// Two fingers from `from` [[x, y], [x, y]] to `to` in `steps` moves (CDP touch events, which
/// the page receives as pointer events).
async function pinch(page, from, to, steps = 8) {
  const cdp = await page.context().newCDPSession(page);
  const at = (k) => from.map(([x, y], i) => ({ x: x + (k / steps) * (to[i][0] - x), y: y + (k / steps) * (to[i][1] - y), id: i }));
  await cdp.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: at(0) });
  for (let k = 1; k <= steps; k++) await cdp.send('Input.dispatchTouchEvent', { type: 'touchMove', touchPoints: at(k) });
  await cdp.send('Input.dispatchTouchEvent', { type: 'touchEnd', touchPoints: [] });
  await cdp.detach();
}

for (const [width, height] of [[390, 844], [768, 1024]]) {
  test(`touch, ${width}×${height}: the view is visible and uncovered, a tap drops, a pinch zooms, one finger turns, Plots and the lesson stay clear`, async () => {
    touchBrowser ??= await launchBrowser();
    const context = await touchBrowser.newContext({ viewport: { width, height }, hasTouch: true, isMobile: true, deviceScaleFactor: 2 });
    const { page, errors } = await openPage(context, `${URL_ROOT}#scene=sandbox&dim=2&drop=0:box:von_mises:0.2:0.3,0.2`);
    await assertViewUncovered(page, 'sandbox');
    assert.equal(await page.evaluate(() => document.documentElement.scrollWidth), width, 'no sideways scrolling');
    // The controls below the view start folded but for the first card; a heading unfolds one.
    assert.equal(await page.isVisible('#world-params'), false, 'the World card is folded');
    await page.tap('.panel.controls .card:has(#world-params) h2 button');
    assert.equal(await page.isVisible('#world-params'), true);
    await page.evaluate(() => window.scrollTo(0, 0));

    // A tap in the box drops a ball.
    await page.tap('#objects button[data-id="ball"]');
    await page.evaluate(() => window.scrollTo(0, 0));
    const [x, y] = await screenOf(page, 1.0, 0.5, 0);
    await page.touchscreen.tap(x, y);
    await page.waitForFunction(() => mpm.sim.bodies === 2 && /drop=[\d.]+:ball:/.test(location.hash), null, { timeout: 10_000 });

    // Two fingers spreading zoom in; closing, out.
    const view = await rectOf(page, '#view');
    const cx = view.x + view.width / 2, cy = view.y + view.height / 2;
    const z0 = await page.evaluate(() => mpm.camera.zoom2d);
    await pinch(page, [[cx - 40, cy], [cx + 40, cy]], [[cx - 100, cy], [cx + 100, cy]]);
    const z1 = await page.evaluate(() => mpm.camera.zoom2d);
    assert.ok(Math.abs(z1 / z0 - 2.5) < 0.05, `spread 80 → 200 px zooms in 2.5×: ${z0} → ${z1}`);
    await pinch(page, [[cx - 100, cy], [cx + 100, cy]], [[cx - 50, cy], [cx + 50, cy]]);
    const z2 = await page.evaluate(() => mpm.camera.zoom2d);
    assert.ok(Math.abs(z2 / z1 - 0.5) < 0.05, `closing 200 → 100 px zooms out 2×: ${z1} → ${z2}`);
    assert.equal(await page.evaluate(() => mpm.sim.bodies), 2, 'a pinch drops nothing');

    // Plots: beneath the view, never over it.
    await page.tap('#toggle-plots');
    assert.equal(await page.getAttribute('#toggle-plots', 'aria-pressed'), 'true');
    assert.ok(await rectOf(page, '.panel.plots'), 'the plots are shown');
    await assertViewUncovered(page, 'plots shown');
    // The header's other controls unfold from More, above the view.
    assert.equal(await page.isVisible('#save'), false);
    await page.tap('#more');
    assert.equal(await page.isVisible('#save'), true);
    await assertViewUncovered(page, 'More unfolded', 0.3);
    await page.screenshot({ path: join(OUT, `touch-${width}.png`) });

    // 3D: one finger turns the view, a tap drops on the floor.
    await page.evaluate(() => { location.hash = '#scene=sandbox&dim=3'; });
    await page.waitForFunction(() => mpm.domain.length === 3 && mpm.sim.bodies === 0, null, { timeout: 30_000 });
    await page.evaluate(() => window.scrollTo(0, 0));
    const v3 = await rectOf(page, '#view');
    const yaw = await page.evaluate(() => mpm.camera.yaw);
    const cdp = await context.newCDPSession(page);
    const [sx, sy] = [v3.x + v3.width / 2, v3.y + v3.height / 2];
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: [{ x: sx, y: sy, id: 0 }] });
    for (let k = 1; k <= 6; k++) await cdp.send('Input.dispatchTouchEvent', { type: 'touchMove', touchPoints: [{ x: sx + 12 * k, y: sy, id: 0 }] });
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchEnd', touchPoints: [] });
    await cdp.detach();
    const yaw1 = await page.evaluate(() => mpm.camera.yaw);
    assert.ok(Math.abs(yaw1 - yaw) > 0.1, `one finger turned the view: yaw ${yaw} → ${yaw1}`);
    assert.equal(await page.evaluate(() => mpm.sim.bodies), 0, 'a drag drops nothing');
    const [fx, fy] = await screenOf(page, 1.0, 0, 0.5);
    await page.touchscreen.tap(fx, fy);
    await page.waitForFunction(() => mpm.sim.bodies === 1, null, { timeout: 10_000 });

    // A lesson: its caption below the view, the view still clear and on the first screen.
    await page.evaluate(() => { location.hash = '#lesson=yield_stress'; });
    await page.waitForFunction(() => mpm.lesson?.id === 'yield_stress', null, { timeout: 30_000 });
    await page.evaluate(() => window.scrollTo(0, 0));
    assert.ok(await page.isVisible('#lesson-caption'));
    await assertViewUncovered(page, 'lesson', 0.3);
    await page.screenshot({ path: join(OUT, `touch-${width}-lesson.png`) });
    assert.deepEqual(errors, []);
    await context.close();
  });
}

test('at desktop widths the plots never cover the view', async () => {
  const { page, errors } = await open('#scene=www/test-scenes/drop_2d.json');
  for (const [width, height] of [[1920, 1080], [1400, 860], [1100, 800], [960, 700]]) {
    await page.setViewportSize({ width, height });
    if ((await page.getAttribute('#toggle-plots', 'aria-pressed')) === 'false') await page.click('#toggle-plots');
    await settled(page);
    assert.ok(await rectOf(page, '.panel.plots'), `${width}: the plots are shown`);
    await assertViewUncovered(page, `${width}×${height}, plots shown`, 0.5);
    await page.click('#toggle-plots');
    await settled(page);
    assert.equal(await rectOf(page, '.panel.plots'), null, `${width}: the plots are hidden`);
    await assertViewUncovered(page, `${width}×${height}, plots hidden`, 0.5);
  }
  assert.deepEqual(errors, []);
  await page.close();
});
