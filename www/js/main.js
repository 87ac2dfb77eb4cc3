// The MPM playground page: starts the solver (wasm, in a Web Worker), loads the scene and
// lesson lists and the shipped bunny, builds the controls from the solver's parameter table,
// opens the scene or lesson of the link (or the default, a sand scene) and starts the
// frame loop. See app.js for the
// state and its actions, session.js for the simulation, loop.js for the frame loop.

import { App } from './app.js';
import { Camera } from './camera.js';
import { buildControls } from './controls.js';
import { setupFiles } from './files.js';
import { setupFolding } from './fold.js';
import { buildLessonMenu, loadLessonList } from './lessons.js';
import { setupRecording } from './record.js';
import { banner } from './hud.js';
import { startLoop } from './loop.js';
import { EnergyPlot, MohrPlot, StressPlot } from './plots.js';
import { Overlay } from './overlay.js';
import { setupPointer } from './pointer.js';
import { GlRenderer } from './render-gl.js';
import { CanvasRenderer } from './render-2d.js';
import { loadBunny, loadSceneList } from './scenes.js';
import { Session } from './session.js';
import { Lab } from './lab.js';

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
  setupFolding();
  let session, scenes, lessons, bunny;
  try {
    [session, scenes, lessons, bunny] = await Promise.all([Session.start(), loadSceneList(), loadLessonList(), loadBunny()]);
  } catch (e) {
    banner('failed', 'bad', `The solver did not load (${e.message}). Build it first: cargo xtask build (or cargo xtask serve).`);
    return;
  }
  await session.setBunny(bunny);
  const app = new App({
    session, renderer, canvas, scenes, lessons,
    camera: new Camera([2, 1, 1]),
    energyPlot: new EnergyPlot($('energy')),
    stressPlot: new StressPlot($('pq')),
    mohrPlot: new MohrPlot($('mohr')),
    overlay: new Overlay($('overlay')),
  });
  window.mpm = app; // for tests, benchmarks and curious students
  window.mpmLab = app.lab = new Lab(app);
  buildControls(app);
  buildLessonMenu(app, lessons);
  setupFiles(app, document.querySelector('.stage'));
  setupRecording(app);
  setupPointer(canvas, app.camera, (x, y) => app.click(x, y), {
    active: () => app.tool === 'measure',
    drag: (from, to, done) => app.measureDrag(from, to, done),
  }, {
    active: () => app.tool === 'pour',
    start: (x, y) => app.startPour(x, y),
    stop: () => app.stopPour(),
  });
  for (const [id, key] of [['hud-details', 'hudDetails'], ['readouts', 'readouts']]) {
    $(id).addEventListener('click', () => {
      app[key] = !app[key];
      $(id).setAttribute('aria-pressed', String(app[key]));
      app.redraw();
    });
  }
  await app.loadFromHash();
  startLoop(app);
}

main();
