// The soil lab's real-time factor as the page reports it: the playground in headless Chromium
// (Debian's package: the floor, not a laptop's), the Lab opened, each test run once to its end
// with the sliders' defaults (φ = 30°, ψ = 0, c = 0) at the load given, and the page's own
// reading of the run's speed, simulated over wall-clock time (`mpmLab.speed`, the figure its
// status line prints), beside the solver's steps per frame and the share of each frame spent
// stepping (the lab steps on the page's thread, up to 14 ms per display frame).
//
//   MPM_URL=http://127.0.0.1:8080/ node www/bench/lab-page.mjs [--budget MS] [shear_box|biaxial_mc|biaxial_dp[:LOAD_KPA]]...
// (default: each test at the load slider's default, 10 kPa; `--budget` sets the lab's stepping
// per display frame instead of its own)
// prints one line per test:
//   lab test=<name> load_kpa=<l> sim=<s> wall=<s> rtf_page=<x> frames=<n> stepping_share=<f> drawing_share=<f>
// (the shares of the run's wall-clock time spent in the solver's `advance` and in the lab's
// `draw`; the rest is the browser's own frame: compositing, the display's pace)
import { launch, openPage } from '../tests/browser.mjs';

const url = process.env.MPM_URL || 'http://127.0.0.1:8080/';
const wanted = process.argv.slice(2);
const b = wanted.indexOf('--budget');
// the lab's stepping per display frame (ms), if not its own (`Lab.frameBudget`)
const budget = b >= 0 ? Number(wanted.splice(b, 2)[1]) : null;
const tests = wanted.length ? wanted : ['shear_box:10', 'biaxial_mc:10', 'biaxial_dp:10'];

const browser = await launch();
const { page, errors } = await openPage(browser.context, url);
await page.click('#lab-open');
if (budget) await page.evaluate((ms) => { window.mpmLab.frameBudget = ms; }, budget);
// the share of each display frame the lab spends stepping: advance() timed in the page
await page.evaluate(() => {
  const lab = window.mpmLab;
  lab.probe = { stepping: 0, frames: 0, drawing: 0 };
  const draw = lab.draw.bind(lab);
  lab.draw = () => {
    const t0 = performance.now();
    try { draw(); } finally { lab.probe.drawing += performance.now() - t0; }
  };
  const wrap = () => {
    const test = lab.test;
    if (!test || test.probed) return;
    const advance = test.advance.bind(test);
    test.advance = (span, every) => {
      const t0 = performance.now();
      try { return advance(span, every); } finally { lab.probe.stepping += performance.now() - t0; }
    };
    test.probed = true;
  };
  const run = lab.runScene.bind(lab);
  lab.runScene = (...args) => {
    lab.probe = { stepping: 0, frames: 0, drawing: 0 };
    const ended = run(...args);
    wrap();
    const count = () => { if (lab.running) { lab.probe.frames += 1; requestAnimationFrame(count); } };
    requestAnimationFrame(count);
    return ended;
  };
});
for (const spec of tests) {
  const [name, load = name === 'shear_box' ? '10' : '20'] = spec.split(':');
  const [test, model] = name === 'shear_box' ? ['shear_box', 'mohr_coulomb']
    : ['biaxial', name === 'biaxial_dp' ? 'drucker_prager' : 'mohr_coulomb'];
  await page.selectOption('#lab-test', test);
  await page.selectOption('#lab-model', model);
  await page.evaluate((v) => { const e = document.getElementById('lab-load'); e.value = v; e.dispatchEvent(new Event('input')); }, load);
  const n = await page.evaluate(() => window.mpmLab.runs.length);
  const t0 = Date.now();
  await page.click('#lab-run');
  await page.waitForFunction((k) => window.mpmLab.runs.length > k && !window.mpmLab.running, n, { timeout: 1_800_000, polling: 500 });
  const wall = (Date.now() - t0) / 1e3;
  const r = await page.evaluate(() => ({ speed: window.mpmLab.speed, sim: window.mpmLab.test.time(), probe: window.mpmLab.probe }));
  const share = (ms) => (ms / (wall * 1e3)).toFixed(2);
  console.log(`lab test=${name}${budget ? ` budget_ms=${budget}` : ''} load_kpa=${load} sim=${r.sim.toFixed(3)} wall=${wall.toFixed(1)} rtf_page=${r.speed.toFixed(3)}`
    + ` frames=${r.probe.frames} stepping_share=${share(r.probe.stepping)} drawing_share=${share(r.probe.drawing)}`);
}
if (errors.length) console.log(`page errors: ${errors.join(' | ')}`);
await browser.close();
