// The level probe's answer on repeated visits: the page opened afresh `--visits` times (default
// 10) with no level in its link and none remembered, each visit's HUD quality line read (the
// probe's step cost, the rate it gives and the level picked).
//
//   MPM_URL=http://127.0.0.1:8080/ node www/bench/probe.mjs [--visits N] [--dim 2|3]
// prints one line per visit, then the spread:
//   probe visit=<k> level=<id> ms_per_step=<x> ratio=<y>
//   probe visits=<n> levels=<id:count,..> ratio_min=<a> ratio_median=<b> ratio_max=<c>
import { launchBrowser } from '../tests/browser.mjs';

const url = process.env.MPM_URL || 'http://127.0.0.1:8080/';
const args = process.argv.slice(2);
const flag = (name, d) => { const i = args.indexOf(name); return i >= 0 ? args[i + 1] : d; };
const visits = Number(flag('--visits', 10));
const dim = flag('--dim', '3');
const browser = await launchBrowser();
const ratios = [], levels = {};
for (let k = 1; k <= visits; k++) {
  const context = await browser.newContext({ viewport: { width: 1366, height: 768 } });
  const page = await context.newPage();
  await page.addInitScript(() => localStorage.removeItem('mpm.quality'));
  await page.goto(`${url}#dim=${dim}`);
  await page.waitForFunction(() => /picked here|probe failed/.test(document.querySelector('[data-hud="quality"]')?.textContent ?? ''), null, { timeout: 120_000 });
  const line = await page.textContent('[data-hud="quality"]');
  const m = line.match(/costs ([\d.]+) ms here, ([\d.]+)× real time/);
  const level = await page.evaluate(() => window.mpm.sim.quality.quality);
  levels[level] = (levels[level] ?? 0) + 1;
  if (m) ratios.push(Number(m[2]));
  console.log(`probe visit=${k} level=${level} ms_per_step=${m?.[1] ?? '-'} ratio=${m?.[2] ?? '-'}`);
  await context.close();
}
ratios.sort((a, b) => a - b);
console.log(`probe visits=${visits} levels=${Object.entries(levels).map(([l, n]) => `${l}:${n}`).join(',')} ` +
  `ratio_min=${ratios[0]} ratio_median=${ratios[Math.floor(ratios.length / 2)]} ratio_max=${ratios[ratios.length - 1]}`);
await browser.close();
