// Starts Debian's Chromium headless through playwright-core, with a fresh profile directory
// and the flags that work on a machine without a network.
import { chromium } from 'playwright-core';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

export const FLAGS = [
  '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
];

/// Before every page the tests open (unless `level` is false): the level probe's answer forced
/// to Live and no level remembered, so that a page opened without `quality=` in its link is
/// at the level the tests were written for, whatever the machine's load.
export const LEVEL_LIVE = () => {
  window.mpmProbe = 'live';
  localStorage.removeItem('mpm.quality');
};

/// Opens the playground at `url` in a new page of `context` (an init script `init` first),
/// collecting console errors and uncaught exceptions, and console warnings; resolves when the
/// simulation has drawn a few frames (one, for a lesson waiting for Play behind its question).
/// `level` (default [`LEVEL_LIVE`]) runs before `init`; false leaves the level to the page.
export async function openPage(context, url, init, level = LEVEL_LIVE) {
  const page = await context.newPage();
  const errors = [], warnings = [];
  page.on('console', (m) => {
    if (m.type() === 'error') errors.push(m.text());
    if (m.type() === 'warning') warnings.push(m.text());
  });
  page.on('pageerror', (e) => errors.push(e.message));
  if (level) await page.addInitScript(level);
  if (init) await page.addInitScript(init);
  await page.goto(url);
  // A lesson waits paused for Play (a soil-lab lesson for Run, in the Lab): its first frame
  // is enough.
  await page.waitForFunction(() => window.mpm?.sim && (window.mpm.stats.frames > 5
    || ((window.mpm.lesson || window.mpmLab?.lessonRun) && !window.mpm.playing
      && window.mpm.stats.frames > 0)), null, { timeout: 60_000 });
  return { page, errors, warnings };
}

/// A browser for contexts of other kinds (`browser.newContext({viewport, hasTouch, isMobile})`).
export function launchBrowser() {
  return chromium.launch({ executablePath: process.env.CHROMIUM || '/usr/bin/chromium', headless: true, args: FLAGS });
}

/// A persistent context on a fresh --user-data-dir; `close()` ends it and removes the profile.
export async function launch({ width = 1400, height = 860 } = {}) {
  const profile = mkdtempSync(join(tmpdir(), 'mpm-chromium-'));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    headless: true,
    args: FLAGS,
    viewport: { width, height },
  });
  const page = context.pages()[0] ?? (await context.newPage());
  return {
    context,
    page,
    async close() {
      await context.close();
      rmSync(profile, { recursive: true, force: true });
    },
  };
}
