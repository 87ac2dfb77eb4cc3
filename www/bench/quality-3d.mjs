// What the page's quality levels cost in accuracy in 3D, measured with the page's own solver
// (the release wasm of www/pkg/, built by `cargo xtask build`) under Node: the shipped
// axisymmetric column (`scenes/column_collapse_3d.json`, a = 2) sampled at each quality level
// as the page samples it, run 3 s in frames of 1/60 s with material at rest asleep (the
// page's default), then measured with the page's readouts (`measures()`): the run-out (the
// mean over the sectors, over R0) and the final height against Lube et al. (2004)'s
// axisymmetric laws, whose markers the page draws. The rows of `COLUMN_3D` in
// src/playground/quality.rs.
//
//   node www/bench/quality-3d.mjs [LEVEL...]
// prints `column3d quality=<id> factor=<f> ppc=<n> particles=<n> runout_error=<x> height_error=<y> …`.
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';

const root = fileURLToPath(new URL('../../', import.meta.url));
const wasm = await import(new URL('www/pkg/mpm.js', `file://${root}`));
wasm.initSync({ module: readFileSync(`${root}www/pkg/mpm_bg.wasm`) });
const text = readFileSync(`${root}scenes/column_collapse_3d.json`, 'utf8');
const levels = process.argv.slice(2).length ? process.argv.slice(2) : JSON.parse(wasm.qualityLevels()).levels.map((l) => l.id);
for (const level of levels) {
  const start = performance.now();
  const pg = new wasm.Playground(text, undefined, level);
  pg.setSleeping(true);
  const q = JSON.parse(pg.quality());
  pg.measures(); // the footprints, as the page records them on the first frame
  while (pg.time() < 3 - 1e-9) pg.frame(Math.min(1 / 60, 3 - pg.time()), 1e12);
  const d = JSON.parse(pg.measures())[0];
  const m = d.column;
  const ratio = d.runout.runout[0] / m.column.half_width;
  console.log(`column3d quality=${level} factor=${(q.cell_size / q.scene_cell_size).toFixed(4)} ppc=${q.particles_per_cell} ` +
    `particles=${pg.particleCount()} a=${m.column.aspect_ratio.toFixed(3)} runout_ratio=${ratio.toFixed(3)} law=${m.law.runout[0].toFixed(3)} ` +
    `runout_error=${(ratio / m.law.runout[0] - 1).toFixed(4)} height=${d.heap.height.toFixed(4)} law_height=${m.height.toFixed(4)} ` +
    `height_error=${(d.heap.height / m.height - 1).toFixed(4)} seconds=${((performance.now() - start) / 1000).toFixed(1)}`);
  pg.free();
}
