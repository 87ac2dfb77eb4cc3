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
  return quality === null ? new wasm.Playground(text, assets) : new wasm.Playground(text, assets, quality);
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
  pg.free();
}
