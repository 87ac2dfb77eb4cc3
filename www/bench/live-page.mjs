// The real-time factor as seen: the playground in headless Chromium (Debian's package, WebGL2
// drawn on the CPU by SwiftShader: the floor, not a laptop's), stepping and rendering at Live
// (the solver's default level) or the level `--quality` names, for each scene given.
//
//   MPM_URL=http://127.0.0.1:8080/ node www/bench/live-page.mjs [--seconds S] [--quality Q] SCENE.json...
// prints one line per scene:
//   seen scene=<path> dim=<d> particles=<n> sim=<s> wall=<s> frames=<k> fps=<x> rtf_seen=<y>
// After the page shows the scene, 3 s of warm-up (V8's tier-up, the rendering governor
// settling), then S wall-clock seconds (default 8) in which the simulated time advanced and the
// frames drawn are counted, then how long 20 commands wait for an answer while it runs
// (`cargo xtask live` serves the page and runs this). `--quality`
// picks another level than Live, the solver's default.
//
// Then the settled phase as seen (unless `--no-settled`; the page's default, sleeping on): once
// the scene has run 3 s simulated, `rtf_seen_settled` over 3 wall-clock seconds at rest, then
// `rtf_seen_drop` from dropping an elastic bunny of the default size on the middle of the floor
// (the session's `dropAt`) until 2 s simulated or 15 wall-clock seconds have passed, printed on
//   seen_settled scene=<path> rtf_seen_settled=<x> rtf_seen_drop=<y> asleep=<fraction at rest>
//
// `--drops` measures only the drop figures, once with sleeping on and once with it off (the
// link's `sleep=0`, the page's sleeping toggle), each in a fresh page: once the scene has run
// 3 s simulated, the same elastic bunny dropped on the middle of the floor, then the 4 s
// simulated after it (or 60 wall-clock seconds, whichever comes first), printed on
//   seen_drop scene=<path> quality=<q> sleeping=<on|off> rtf_drop=<x> sim=<s> wall=<s> asleep_before=<fraction>
import { launch } from '../tests/browser.mjs';

const url = process.env.MPM_URL || 'http://127.0.0.1:8080/';
const args = process.argv.slice(2);
let seconds = 8;
const i = args.indexOf('--seconds');
if (i >= 0) seconds = Number(args.splice(i, 2)[1]);
const noSettled = args.indexOf('--no-settled');
const settled = noSettled < 0;
if (!settled) args.splice(noSettled, 1);
const dropsAt = args.indexOf('--drops');
const drops = dropsAt >= 0;
if (drops) args.splice(dropsAt, 1);
// `--sleep on|off`: the drop figures with sleeping on or off only (default both).
const sl = args.indexOf('--sleep');
const sleepModes = sl >= 0 ? [args.splice(sl, 2)[1] === 'on'] : [true, false];
const q = args.indexOf('--quality');
// The level named in the link: without one the page would pick its own by its probe of this
// machine, and the Node half (`live-node.mjs`) measures the solver's default, Live.
const level = q >= 0 ? args.splice(q, 2)[1] : 'live';
const quality = `&quality=${level}`;
const width = Number(process.env.MPM_WIDTH || 1280), height = Number(process.env.MPM_HEIGHT || 720);

const browser = await launch({ width, height });
// What the page reports, whichever way it holds its simulation.
const sample = () => ({
  t: performance.now(),
  flush: window.mpm.stats.flushMs,
  render: window.mpm.stats.renderMs,
  stepping: window.mpm.stats.stepWallMs,
  sim: window.mpm.simTime ?? window.mpm.pg.time(),
  frames: window.mpm.stats.frames,
  particles: window.mpm.particleCount ?? window.mpm.pg.particleCount(),
  dim: window.mpm.domain.length,
});
// The page's clocks: wall time, simulated time and the share of the particles asleep.
const clock = (page) => page.evaluate(() => ({
  t: performance.now(), sim: window.mpm.simTime,
  asleep: (window.mpm.session.frame?.asleep ?? 0) / Math.max(1, window.mpm.session.frame?.count ?? 1),
}));
// An elastic bunny of the default size dropped on the middle of the floor, as a click does.
const dropBunny = (page) => page.evaluate(() => {
  const m = window.mpm, [w, , d] = m.sim.scene.domain.size;
  const point = m.domain.length === 3 ? [w / 2, 0, d / 2] : [w / 2, 0];
  return m.session.dropAt('bunny', 'elastic', point, 0, m.session.sizeRange().default);
});
// The drop figures: `scene` settled for 3 s simulated with sleeping `on` or off, an elastic
// bunny of the default size dropped on the middle of the floor, the 4 s after it.
async function dropFigure(scene, on) {
  const page = await browser.context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(`${url}#scene=${scene}${quality}${on ? '' : '&sleep=0'}`);
  await page.waitForFunction(() => window.mpm?.session?.dropAt && window.mpm.simTime >= 3, null, { timeout: 900_000 });
  const now = () => clock(page);
  const before = await now();
  await dropBunny(page);
  const d0 = await now();
  await page.waitForFunction((t) => window.mpm.simTime >= t, d0.sim + 4, { timeout: 60_000, polling: 100 }).catch(() => {});
  const d1 = await now();
  const wall = (d1.t - d0.t) / 1000;
  console.log(`seen_drop scene=${scene} quality=${level} sleeping=${on ? 'on' : 'off'} rtf_drop=${((d1.sim - d0.sim) / wall).toFixed(3)} ` +
    `sim=${(d1.sim - d0.sim).toFixed(3)} wall=${wall.toFixed(2)} asleep_before=${before.asleep.toFixed(3)}`);
  if (errors.length) console.log(`page errors (${scene}): ${errors.join('; ')}`);
  await page.close();
}
for (const scene of drops ? args : []) {
  for (const on of sleepModes) await dropFigure(scene, on);
}
for (const scene of drops ? [] : args) {
  const page = await browser.context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  await page.goto(`${url}#scene=${scene}${quality}`);
  await page.waitForFunction(() => window.mpm?.stats?.frames > 3, null, { timeout: 120_000 });
  await page.waitForTimeout(3000);
  const a = await page.evaluate(sample);
  await page.waitForTimeout(seconds * 1000);
  const b = await page.evaluate(sample);
  const wall = (b.t - a.t) / 1000;
  // How long a command waits for the simulation while it runs (a size check: no work of its
  // own), over 20 commands 50 ms apart.
  const waits = await page.evaluate(async () => {
    if (!window.mpm.session?.checkSize) return null;
    const out = [];
    for (let k = 0; k < 20; k++) {
      const t0 = performance.now();
      await window.mpm.session.checkSize(0.2);
      out.push(performance.now() - t0);
      await new Promise((r) => setTimeout(r, 50));
    }
    return out.sort((x, y) => x - y);
  });
  console.log(
    `seen scene=${scene} dim=${b.dim} particles=${b.particles} sim=${(b.sim - a.sim).toFixed(4)} wall=${wall.toFixed(3)} ` +
      `frames=${b.frames - a.frames} fps=${((b.frames - a.frames) / wall).toFixed(1)} rtf_seen=${((b.sim - a.sim) / wall).toFixed(3)}` +
      (b.flush === undefined ? '' : ` stepping_share=${((b.stepping - a.stepping) / 1000 / wall).toFixed(2)} ` +
        `frame_send_ms=${b.flush.toFixed(2)} draw_js_ms=${b.render.toFixed(2)}`) +
      (waits ? ` command_wait_ms=${waits[10].toFixed(1)} command_wait_max_ms=${waits[19].toFixed(1)}` : ''),
  );
  if (settled && (await page.evaluate(() => !!window.mpm.session?.dropAt))) {
    const now = () => clock(page);
    await page.waitForFunction(() => window.mpm.simTime >= 3, null, { timeout: 300_000 });
    const r0 = await now();
    await page.waitForTimeout(3000);
    const r1 = await now();
    await dropBunny(page);
    const d0 = await now();
    await page.waitForFunction((t) => window.mpm.simTime >= t, d0.sim + 2, { timeout: 15_000 }).catch(() => {});
    const d1 = await now();
    const rtf = (a, b) => ((b.sim - a.sim) / ((b.t - a.t) / 1000)).toFixed(3);
    console.log(`seen_settled scene=${scene} rtf_seen_settled=${rtf(r0, r1)} rtf_seen_drop=${rtf(d0, d1)} asleep=${r1.asleep.toFixed(3)}`);
  }
  if (errors.length) console.log(`page errors (${scene}): ${errors.join('; ')}`);
  await page.close();
}
await browser.close();
