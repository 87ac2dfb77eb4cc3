// The playground in Firefox: Debian's firefox-esr, headless, driven by puppeteer-core over
// WebDriver BiDi (playwright-core needs its own patched Firefox, which npm cannot download
// here). Served by `cargo xtask test` (MPM_URL); the screenshot goes to MPM_OUT.
//
//   MPM_URL=http://127.0.0.1:8080/ FIREFOX=/usr/bin/firefox-esr node --test www/tests/firefox.test.mjs
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import { join } from 'node:path';
import puppeteer from 'puppeteer-core';
import { decodePng, pixelStats } from './png.mjs';
import { screenOf } from './view.mjs';

const URL_ROOT = process.env.MPM_URL || 'http://127.0.0.1:8080/';
const OUT = process.env.MPM_OUT || 'target/e2e';
mkdirSync(OUT, { recursive: true });

let browser;
before(async () => {
  browser = await puppeteer.launch({
    browser: 'firefox',
    protocol: 'webDriverBiDi',
    executablePath: process.env.FIREFOX || '/usr/bin/firefox-esr',
    headless: true,
    args: ['--no-remote'],
  });
});
after(async () => { await browser?.close(); });

test('Firefox: the default scene runs and draws, a click drops a ball, no console error', async () => {
  const page = await browser.newPage();
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(e.message));
  await page.setViewport({ width: 1400, height: 860 });
  await page.goto(URL_ROOT);
  await page.waitForFunction(() => window.mpm?.pg && window.mpm.stats.frames > 5, { timeout: 60_000 });
  const stats = () => page.evaluate(() => ({
    particles: mpm.pg.particleCount(), bodies: mpm.pg.bodyCount(), time: mpm.pg.time(),
    frames: mpm.stats.frames, renderer: mpm.renderer.kind, ua: navigator.userAgent,
  }));
  const s0 = await stats();
  assert.match(s0.ua, /Firefox\//, s0.ua);
  assert.ok(s0.particles > 10_000 && s0.bodies === 2, JSON.stringify(s0));
  // a ball dropped by clicking on the floor
  await page.click('#objects button[data-id="ball"]');
  const size = await page.evaluate(() => JSON.parse(mpm.pg.sceneJson()).domain.size);
  const [x, y] = await screenOf(page, 0.8 * size[0], 0, 0.5 * size[2]);
  await page.mouse.click(x, y);
  await page.waitForFunction((t) => mpm.pg.time() > t + 0.02, { timeout: 60_000 }, s0.time);
  const s1 = await stats();
  assert.equal(s1.bodies, 3, 'a ball dropped');
  assert.ok(s1.particles > s0.particles, `particle count grew: ${s0.particles} → ${s1.particles}`);
  assert.ok(s1.frames > s0.frames && s1.time > s0.time, `the simulation advanced: ${JSON.stringify([s0, s1])}`);
  const view = await page.$('#view');
  const shot = join(OUT, 'firefox.png');
  const px = pixelStats(decodePng(await view.screenshot({ path: shot })));
  assert.ok(px.variance > 50 && px.colours > 5, `the view is not blank: ${JSON.stringify(px)}`);
  assert.deepEqual(errors, [], 'no console error');
  console.log(`firefox: ${s1.ua}; renderer ${s1.renderer}; ${s1.particles} particles; screenshot ${shot}`);
  await page.close();
});
