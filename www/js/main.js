// The MPM playground page: starts the solver (wasm, in a Web Worker), loads the scene list and
// the shipped bunny, builds the controls from the solver's parameter table, opens the scene of
// the link (or a sand scene on a first visit) and starts the frame loop. See app.js for the
// state and its actions, session.js for the simulation, loop.js for the frame loop.

import { App } from './app.js';
import { Camera } from './camera.js';
import { buildControls } from './controls.js';
import { banner } from './hud.js';
import { startLoop } from './loop.js';
import { EnergyPlot, StressPlot } from './plots.js';
import { setupPointer } from './pointer.js';
import { GlRenderer } from './render-gl.js';
import { CanvasRenderer } from './render-2d.js';
import { loadBunny, loadSceneList } from './scenes.js';
import { Session } from './session.js';

const $ = (id) => document.getElementById(id);

async function main() {
  const canvas = $('view');
  let renderer;
  try {
    renderer = new GlRenderer(canvas);
  } catch (e) {
    console.warn(`WebGL2 unavailable (${e.message}); using the 2D canvas fallback`);
    renderer = new CanvasRenderer(canvas);
  }
  let session, scenes, bunny;
  try {
    [session, scenes, bunny] = await Promise.all([Session.start(), loadSceneList(), loadBunny()]);
  } catch (e) {
    banner('failed', 'bad', `The solver did not load (${e.message}). Build it first: cargo xtask build (or cargo xtask serve).`);
    return;
  }
  await session.setBunny(bunny);
  const app = new App({
    session, renderer, canvas, scenes,
    camera: new Camera([2, 1, 1]),
    energyPlot: new EnergyPlot($('energy')),
    stressPlot: new StressPlot($('pq')),
  });
  window.mpm = app; // for tests, benchmarks and curious students
  if (!location.hash) {
    // First visit: a scene with sand, if the scene list has one.
    const pick = ['bunny_on_sand_ball', 'notched_sand_block', 'column_collapse'].find((b) => scenes.some((s) => s.base === b));
    if (pick) app.view.scene = pick;
  }
  buildControls(app);
  setupPointer(canvas, app.camera, (x, y) => app.click(x, y));
  await app.loadFromHash();
  startLoop(app);
}

main();
