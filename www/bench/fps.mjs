// Frame rate of the playground in headless Chromium (Debian's package; WebGL2 through
// SwiftShader, i.e. rendered on the CPU), and where the frame time goes.
//
//   MPM_URL=http://127.0.0.1:8080/ MPM_SCENE=www/test-scenes/bench_3d.json node www/bench/fps.mjs
// (`cargo xtask bench-web` serves the page and runs this.) Prints medians over MPM_SECONDS
// (default 10) of: frames per second; simulation and rendering milliseconds per frame; steps
// per frame; simulated time per real time. Phases: as a user sees it (the page lowers its
// rendering quality when frames are slow); at full quality; paused (rendering only) at full
// and at the lowest quality; running at the lowest quality.
import { launch } from '../tests/browser.mjs';

const url = process.env.MPM_URL || 'http://127.0.0.1:8080/';
const scene = process.env.MPM_SCENE || 'www/test-scenes/bench_3d.json';
const seconds = Number(process.env.MPM_SECONDS || 10);
const width = Number(process.env.MPM_WIDTH || 1280), height = Number(process.env.MPM_HEIGHT || 720);

const median = (v) => { const s = [...v].sort((a, b) => a - b); return s.length ? s[Math.floor(s.length / 2)] : NaN; };

const browser = await launch({ width, height });
const page = browser.page;
const errors = [];
page.on('pageerror', (e) => errors.push(e.message));
page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
await page.goto(`${url}#scene=${scene}&dim=3`);
await page.waitForFunction(() => window.mpm?.sim && mpm.stats.frames > 3, null, { timeout: 120_000 });
const info = await page.evaluate(() => ({
  particles: mpm.sim.particles,
  renderer: mpm.renderer.kind,
  gl: (() => {
    const gl = document.getElementById('view').getContext('webgl2');
    const ext = gl && gl.getExtension('WEBGL_debug_renderer_info');
    return gl ? (ext ? gl.getParameter(ext.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER)) : 'none';
  })(),
  canvas: [document.getElementById('view').width, document.getElementById('view').height],
}));
console.log(`scene=${scene} particles=${info.particles} renderer=${info.renderer} (${info.gl}) canvas=${info.canvas.join('x')}`);

async function phase(name, setup) {
  await page.evaluate(setup);
  await page.waitForTimeout(2000);
  await page.evaluate(() => { mpm.timings.length = 0; });
  await page.waitForTimeout(seconds * 1000);
  const t = await page.evaluate(() => mpm.timings.slice());
  const wall = t.map((x) => x.wall);
  const simTime = t.reduce((a, x) => a + x.simTime, 0), realTime = wall.reduce((a, b) => a + b, 0) / 1000;
  const r = {
    fps: 1000 / median(wall),
    sim_ms: median(t.map((x) => x.sim)),
    render_ms: median(t.map((x) => x.render)),
    steps_per_frame: median(t.map((x) => x.substeps)),
    sim_per_real: simTime / realTime,
    frames: t.length,
    quality: await page.evaluate(() => mpm.quality || 'full'),
  };
  console.log(`fps phase=${name} median_fps=${r.fps.toFixed(1)} sim_ms_per_frame=${r.sim_ms.toFixed(1)} ` +
    `render_ms_per_frame=${r.render_ms.toFixed(1)} steps_per_frame=${r.steps_per_frame} ` +
    `sim_time_per_real_time=${r.sim_per_real.toFixed(3)} frames=${r.frames} quality="${r.quality}"`);
  return r;
}

await phase('as-seen', () => { mpm.syncRender = false; mpm.playing = true; });
await phase('full-quality', () => { mpm.fixedQuality = true; mpm.setQuality(0); mpm.syncRender = true; });
await phase('paused-full-quality', () => { mpm.playing = false; });
await phase('paused-lowest-quality', () => { mpm.setQuality(4); });
await phase('lowest-quality', () => { mpm.playing = true; });
if (errors.length) console.log(`page errors: ${errors.join('; ')}`);
await browser.close();
