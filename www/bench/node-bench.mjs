// Time per step of a scene in the release wasm (www/pkg/, built by `cargo xtask build`) under
// Node, the same steps as `cargo bench --bench playground` takes natively.
//
//   node www/bench/node-bench.mjs SCENE.json [STEPS]    (MPM_PKG=DIR: another build)
// prints `wasm scene=<path> particles=<n> steps=<k> median_ms_per_step=<x> mean_ms_per_step=<y>`.
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { performance } from 'node:perf_hooks';

const root = fileURLToPath(new URL('../../', import.meta.url));
const [path = 'www/test-scenes/bench_3d.json', stepsArg = '200'] = process.argv.slice(2);
const steps = Number(stepsArg);

// MPM_PKG: another build's directory of `mpm.js` and `mpm_bg.wasm` (one wasm-opt level
// against another), instead of www/pkg/.
const pkg = process.env.MPM_PKG ? `${process.env.MPM_PKG.replace(/\/$/, '')}/` : `${root}www/pkg/`;
const wasm = await import(new URL('mpm.js', `file://${pkg}`));
wasm.initSync({ module: readFileSync(`${pkg}mpm_bg.wasm`) });

const text = readFileSync(`${root}${path}`, 'utf8');
const dir = path.slice(0, path.lastIndexOf('/') + 1);
const files = wasm.assetPaths(text);
const assets = files.length
  ? JSON.stringify(Object.fromEntries(files.map((f) => [f, readFileSync(`${root}${dir}${f}`, 'utf8')])))
  : undefined;
// The scene as written (the `fine` quality level), as the native bench loads it: the page's
// default level resamples it more coarsely.
const pg = wasm.qualityLevels ? new wasm.Playground(text, assets, 'fine') : new wasm.Playground(text, assets);
// Warm up: V8 first runs wasm in its baseline compiler (Liftoff) and tiers hot functions up
// to TurboFan; a step-sized function needs a few dozen calls before it is tiered up.
const warm = performance.now();
for (let i = 0; i < 30 || performance.now() - warm < 3000; i++) pg.step();
const times = [];
for (let i = 0; i < steps; i++) {
  const t = performance.now();
  pg.step();
  times.push(performance.now() - t);
}
const mean = times.reduce((a, b) => a + b, 0) / steps;
times.sort((a, b) => a - b);
console.log(
  `wasm scene=${path} particles=${pg.particleCount()} steps=${steps} ` +
    `median_ms_per_step=${times[Math.floor(steps / 2)].toFixed(4)} mean_ms_per_step=${mean.toFixed(4)}`,
);
