// End-to-end test of the playground in a real headless Chromium (Debian's package, driven by
// playwright-core). The page is served by `cargo xtask test` (MPM_URL); screenshots go to
// MPM_OUT (default target/e2e).
//
//   MPM_URL=http://127.0.0.1:8080/ node --test www/tests/e2e.test.mjs
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { mkdirSync, statSync } from 'node:fs';
import { join } from 'node:path';
import { launch, openPage } from './browser.mjs';
import { decodePng, pixelStats } from './png.mjs';
import { hideWebgl2, screenOf } from './view.mjs';

const URL_ROOT = process.env.MPM_URL || 'http://127.0.0.1:8080/';
const OUT = process.env.MPM_OUT || 'target/e2e';
mkdirSync(OUT, { recursive: true });

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

/// Opens the page with `hash` (see `openPage`).
const open = (hash = '', init) => openPage(browser.context, URL_ROOT + hash, init);

/// The body `i` of the simulated scene, as JSON text.
const bodyJson = (page, i) => page.evaluate((i) => JSON.stringify(mpm.sim.scene.bodies[i]), i);

/// What the page knows of the simulation (which steps in a worker, or on the page's thread).
const stats = (page) => page.evaluate(() => ({
  particles: mpm.sim.particles,
  bodies: mpm.sim.bodies,
  time: mpm.simTime,
  frames: mpm.stats.frames,
  hash: location.hash,
  renderer: mpm.renderer.kind,
  thread: mpm.session.kind,
  quality: mpm.sim.quality,
}));

/// Waits until the simulated time passes `t` + `dt`.
const advanced = (page, t, dt = 0.02) => page.waitForFunction(([t, dt]) => mpm.simTime > t + dt, [t, dt], { timeout: 60_000 });


/// Screenshot of the simulation view, with its pixel statistics.
async function viewShot(page, path) {
  const box = await page.locator('#view').boundingBox();
  const buf = await page.screenshot({ path, clip: box });
  return pixelStats(decodePng(buf));
}

test('3D: the default scene runs in a worker, a click drops a bunny, the friction slider changes the sand and the link', async () => {
  const { page, errors } = await open('');
  const s0 = await stats(page);
  assert.equal(s0.renderer, 'WebGL2');
  assert.equal(s0.thread, 'worker', 'the simulation steps in a Web Worker');
  assert.equal(s0.quality.quality, 'live', 'the default quality');
  assert.match(s0.hash, /quality=live/);
  // The picker lists every scene in scenes/ (2D and 3D files paired) and the sandbox.
  const options = await page.$$eval('#scene option', (o) => o.map((x) => x.value));
  for (const base of ['bunny_on_sand_heap', 'bunny_on_sand_ball', 'column_collapse', 'elastic_bunny', 'notched_sand_block', 'plastic_bunny', 'sandbox'])
    assert.ok(options.includes(base), `${base} in ${options}`);
  assert.equal(await page.inputValue('#scene'), 'bunny_on_sand_heap', 'a sand heap by default');
  assert.ok(s0.particles > 4_500 && s0.bodies === 2, JSON.stringify(s0));
  // Drop an elastic bunny (the shipped mesh) by clicking on the floor.
  await page.click('#objects button[data-id="bunny"]');
  await page.click('#materials button[data-id="elastic"]');
  const size = await page.evaluate(() => mpm.sim.scene.domain.size);
  let [x, y] = await screenOf(page, 0.8 * size[0], 0, 0.5 * size[2]);
  await page.mouse.click(x, y);
  await page.waitForFunction(() => mpm.sim.bodies === 3 && /drop=/.test(location.hash), null, { timeout: 10_000 });
  const s1 = await stats(page);
  assert.ok(s1.particles > s0.particles + 300, `particle count grew: ${s0.particles} → ${s1.particles}`);
  const shape = await page.evaluate(() => mpm.sim.scene.bodies[2].shape);
  assert.ok(await page.evaluate(() => mpm.sim.scene.bodies[2].particles_per_cell) >= s0.quality.particles_per_cell,
    'the dropped body takes the quality level\'s particles per cell (or more, to keep its shape)');
  assert.ok('mesh' in shape, `the dropped bunny is the mesh: ${JSON.stringify(shape).slice(0, 80)}`);
  // The link records the drop: simulated time, object, material, size, centre (no velocity).
  const m = s1.hash.match(/&drop=([\d.]+):bunny:elastic:([\d.]+):([\d.]+),([\d.]+),([\d.]+)$/);
  assert.ok(m, `the hash records the drop: ${s1.hash}`);
  const [t, dropSize, cx, , cz] = m.slice(1).map(Number);
  // Dropped at the simulation's time when the click arrived: after the frame on screen at the
  // click, at most a slice of stepping later.
  assert.ok(t > 0 && t >= s0.time - 1e-4, `dropped at ${t} s, after ${s0.time}`);
  await page.waitForFunction((t) => mpm.simTime >= t, t, { timeout: 10_000 });
  assert.equal(dropSize, await page.evaluate(() => +mpm.size.toPrecision(3)));
  assert.ok(Math.abs(cx - 0.8 * size[0]) < 0.03 && Math.abs(cz - 0.5 * size[2]) < 0.03, `dropped where clicked: ${m[0]}`);
  const dropped = await bodyJson(page, 2);
  await advanced(page, s1.time);

  // Move the friction-angle slider of the sand.
  await page.click('#materials button[data-id="drucker_prager"]');
  const slider = page.locator('input[type=range][data-param="drucker_prager.friction_angle"]');
  await slider.focus();
  for (let i = 0; i < 40; i++) await page.keyboard.press('ArrowLeft');
  // The page holds the slider's value once the simulation took it: every command the key
  // presses sent has been answered (they are applied in order).
  await page.waitForFunction(() => {
    const phi = mpm.sim.parameters['drucker_prager.friction_angle'];
    return mpm.session.waiting.size === 0 && phi < 35 && location.hash.includes(`friction_angle=${phi}`);
  }, null, { timeout: 10_000 });
  const phi = await page.evaluate(() => mpm.sim.parameters['drucker_prager.friction_angle']);
  assert.ok(phi < 35 && phi >= 0, `friction angle moved: ${phi}`);
  const scene = await page.evaluate(() => mpm.sim.scene);
  assert.equal(scene.bodies[0].material.drucker_prager.friction_angle, phi, 'the sand body got the new angle');
  const s2 = await stats(page);
  assert.notEqual(s2.hash, s0.hash, 'the URL hash changed');
  assert.match(decodeURIComponent(s2.hash), new RegExp(`drucker_prager\\.friction_angle=${phi}`));

  // A typed out-of-range value is refused with the scene-file message, state unchanged.
  const box = page.locator('input[data-param-value="drucker_prager.friction_angle"]');
  await box.fill('95');
  await box.press('Enter');
  const error = page.locator('.param:has([data-param="drucker_prager.friction_angle"]) .error');
  await page.waitForFunction(() => document.querySelector('.param:has([data-param="drucker_prager.friction_angle"]) .error').textContent !== '');
  assert.match(await error.textContent(), /friction_angle = 95: must be in \[0, 90\) \(degrees\)/);
  assert.equal(await page.evaluate(() => mpm.sim.parameters['drucker_prager.friction_angle']), phi);

  await advanced(page, s2.time);
  const s3 = await stats(page);
  assert.ok(s3.time > s1.time, `the simulation advanced: ${s1.time} → ${s3.time}`);
  assert.ok(s3.frames > s1.frames);

  // Inspect a particle: the p–q plot follows it.
  await page.click('#tool-inspect');
  [x, y] = await screenOf(page, 0.5 * size[0], 0.02, 0.5 * size[2]);
  const picked = await page.evaluate(() => mpm.probeId);
  await page.mouse.click(x, y);
  await page.waitForFunction(() => mpm.probeId !== null, null, { timeout: 10_000 }).catch(() => {});
  assert.notEqual(await page.evaluate(() => mpm.probeId), picked, 'a particle was picked');
  await page.waitForFunction(() => /drucker prager/.test(document.getElementById('pq-note').textContent), null, { timeout: 20_000 });

  const px = await viewShot(page, join(OUT, 'view-3d.png'));
  if ((await page.getAttribute('#toggle-plots', 'aria-pressed')) === 'false') await page.click('#toggle-plots');
  await page.waitForTimeout(500);
  const shot = join(OUT, 'playground-3d.png');
  await page.screenshot({ path: shot });
  assert.ok(statSync(shot).size > 20_000, 'the screenshot has content');
  assert.ok(px.variance > 50 && px.colours > 20, `the view is not blank: ${JSON.stringify(px)}`);
  assert.deepEqual(errors, [], 'no console error');
  await page.close();

  // The link of the moment after the drop drops the same bunny at the same simulated time.
  const again = await open(s1.hash);
  await again.page.waitForFunction(() => mpm.sim.bodies === 3, null, { timeout: 60_000 });
  const r = await stats(again.page);
  assert.equal(r.particles, s1.particles, 'the same particle count as where the link was taken');
  assert.equal(await bodyJson(again.page, 2), dropped, 'the same body');
  const appliedAt = await again.page.evaluate(() => mpm.drops[0].applied_at);
  assert.ok(Math.abs(appliedAt - t) < 1e-6, `dropped when the simulation reached ${t} s, not at ${appliedAt} s`);
  assert.equal(r.hash, s1.hash, 'the page keeps the link it was opened with');
  // Reset forgets the drops, in the page and in the link.
  await again.page.click('#reset');
  await again.page.waitForFunction(() => mpm.sim.bodies === 2 && !/drop=/.test(location.hash), null, { timeout: 10_000 });
  const r2 = await stats(again.page);
  assert.equal(r2.bodies, 2);
  assert.doesNotMatch(r2.hash, /drop=/);
  assert.deepEqual(again.errors, [], 'no console error');
  await again.page.close();
});

test('2D: a link reproduces the parameters and drops, malformed drops are warned about, a box drops where clicked', async () => {
  const bad = ['drop=ball:oops', 'drop=0:teapot:elastic:0.2:0.5,0.5', 'drop=0:ball:elastic:0.2:0.5,0.5,0.5'];
  const ball = 'drop=0:ball:elastic:0.2:0.5,0.5';
  const { page, errors, warnings } = await open(`#scene=sandbox&dim=2&gravity=3.5&elastic.youngs_modulus=20000&colour=speed&${bad.join('&')}&${ball}`);
  assert.equal(await page.evaluate(() => mpm.sim.parameters.gravity), 3.5);
  assert.equal(await page.evaluate(() => mpm.sim.parameters['elastic.youngs_modulus']), 20000);
  for (const entry of bad) assert.ok(warnings.some((w) => w.includes(entry)), `a warning names ${entry}: ${JSON.stringify(warnings)}`);
  assert.equal((await stats(page)).bodies, 1, 'the ball of the link dropped, nothing else');
  await page.click('#objects button[data-id="box"]');
  await page.click('#materials button[data-id="von_mises"]');
  const [x, y] = await screenOf(page, 1.0, 0.6, 0);
  await page.mouse.click(x, y);
  await page.waitForFunction(() => mpm.sim.bodies === 2 && /box:von_mises/.test(location.hash), null, { timeout: 10_000 });
  const s = await stats(page);
  assert.match(s.hash, /colour=speed/);
  assert.match(s.hash, /&drop=0:ball:elastic:0\.2:0\.5,0\.5&drop=[\d.]+:box:von_mises:[\d.]+:[\d.]+,[\d.]+$/);
  await page.waitForFunction(() => mpm.simTime > 0.05, null, { timeout: 60_000 });
  await page.screenshot({ path: join(OUT, 'playground-2d.png') });
  assert.deepEqual(errors, []);
  await page.close();
});

test('2D: Clear and the drops after it are in the link, which reproduces them', async () => {
  const { page, errors } = await open('#scene=www/test-scenes/drop_2d.json');
  const s0 = await stats(page);
  assert.ok(s0.bodies >= 2 && s0.time > 0, JSON.stringify(s0));
  await page.click('#clear');
  await page.waitForFunction(() => mpm.sim.bodies === 0 && /cleared=1$/.test(location.hash), null, { timeout: 10_000 });
  const s1 = await stats(page);
  assert.match(s1.hash, /&cleared=1$/);
  await page.click('#objects button[data-id="ball"]');
  const [x, y] = await screenOf(page, 1.5, 0.5, 0);
  await page.mouse.click(x, y);
  await page.waitForFunction(() => mpm.sim.bodies === 1 && /drop=/.test(location.hash), null, { timeout: 10_000 });
  const s2 = await stats(page);
  // In an empty box time stands still: the ball dropped at the time of the Clear.
  assert.match(s2.hash, /&cleared=1&drop=0:ball:/);
  const ball = await bodyJson(page, 0);
  await page.close();
  const again = await open(s2.hash);
  const r = await stats(again.page);
  assert.equal(r.bodies, 1, 'the scene\'s own bodies cleared, the ball dropped');
  assert.equal(r.particles, s2.particles);
  assert.equal(await bodyJson(again.page, 0), ball);
  assert.deepEqual([...errors, ...again.errors], []);
  await again.page.close();
});

test('without WebGL2 the canvas fallback draws the particles', async () => {
  const { page, errors } = await open('#scene=www/test-scenes/drop_2d.json', hideWebgl2);
  const s = await stats(page);
  assert.match(s.renderer, /Canvas 2D/);
  assert.ok(s.particles > 0);
  const px = await viewShot(page, join(OUT, 'view-fallback.png'));
  assert.ok(px.variance > 50 && px.colours > 5, `fallback view is not blank: ${JSON.stringify(px)}`);
  await page.screenshot({ path: join(OUT, 'playground-fallback.png') });
  assert.deepEqual(errors, []);
  await page.close();
});

test('the quality control samples the scene again: particles by the expected factor, the link keeps it', async () => {
  const { page, errors } = await open('#scene=scenes/column_collapse_2d.json');
  const live = await stats(page);
  assert.equal(live.quality.quality, 'live');
  assert.equal(live.quality.cell_size, 2 * live.quality.scene_cell_size, 'cells twice the scene file\'s');
  assert.ok(live.particles >= 2000, `at least 2 000 particles in 2D: ${live.particles}`);
  // A drop made now is replayed at the new resolution.
  await page.click('#objects button[data-id="ball"]');
  const [x, y] = await screenOf(page, 0.2, 0.25, 0);
  await page.mouse.click(x, y);
  await page.waitForFunction(() => mpm.sim.bodies === 2, null, { timeout: 10_000 });
  await page.selectOption('#quality', 'fine');
  await page.waitForFunction(() => mpm.sim.quality.quality === 'fine' && /quality=fine/.test(location.hash), null, { timeout: 30_000 });
  // The Clear-free session replays: the ball lands again when the simulation reaches its time.
  await page.waitForFunction(() => mpm.sim.bodies === 2, null, { timeout: 60_000 });
  const fine = await stats(page);
  assert.equal(fine.quality.cell_size, fine.quality.scene_cell_size);
  // The column's particles (body 0; the view colours by body) scale as (ppc / cell factor)^dim.
  const fineColumn = await page.evaluate(() => {
    const f = mpm.frame;
    let n = 0;
    for (let i = 0; i < f.count; i++) if (f.values[i] === 0) n++;
    return n;
  });
  const want = (live.quality.particles_per_cell / fine.quality.particles_per_cell / 2) ** 2;
  const got = live.particles / fineColumn;
  assert.ok(Math.abs(got / want - 1) < 0.15, `live ${live.particles} against fine ${fineColumn} particles: ${got}, want ${want}`);
  // The link opens at that quality, with the same particles.
  const again = await open(fine.hash);
  await again.page.waitForFunction(() => mpm.sim.bodies === 2, null, { timeout: 60_000 });
  const back = await stats(again.page);
  assert.equal(back.quality.quality, 'fine');
  assert.equal(back.particles, fine.particles);
  assert.equal(await again.page.inputValue('#quality'), 'fine');
  assert.deepEqual([...errors, ...again.errors], []);
  await page.close();
  await again.page.close();
});

test('without a worker the simulation steps on the page\'s thread', async () => {
  const { page, errors } = await open('#scene=www/test-scenes/drop_2d.json', () => { delete window.Worker; });
  const s0 = await stats(page);
  assert.equal(s0.thread, 'main thread');
  await advanced(page, s0.time);
  await page.click('#objects button[data-id="box"]');
  const [x, y] = await screenOf(page, 1.5, 0.6, 0);
  await page.mouse.click(x, y);
  await page.waitForFunction((n) => mpm.sim.bodies === n + 1, s0.bodies, { timeout: 10_000 });
  await page.selectOption('#quality', 'balanced');
  await page.waitForFunction(() => mpm.sim.quality.quality === 'balanced', null, { timeout: 30_000 });
  const s1 = await stats(page);
  await advanced(page, s1.time);
  assert.deepEqual(errors, []);
  await page.close();
});

test('2D: sleeping is on by default, the settled sand falls asleep and shows in the sleeping colours; off wakes it', async () => {
  const { page, errors } = await open('#scene=notched_sand_block&dim=2&quality=live&colour=sleeping');
  assert.equal(await page.evaluate(() => mpm.sim.sleeping), true);
  assert.equal(await page.$eval('#sleeping', (c) => c.checked), true);
  // At rest the sand falls asleep: the frame counts it and the colour scalars mark it (< 0).
  const marked = await (await page.waitForFunction(() => {
    const f = mpm.session.frame;
    return (f?.asleep ?? 0) > 0 ? { asleep: f.asleep, negative: Array.from(f.values.subarray(0, f.count)).filter((v) => v < 0).length } : null;
  }, null, { timeout: 90_000 })).jsonValue();
  assert.equal(marked.negative, marked.asleep, 'the colour scalars mark the particles asleep');
  await page.screenshot({ path: join(OUT, 'playground-sleeping.png') });
  await page.evaluate(() => {
    const c = document.getElementById('sleeping');
    c.checked = false;
    c.dispatchEvent(new Event('change'));
  });
  await page.waitForFunction(() => mpm.sim.sleeping === false && mpm.session.frame?.asleep === 0, null, { timeout: 10_000 });
  // Reset keeps the choice.
  await page.click('#reset');
  // The frame is read where it is waited for: a restart drops the frames before it, so a
  // frame seen in one evaluation may be gone in the next.
  const afterReset = await page.waitForFunction(() => {
    const f = mpm.session.frame;
    return mpm.sim.sleeping === false && mpm.simTime > 0.3 && f && f.generation === mpm.session.generation ? { asleep: f.asleep } : null;
  }, null, { timeout: 60_000 });
  assert.equal((await afterReset.jsonValue()).asleep, 0);
  // The link keeps the choice, and opens with it.
  const hash = await page.evaluate(() => location.hash);
  assert.match(hash, /[#&]sleep=0(&|$)/);
  assert.deepEqual(errors, []);
  await page.close();
  const again = await open(hash);
  await again.page.waitForFunction(() => mpm.sim.sleeping === false && mpm.simTime > 0.3, null, { timeout: 60_000 });
  assert.equal(await again.page.$eval('#sleeping', (c) => c.checked), false);
  assert.deepEqual(again.errors, []);
  await again.page.close();
});

// --- links ----------------------------------------------------------------------------------

/// Opens link `hash` in the page as a link opens (the hash set, then read), and waits until
/// it shows: resolves to {scene, dim, toast, warnings since}.
async function follow(page, warnings, hash) {
  const before = warnings.length;
  await page.evaluate(async (h) => {
    history.replaceState(null, '', h);
    await mpm.loadFromHash();
  }, hash);
  await page.waitForFunction(() => mpm.frame?.generation === mpm.session.generation && document.querySelector('[data-hud="time"]'), null, { timeout: 30_000 });
  return {
    ...(await page.evaluate(() => ({
      scene: mpm.view.scene, lesson: mpm.view.lesson ?? null, dim: mpm.sim.scene.dim, colour: mpm.view.colour,
      quality: mpm.sim.quality.quality, toast: document.getElementById('toast').textContent,
      hud: [...document.querySelectorAll('#hud [data-hud]')].map((e) => e.textContent),
    }))),
    warnings: warnings.slice(before),
  };
}

test('every link opens a working page: unusable entries are named in one message and in the console, the rest is used, the fallback is the default scene', async () => {
  const { page, errors, warnings } = await open('#scene=sandbox&dim=2&drop=0:box:von_mises:0.2:0.5,0.2');
  const named = (r, entry) => {
    assert.ok(r.warnings.some((w) => w.includes(entry)), `the console names ${entry}: ${JSON.stringify(r.warnings)}`);
    assert.ok(r.toast.includes(entry), `the message names ${entry}: ${r.toast}`);
  };
  let r = await follow(page, warnings, '#dim=7');
  assert.equal(r.scene, 'bunny_on_sand_heap', 'the default scene');
  named(r, 'dim=7');
  await page.click('#dim2');
  await page.waitForFunction(() => mpm.sim.scene.dim === 2 && mpm.frame?.generation === mpm.session.generation, null, { timeout: 30_000 });
  r = await follow(page, warnings, '#quality=balanced');
  assert.deepEqual([r.scene, r.quality], ['bunny_on_sand_heap', 'balanced'], 'settings alone: the default scene at that level');
  assert.ok(r.hud.every((t) => t.trim()), `the HUD: ${r.hud}`);
  r = await follow(page, warnings, '#scene=column_collapse&dim=2&quality=ultra&drucker_prager.friction_angle=200&colour=speed');
  assert.deepEqual([r.scene, r.dim, r.colour], ['column_collapse', 2, 'speed'], 'the rest of the link is used');
  named(r, 'quality=ultra');
  named(r, 'drucker_prager.friction_angle');
  assert.ok(/friction_angle = 200/.test(r.toast) && /quality=ultra/.test(r.toast), `one message names both: ${r.toast}`);
  r = await follow(page, warnings, '#scene=nope&colour=pressure');
  assert.deepEqual([r.scene, r.colour], ['bunny_on_sand_heap', 'pressure']);
  named(r, 'scene=nope');
  r = await follow(page, warnings, '#scene=file:gone.json&dim=2');
  assert.equal(r.scene, 'bunny_on_sand_heap');
  named(r, 'scene=file:gone.json');

  // The parser's fuzz, extended to the page: links of random entries, and good links mutated.
  let seed = 48;
  const rand = () => {
    seed = (seed + 0x6d2b79f5) | 0;
    let t = Math.imul(seed ^ (seed >>> 15), 1 | seed);
    t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
  const pick = (a) => a[Math.floor(rand() * a.length)];
  const KEYS = ['scene', 'lesson', 'dim', 'colour', 'object', 'material', 'time', 'size', 'sleep', 'quality', 'cleared', 'drop',
    'gravity', 'cfl', 'wall_friction', 'drucker_prager.friction_angle', 'elastic.youngs_modulus', 'von_mises.yield_stress',
    'bodies[0].drucker_prager.friction_angle', 'bodies[9].elastic.flip', 'warp', ''];
  const VALUES = ['', '-1', '0', '1', '2', '3', '7', '200', '1e999', '-1e-300', 'NaN', 'ultra', 'live', 'fine', 'x', '%', '%ZZ',
    '0.0000001', '99999999', '[', 'sandbox', 'nope', 'column_collapse', 'friction_angle', 'stress_path', 'file:x.json',
    '../../etc/passwd', 'speed', 'bunny', 'box', 'von_mises', '0.5', '0:ball:elastic:0.2:0.5,0.5', '1e9:box:elastic:0.1:0.5,0.5,0.5',
    '0:bunny:drucker_prager:5:0.5,0.5:0,-1e6', '0:ball:elastic:0.2:NaN,0.5'];
  const GOOD = [
    '#scene=column_collapse&dim=2&colour=speed&quality=live&drucker_prager.friction_angle=30&gravity=9.81&drop=0.5:ball:elastic:0.2:0.5,0.5',
    '#lesson=friction_angle&bodies%5B1%5D.drucker_prager.friction_angle=30',
    '#scene=bunny_on_sand_ball&dim=3&object=box&material=von_mises&size=0.2&time=0.5&sleep=0&drop=0:bunny:drucker_prager:0.25:1,0.5,0.5:0,-1,0',
    '#scene=sandbox&dim=2&cleared=1&cfl=0.4',
  ];
  const CHARS = '&=:,.#%[]-e0123456789abcxyz_ ';
  const mutate = (link) => {
    let s = link;
    for (let k = 0, n = 1 + Math.floor(rand() * 3); k < n; k++) {
      const i = Math.floor(rand() * s.length);
      const how = Math.floor(rand() * 5);
      if (how === 0) s = s.slice(0, i) + s.slice(i + 1);
      else if (how === 1) s = s.slice(0, i) + pick([...CHARS]) + s.slice(i);
      else {
        const entries = s.replace(/^#/, '').split('&');
        const j = Math.floor(rand() * entries.length);
        const [key] = entries[j].split('=');
        if (how === 2) entries[j] = `${key}=${pick(VALUES)}`;
        else if (how === 3) entries.splice(j, 0, entries[j]);
        else entries[j] = `${pick(KEYS)}=${entries[j].split('=').slice(1).join('=')}`;
        s = `#${entries.join('&')}`;
      }
    }
    return s;
  };
  const links = [];
  for (let k = 0; k < 24; k++) links.push(mutate(pick(GOOD)));
  for (let k = 0; k < 12; k++) links.push(`#${Array.from({ length: 1 + Math.floor(rand() * 5) }, () => `${pick(KEYS)}=${pick(VALUES)}`).join('&')}`);
  for (const link of links) {
    const r = await follow(page, warnings, link).catch((e) => assert.fail(`${link}: ${e.message}`));
    assert.ok([2, 3].includes(r.dim), `${link}: ${JSON.stringify(r)}`);
    assert.ok(r.hud.length === 3 && r.hud.every((t) => t.trim()), `${link}: the HUD ${JSON.stringify(r.hud)}`);
    assert.deepEqual(errors, [], `${link}: no page error`);
  }
  assert.deepEqual(errors, []);
  await page.close();
});

test('the energy note\'s claim: the energies count from the last change of bodies, a drop of the link landing included', async () => {
  const { page, errors } = await open('#scene=sandbox&dim=2&drop=0:box:von_mises:0.2:0.5,0.2&drop=0.4:ball:elastic:0.15:1.2,0.5');
  const note = await page.textContent('#energy-note');
  assert.match(note, /count from the last change of bodies/);
  await page.waitForFunction(() => mpm.sim.bodies === 2 && mpm.energyPlot.samples.length > 3, null, { timeout: 60_000 });
  const landed = await page.evaluate(() => mpm.drops[1].t);
  const ref = await page.evaluate(() => mpm.energyPlot.ref);
  assert.ok(ref.time >= landed - 1e-6 && ref.time < landed + 0.2, `counted from the ball's entry at ${landed} s: from ${ref.time} s`);
  // and from a click's drop
  const [x, y] = await screenOf(page, 0.8, 0.5, 0);
  const t = await page.evaluate(() => mpm.simTime);
  await page.mouse.click(x, y);
  await page.waitForFunction(() => mpm.sim.bodies === 3 && mpm.energyPlot.samples.length > 3, null, { timeout: 60_000 });
  const again = await page.evaluate(() => mpm.energyPlot.ref.time);
  assert.ok(again >= t, `counted from the click's drop after ${t} s: from ${again} s`);
  assert.deepEqual(errors, []);
  await page.close();
});

test('the energy note\'s claim: a sand box dropped in the sandbox settles with the plotted sum level', async () => {
  const { page, errors } = await open('#scene=sandbox&dim=2&drop=0:box:drucker_prager:0.25:1,0.3');
  assert.match(await page.textContent('#energy-note'), /so the sum stays level; where it moves, the account misses/);
  await page.waitForFunction(() => mpm.simTime > 3 && mpm.energyPlot.samples.length > 20, null, { timeout: 120_000 });
  const s = await page.evaluate(() => mpm.energyPlot.samples.map(({ time, kinetic, potential, elastic, dissipated, total }) =>
    ({ time, kinetic, potential, elastic, dissipated, total })));
  // The terms as plotted (from the first frame after the box entered, which under load may
  // come while it falls: its kinetic energy then is the sum's level): it fell, hit the floor and
  // came to rest.
  const last = s[s.length - 1];
  const released = -Math.min(...s.map((x) => x.potential));
  const totals = s.map((x) => x.total);
  const drift = Math.max(...totals) - Math.min(...totals);
  const figures = `released ${released.toFixed(2)} J/m, dissipated ${last.dissipated.toFixed(2)} J/m, kinetic at the end ` +
    `${last.kinetic.toExponential(2)} J/m, the sum from ${s[0].total.toFixed(2)} J/m, moving over ${drift.toExponential(2)} J/m ` +
    `in ${s[0].time.toFixed(2)}–${last.time.toFixed(2)} s`;
  console.log(figures);
  assert.ok(released > 0 && last.kinetic < 0.01 * last.dissipated, `at rest: ${figures}`);
  // The sum stays level: within 2 % of the energy the fall dissipated, all the way.
  assert.ok(drift <= 0.02 * last.dissipated, figures);
  // Dropped, the box collapsed: the overlay says so over its heap and draws no angle of repose.
  const marks = await page.evaluate(() => ({ labels: mpm.overlay.labels, poured: mpm.frame.measures.map((d) => d.poured) }));
  assert.deepEqual(marks.poured, [false]);
  assert.ok(marks.labels.some((l) => l.kind === 'note' && /^a collapse/.test(l.text)), JSON.stringify(marks.labels));
  assert.ok(!marks.labels.some((l) => l.kind === 'law'), JSON.stringify(marks.labels));
  assert.deepEqual(errors, []);
  await page.close();
});

test('the page opens at the level the probe picks, says why, and the user\'s choice wins, is remembered and goes in the link', async () => {
  // (init scripts are sent as text: the level goes in the script)
  const forced = (id) => `window.mpmProbe = '${id}'; localStorage.removeItem('mpm.quality');`;
  const line = (page) => page.textContent('[data-hud="quality"]');
  const shown = (page) => page.waitForFunction(() => document.querySelector('[data-hud="quality"]'), null, { timeout: 20_000 });
  // The probe's answer forced both ways: the default scene opens at that level, the HUD says so.
  for (const [id, label] of [['balanced', 'Balanced'], ['live', 'Live']]) {
    const { page, errors } = await openPage(browser.context, `${URL_ROOT}#dim=2`, undefined, forced(id));
    await shown(page);
    const s = await stats(page);
    assert.equal(s.quality.quality, id);
    assert.match(s.hash, new RegExp(`quality=${id}`));
    assert.match(await line(page), new RegExp(`^${label}: .*\\(the probe's answer set to ${label}\\)$`));
    assert.equal(await page.inputValue('#quality'), id);
    assert.deepEqual(errors, []);
    await page.close();
  }
  // The probe itself: its answer follows from the step cost it measured and the rate that
  // cost steps at (Balanced at 1× real time in 2D), said in the HUD's quality line.
  {
    const { page, errors } = await openPage(browser.context, `${URL_ROOT}#dim=2`, undefined, () => localStorage.removeItem('mpm.quality'));
    await shown(page);
    const s = await stats(page);
    const text = await line(page);
    console.log(text);
    const m = text.match(/\(picked here: a Balanced step costs [\d.]+ ms here, ([\d.]+)× real time(, too slow for Balanced)?\)$/);
    assert.ok(m, text);
    assert.equal(s.quality.quality, Number(m[1]) >= 1 ? 'balanced' : 'live', text);
    assert.equal(!!m[2], s.quality.quality === 'live', text);
    assert.deepEqual(errors, []);
    await page.close();
  }
  // The user's choice wins over the probe's, goes in the link and is remembered for the next visit.
  const { page, errors } = await openPage(browser.context, `${URL_ROOT}#dim=2`, undefined, forced('live'));
  await shown(page);
  await page.selectOption('#quality', 'fine');
  await page.waitForFunction(() => mpm.sim.quality.quality === 'fine' && /quality=fine/.test(location.hash), null, { timeout: 30_000 });
  assert.equal(await page.evaluate(() => localStorage.getItem('mpm.quality')), 'fine');
  await page.close();
  const next = await openPage(browser.context, `${URL_ROOT}#dim=2`, undefined, () => { window.mpmProbe = 'live'; });
  await shown(next.page);
  assert.equal((await stats(next.page)).quality.quality, 'fine', 'the remembered choice, not the probe\'s');
  assert.match(await line(next.page), /^Fine: .*\(your choice, remembered\)$/);
  await next.page.close();
  // A link naming a level wins over the remembered one.
  const linked = await openPage(browser.context, `${URL_ROOT}#dim=2&quality=balanced`, undefined, () => { window.mpmProbe = 'live'; });
  assert.equal((await stats(linked.page)).quality.quality, 'balanced');
  await linked.page.evaluate(() => localStorage.removeItem('mpm.quality'));
  await linked.page.close();
  assert.deepEqual([...errors, ...next.errors, ...linked.errors], []);
});
