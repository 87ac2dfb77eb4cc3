// The frame loop: each animation frame advances the simulation by a frame's worth of time
// within what is left of the frame's time budget, draws the particles straight from wasm
// memory, and every few frames refreshes the plots and the HUD.

import { TARGET_FPS } from './app.js';
import { format } from './params.js';
import { hud, hudRows, legend, toast } from './hud.js';

export function startLoop(app) {
  let last = 0;
  const frame = (ts) => {
    requestAnimationFrame(frame);
    const wall = last ? Math.min(250, ts - last) : 1000 / 60;
    last = ts;
    const t0 = performance.now();
    const report = advance(app, wall);
    const t1 = performance.now();
    const n = draw(app, report);
    const t2 = performance.now();
    record(app, wall, report, t1 - t0, t2 - t1);
    if (app.stats.frames % 6 === 0) refresh(app, n);
  };
  requestAnimationFrame(frame);
}

/// Steps for a frame that took `wall` ms (one step after Step); returns the solver's report,
/// or null when nothing ran.
function advance(app, wall) {
  const s = app.session;
  if (!((app.playing || app.stepOnce) && !s.failure())) return null;
  // The stepping budget: what the rest of the frame (rendering, compositing) leaves of
  // 1/30 s, and at least one step.
  const budget = Math.min(40, Math.max(4, 1000 / TARGET_FPS - app.stats.otherMs - 2));
  const simTime = app.stepOnce ? null : (Math.min(wall, 100) / 1000) * Number(app.view.time);
  app.stepOnce = false;
  let report = null;
  try {
    report = s.advance(simTime, budget);
  } catch (e) {
    app.fail(e.message);
    return null;
  }
  const refused = app.refused(report.refused);
  if (refused.length) {
    toast(`Ignored from the link: ${refused.join('; ')}`);
    app.updateHash();
  }
  return report;
}

/// Draws the particles (coloured as chosen, the inspected one marked); returns their count.
function draw(app, report) {
  const v = app.session.view(app.view.colour);
  smoothRange(app, v.range);
  let marker = null;
  if (app.probeId !== null) {
    const sp = app.session.stressPoint(app.probeId);
    const note = document.getElementById('pq-note');
    if (!sp) {
      app.probeId = null;
      note.textContent = 'The inspected particle is gone.';
    } else {
      marker = sp.position;
      if (report || !app.stressPlot.point) app.stressPlot.push(sp);
      note.textContent = `particle #${sp.id} of body ${sp.body + 1} (${sp.model.replace('_', ' ')}): ` +
        `p = ${format(sp.p, 'Pa')}, q = ${format(sp.q, 'Pa')}, plastic strain ${sp.plastic_strain.toPrecision(2)}`;
    }
  }
  app.camera.matrices(app.canvas.clientWidth, app.canvas.clientHeight);
  app.renderer.draw({ camera: app.camera, ...v, mode: app.view.colour, range: app.range, radius: app.radius, marker });
  if (app.syncRender) app.renderer.finish(); // benchmarks: count the GPU's work in renderMs
  return v.count;
}

/// A colour range that grows at once and shrinks slowly, so that colours do not flicker.
function smoothRange(app, range) {
  const mode = app.view.colour;
  if (mode === 'body' || mode === 'yield' || !app.range || app.rangeMode !== mode) app.range = [range[0], range[1]];
  else app.range = [range[0], Math.max(range[1], 0.95 * app.range[1] + 0.05 * range[1])];
  app.rangeMode = mode;
}

/// The frame's figures: fps, time per step, simulated per real time, the timings.
function record(app, wall, report, simMs, renderMs) {
  const st = app.stats;
  const fps = 1000 / Math.max(1, wall);
  st.fps = st.fps ? 0.9 * st.fps + 0.1 * fps : fps;
  st.simMs = simMs;
  st.renderMs = 0.8 * st.renderMs + 0.2 * renderMs;
  app.governQuality(wall);
  if (report) {
    st.substeps = report.substeps;
    if (report.substeps > 0) st.msPerStep = report.ms_per_step;
    st.fellBehind = report.fell_behind;
    const ratio = report.sim_time / (wall / 1000);
    st.ratio = st.ratio ? 0.9 * st.ratio + 0.1 * ratio : ratio;
    if (app.session.pg.particleCount() > 0) app.energyPlot.push(app.session.diagnostics());
  } else if (!app.playing) {
    st.substeps = 0;
    st.ratio = 0;
  }
  st.frames++;
  app.timings.push({ wall, sim: simMs, render: renderMs, substeps: report ? report.substeps : 0, simTime: report ? report.sim_time : 0 });
  if (app.timings.length > 600) app.timings.shift();
}

/// The plots, the HUD and the legend.
function refresh(app, n) {
  const s = app.session;
  app.energyPlot.draw(app.domain.length === 2 ? 'energy (J/m)' : 'energy (J)');
  app.stressPlot.draw();
  const rows = hudRows(app.stats, s.diagnostics(), {
    particles: n, playing: app.playing, stableDt: s.pg.stableDt(), time: s.pg.time(),
    renderer: app.renderer.kind, quality: app.quality,
  });
  hud(rows, app.playing && app.stats.fellBehind);
  legend(app.view.colour, s.scene, app.range);
}
