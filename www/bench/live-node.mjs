// The real-time factor of stepping alone: simulated seconds per wall-clock second of the
// release wasm (www/pkg/, built by `cargo xtask build`) in Node, for each scene given, at the
// playground's default quality (the solver's `qualityLevels().default`, when the build has
// quality levels). `cargo xtask live` runs this pinned to one core (`taskset -c 0`).
//
//   node www/bench/live-node.mjs [--seconds S] [--sim T] [--quality Q] SCENE.json...
// prints one line per scene:
//   step scene=<path> dim=<d> particles=<n> quality=<q> sim=<s> wall=<s> steps=<k> ms_per_step=<x> rtf_step=<y>
// Each scene runs from its start for T simulated seconds (default 1.5: the fall and the impact
// of the bunny scenes, the collapse of the sand) or S wall-clock seconds (default 12),
// whichever comes first, after a warm-up on a separate copy of the scene (V8 runs wasm in its
// baseline compiler first and tiers hot functions up). `--quality` picks another level.
//
// Then the settled phase (unless `--no-settled`): the scene runs on to 3 s simulated (sleeping
// on, the page's default), and four windows are timed, each a real-time factor of stepping:
//   rtf_settled        1 s at rest, sleeping on;
//   rtf_settled_awake  1 s at rest, sleeping off (everything stepped);
//   rtf_drop           2 s after a bunny (elastic, the page's default size) is dropped on the
//                      middle of the floor through the session's drop API, sleeping on;
//   rtf_drop_awake     the same drop on a second copy settled the same way, sleeping off.
// printed on one line per scene:
//   settled scene=<path> rtf_settled=<x> rtf_settled_awake=<x> rtf_drop=<x> rtf_drop_awake=<x> asleep=<fraction at rest>
// Each window stops early after `--seconds` of wall-clock time.
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { performance } from 'node:perf_hooks';

const root = fileURLToPath(new URL('../../', import.meta.url));
const args = process.argv.slice(2);
const option = (name, fallback) => {
  const i = args.indexOf(name);
  if (i < 0) return fallback;
  const v = Number(args[i + 1]);
  args.splice(i, 2);
  return v;
};
const seconds = option('--seconds', 12);
const noSettled = args.indexOf('--no-settled');
const settled = noSettled < 0;
if (!settled) args.splice(noSettled, 1);
const simSeconds = option('--sim', 1.5);
const q = args.indexOf('--quality');
const asked = q >= 0 ? args.splice(q, 2)[1] : null;
const scenes = args;

const wasm = await import(new URL('www/pkg/mpm.js', `file://${root}`));
wasm.initSync({ module: readFileSync(`${root}www/pkg/mpm_bg.wasm`) });
const quality = wasm.qualityLevels ? asked ?? JSON.parse(wasm.qualityLevels()).default : null;

/// A playground over the scene file at `path` (relative to the repository root).
function load(path) {
  const text = readFileSync(`${root}${path}`, 'utf8');
  const dir = path.slice(0, path.lastIndexOf('/') + 1);
  const files = wasm.assetPaths(text);
  const assets = files.length
    ? JSON.stringify(Object.fromEntries(files.map((f) => [f, readFileSync(`${root}${dir}${f}`, 'utf8')])))
    : undefined;
  const pg = quality === null ? new wasm.Playground(text, assets) : new wasm.Playground(text, assets, quality);
  pg.setBunny?.(readFileSync(`${root}scenes/bunny.obj`, 'utf8'), readFileSync(`${root}scenes/bunny2d.txt`, 'utf8'));
  return pg;
}

/// Steps `pg` for `t` simulated seconds (at most `seconds` of wall-clock time); returns the
/// real-time factor of that window.
function timed(pg, t) {
  const end = pg.time() + t;
  const start = performance.now();
  let wall = 0;
  const t0 = pg.time();
  while (pg.time() < end && wall < seconds * 1000) {
    pg.step();
    wall = performance.now() - start;
  }
  return (pg.time() - t0) / Math.max(1e-9, wall / 1000);
}

/// Runs `pg` on to 3 s simulated, sleeping on (no figure taken).
function settle(pg) {
  pg.setSleeping(true);
  while (pg.time() < 3) pg.step();
}

/// Drops the page's default bunny on the middle of the floor.
function dropBunny(pg) {
  const scene = JSON.parse(pg.sceneJson());
  const size = JSON.parse(pg.sizeRange()).default;
  const [w, , d] = scene.domain.size;
  const point = pg.dim() === 3 ? [w / 2, 0, d / 2] : [w / 2, 0];
  pg.dropAt('bunny', 'elastic', new Float64Array(point), 0, size);
}

/// The settled-phase figures of `pg` (already run from its start) and a second copy of `path`.
function settledPhase(pg, path) {
  settle(pg);
  const rest = timed(pg, 1);
  const asleep = pg.asleep() / Math.max(1, pg.particleCount());
  pg.setSleeping(false);
  const restAwake = timed(pg, 1);
  pg.setSleeping(true);
  timed(pg, 0.5); // back to sleep
  dropBunny(pg);
  const drop = timed(pg, 2);
  const other = load(path);
  settle(other);
  other.setSleeping(false);
  dropBunny(other);
  const dropAwake = timed(other, 2);
  other.free();
  const f = (x) => x.toFixed(3);
  console.log(
    `settled scene=${path} rtf_settled=${f(rest)} rtf_settled_awake=${f(restAwake)} rtf_drop=${f(drop)} ` +
      `rtf_drop_awake=${f(dropAwake)} asleep=${asleep.toFixed(3)}`,
  );
}

for (const path of scenes) {
  const warm = load(path);
  const t0 = performance.now();
  for (let i = 0; i < 30 || performance.now() - t0 < 2000; i++) warm.step();
  warm.free();
  const pg = load(path);
  const n = pg.particleCount();
  let steps = 0;
  const start = performance.now();
  let wall = 0;
  while (pg.time() < simSeconds && wall < seconds * 1000) {
    pg.step();
    steps++;
    wall = performance.now() - start;
  }
  const sim = pg.time();
  console.log(
    `step scene=${path} dim=${pg.dim()} particles=${n} quality=${quality ?? 'scene'} sim=${sim.toFixed(4)} ` +
      `wall=${(wall / 1000).toFixed(3)} steps=${steps} ms_per_step=${(wall / steps).toFixed(3)} ` +
      `rtf_step=${(sim / (wall / 1000)).toFixed(3)}`,
  );
  if (settled && pg.setSleeping) settledPhase(pg, path);
  pg.free();
}
