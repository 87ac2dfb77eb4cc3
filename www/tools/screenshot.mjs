// The README's picture of the page: the default scene in headless Chromium a moment after an
// elastic bunny was dropped on the sand, a sand particle inspected, the plots open.
//
//   MPM_URL=http://127.0.0.1:8080/ node www/tools/screenshot.mjs docs/playground.jpg
// (`cargo xtask screenshot` serves the page and runs this.)
import { launch } from '../tests/browser.mjs';
import { screenOf } from '../tests/view.mjs';

const url = process.env.MPM_URL || 'http://127.0.0.1:8080/';
const out = process.argv[2] || 'docs/playground.jpg';
const browser = await launch({ width: 1400, height: 860 });
const page = browser.page;
const errors = [];
page.on('pageerror', (e) => errors.push(e.message));
await page.goto(url);
await page.waitForFunction(() => window.mpm?.sim && mpm.stats.frames > 5, null, { timeout: 120_000 });
const [w, , d] = await page.evaluate(() => mpm.domain);
if ((await page.getAttribute('#toggle-plots', 'aria-pressed')) === 'false') await page.click('#toggle-plots');
await page.click('#objects button[data-id="bunny"]');
await page.click('#materials button[data-id="elastic"]');
await page.mouse.click(...(await screenOf(page, 0.75 * w, 0, 0.5 * d)));
await page.click('#materials button[data-id="drucker_prager"]');
await page.click('#tool-inspect');
await page.mouse.click(...(await screenOf(page, 0.5 * w, 0.05, 0.5 * d)));
await page.waitForFunction(() => mpm.simTime > 0.5, null, { timeout: 600_000 });
await page.click('#play');
await page.waitForTimeout(1000);
await page.screenshot({ path: out, type: 'jpeg', quality: 82 });
await browser.close();
if (errors.length) throw new Error(`page errors: ${errors.join('; ')}`);
console.log(`screenshot: ${out}`);
