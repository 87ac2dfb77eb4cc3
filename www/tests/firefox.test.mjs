// The playground in Firefox: Debian's firefox-esr, headless, driven by puppeteer-core over
// WebDriver BiDi (playwright-core needs its own patched Firefox, which npm cannot download
// here). Firefox makes WebGL contexts with EGL on an X display even when headless, so the test
// starts Xvfb (Mesa's llvmpipe draws) and the page gets WebGL2; a second page hides WebGL2 to
// test the Canvas 2D fallback. Served by `cargo xtask test` (MPM_URL); screenshots go to MPM_OUT.
//
//   MPM_URL=http://127.0.0.1:8080/ FIREFOX=/usr/bin/firefox-esr node --test www/tests/firefox.test.mjs
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import { join } from 'node:path';
import puppeteer from 'puppeteer-core';
import { decodePng, pixelStats } from './png.mjs';
import { bodyPoints, fractionAt, hideWebgl2, screenOf } from './view.mjs';
import { startXvfb } from './xvfb.mjs';

const URL_ROOT = process.env.MPM_URL || 'http://127.0.0.1:8080/';
const OUT = process.env.MPM_OUT || 'target/e2e';
mkdirSync(OUT, { recursive: true });

let browser, xvfb;
before(async () => {
  xvfb = await startXvfb();
  browser = await puppeteer.launch({
    browser: 'firefox',
    protocol: 'webDriverBiDi',
    executablePath: process.env.FIREFOX || '/usr/bin/firefox-esr',
    headless: true,
    args: ['--no-remote'],
    env: { ...process.env, DISPLAY: xvfb.display },
  });
});
after(async () => {
  await browser?.close();
  xvfb?.stop();
});

/// Opens the page (after running `init` in it, if given), collecting console errors.
async function open(hash = '', init) {
  const page = await browser.newPage();
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(e.message));
  if (init) await page.evaluateOnNewDocument(init);
  await page.setViewport({ width: 1400, height: 860 });
  await page.goto(URL_ROOT + hash);
  await page.waitForFunction(() => window.mpm?.sim && window.mpm.stats.frames > 5, { timeout: 60_000 });
  return { page, errors };
}

const stats = (page) => page.evaluate(() => ({
  particles: mpm.sim.particles, bodies: mpm.sim.bodies, time: mpm.simTime, thread: mpm.session.kind,
  frames: mpm.stats.frames, renderer: mpm.renderer.kind, ua: navigator.userAgent,
  gl: mpm.renderer.gl ? mpm.renderer.gl.getParameter(mpm.renderer.gl.RENDERER) : null,
}));

/// Sand orange, lit or in shade (not the blue bunny, the red ball, the grey floor or the
/// pale background).
const orange = ([r, g, b]) => r > 40 && g > 0.55 * r && g < 0.9 * r && b < 0.5 * r;

/// Pauses the page, screenshots the view and checks that it is not blank and that body 0
/// (the sand) is drawn where its particles are: that is what the renderer drew, not only the
/// HUD over it.
async function checkView(page, path) {
  await page.click('#play');
  assert.equal(await page.evaluate(() => mpm.playing), false, 'paused');
  // The simulation stops; the last frame it sent is drawn at the next animation frames.
  await page.evaluate(() => new Promise((r) => setTimeout(() => requestAnimationFrame(() => requestAnimationFrame(r)), 200)));
  const view = await page.$('#view');
  // A frame the worker sent before it took the pause may still be drawn after the first
  // wait: the screenshot and the positions must be of the same frame (sand on the APIC base
  // moves a particle's width in a frame while it spreads), so take both again if it changed.
  let png, points, seq;
  for (let tries = 0; tries < 5; tries++) {
    seq = await page.evaluate(() => mpm.frame.seq);
    png = decodePng(await view.screenshot({ path }));
    // The sand's particles that the bunny or the ball do not cover.
    points = await bodyPoints(page, 0, 200, 12);
    if ((await page.evaluate(() => mpm.frame.seq)) === seq) break;
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  }
  const px = pixelStats(png);
  assert.ok(px.variance > 50 && px.colours > 5, `the view is not blank: ${JSON.stringify(px)}`);
  const width = await page.evaluate(() => document.getElementById('view').clientWidth);
  const sand = fractionAt(png, points, width, orange);
  assert.ok(points.length > 50 && sand > 0.8, `the sand is drawn where its particles are: ${sand} of ${points.length} points (frame ${seq})`);
  return { px, sand };
}

test('Firefox, WebGL2: the default scene runs in a worker and draws, a click drops a ball, no console error', async () => {
  const { page, errors } = await open();
  const s0 = await stats(page);
  assert.match(s0.ua, /Firefox\//, s0.ua);
  assert.equal(s0.renderer, 'WebGL2', `the WebGL2 renderer draws (GL renderer ${s0.gl})`);
  assert.equal(s0.thread, 'worker', 'the simulation steps in a Web Worker');
  assert.ok(s0.particles > 4_500 && s0.bodies === 2, JSON.stringify(s0));
  // a ball dropped by clicking on the floor
  await page.click('#objects button[data-id="ball"]');
  const size = await page.evaluate(() => mpm.sim.scene.domain.size);
  const [x, y] = await screenOf(page, 0.8 * size[0], 0, 0.5 * size[2]);
  await page.mouse.click(x, y);
  await page.waitForFunction((t) => mpm.simTime > t + 0.02 && mpm.sim.bodies === 3, { timeout: 60_000 }, s0.time);
  const s1 = await stats(page);
  assert.equal(s1.bodies, 3, 'a ball dropped');
  assert.ok(s1.particles > s0.particles, `particle count grew: ${s0.particles} → ${s1.particles}`);
  assert.ok(s1.frames > s0.frames && s1.time > s0.time, `the simulation advanced: ${JSON.stringify([s0, s1])}`);
  const shot = join(OUT, 'firefox.png');
  const { sand } = await checkView(page, shot);
  assert.deepEqual(errors, [], 'no console error');
  console.log(`firefox: ${s1.ua}; renderer ${s1.renderer} (${s1.gl}); ${s1.particles} particles; ` +
    `${(100 * sand).toFixed(0)} % of sampled sand particles drawn orange; screenshot ${shot}`);
  await page.close();
});

test('Firefox without WebGL2: the Canvas 2D fallback draws the particles', async () => {
  const { page, errors } = await open('', hideWebgl2);
  const s = await stats(page);
  assert.match(s.renderer, /Canvas 2D/);
  assert.ok(s.particles > 4_500, JSON.stringify(s));
  await checkView(page, join(OUT, 'firefox-fallback.png'));
  assert.deepEqual(errors, [], 'no console error');
  await page.close();
});
