// The frame loop: each animation frame draws the latest frame the simulation sent (it steps in
// a Web Worker meanwhile; without one, it steps here first, within what is left of the frame's
// time budget), and every few frames refreshes the plots and the HUD. A frame with nothing new
// to show (paused, the camera still) is not drawn again, and while the simulation is slower
// than real time new frames are drawn at most TARGET_FPS times a second: on a machine that
// draws on the CPU (no GPU), the time saved goes to stepping.

import { TARGET_FPS } from './app.js';
import { format } from './params.js';
import { hud, hudRows, legend, toast } from './hud.js';
import { captionText } from './record.js';

export function startLoop(app) {
  let last = 0, lastDrawn = false, lastFresh = 0;
  const frame = (ts) => {
    requestAnimationFrame(frame);
    const wall = last ? Math.min(250, ts - last) : 1000 / 60;
    last = ts;
    const t0 = performance.now();
    // The stepping budget on the page's thread: what rendering leaves of 1/30 s, at least 4 ms.
    const budget = Math.min(40, Math.max(4, 1000 / TARGET_FPS - app.stats.otherMs - 2));
    const due = !app.stats.fellBehind || ts - lastFresh >= 1000 / TARGET_FPS - 4;
    const { frame: f, fresh } = app.session.take(budget, due);
    if (fresh) lastFresh = ts;
    const t1 = performance.now();
    if (!f) return;
    if (fresh) received(app, f);
    const drawn = app.viewChanged() || fresh;
    if (drawn) draw(app, f);
    const t2 = performance.now();
    // The time a drawn frame costs shows in the interval to the next animation frame.
    if (lastDrawn) app.governQuality(wall);
    lastDrawn = drawn;
    record(app, wall, fresh ? f : null, t1 - t0, t2 - t1, drawn);
    // Every few frames while it runs; every frame drawn while paused (a view that turns, the
    // hand tool), so that the HUD and plots show the state before the first Play.
    if (drawn && (app.stats.frames % 6 === 0 || !app.playing)) refresh(app, f);
  };
  requestAnimationFrame(frame);
}

/// What a new frame brings besides the particles: a failure, drops of the link refused, the
/// stress of the inspected particle, the energies.
function received(app, f) {
  if (f.failure && app.playing) app.fail(f.failure);
  const refused = app.refused(f.report.refused);
  if (refused.length) toast(`Ignored from the link: ${refused.join('; ')}`);
  if (f.state) app.stateChanged();
  // The energies count from the last change of bodies (a drop of the link landing, a body of
  // the scene entering at its time, as well as a click's drop, Clear and every start).
  const bodies = `${app.session.state.bodies}:${f.count}`;
  if (bodies !== app.energyBodies) app.energyPlot.restart();
  app.energyBodies = bodies;
  if (f.report.substeps > 0 && f.count > 0) app.energyPlot.push(f.diagnostics);
  const note = document.getElementById('pq-note');
  if (f.stress?.gone) {
    app.probeId = null;
    note.textContent = 'The inspected particle is gone.';
  } else if (f.stress && app.probeId !== null && f.stress.id === app.probeId) {
    const sp = f.stress;
    if (f.report.substeps > 0 || !app.stressPlot.point) app.stressPlot.push(sp);
    app.mohrPlot?.set(sp, app.domain.length);
    note.textContent = `particle #${sp.id} of body ${sp.body + 1} (${sp.model.replace('_', ' ')}): ` +
      `p = ${format(sp.p, 'Pa')}, q = ${format(sp.q, 'Pa')}, plastic strain ${sp.plastic_strain.toPrecision(2)}`;
  }
}

/// Draws the particles of frame `f` (coloured as chosen, the inspected one marked).
function draw(app, f) {
  smoothRange(app, f.range);
  const marker = app.probeId !== null && f.stress && !f.stress.gone ? f.stress.position : null;
  app.camera.matrices(app.canvas.clientWidth, app.canvas.clientHeight);
  app.renderer.draw({
    camera: app.camera, positions: f.positions, stride: f.stride, values: f.values, count: f.count,
    mode: app.view.colour, range: app.range, radius: app.radius, marker,
  });
  app.overlay?.draw({
    camera: app.camera, dim: app.domain.length, measures: app.readouts ? f.measures : [], hand: app.hand,
    show: { readouts: app.readouts, laws: app.readouts },
    particles: { positions: f.positions, stride: f.stride, count: f.count, radius: app.radius },
  });
  if (app.syncRender) app.renderer.finish(); // benchmarks: count the GPU's work in renderMs
  // A recording or a snapshot copies the frame now, while the drawing buffer holds it.
  app.recorder?.drawn(() => captionText(app.session.scene.name, f.time));
}

/// A colour range that grows at once and shrinks slowly, so that colours do not flicker.
function smoothRange(app, range) {
  const mode = app.view.colour;
  if (mode === 'body' || mode === 'yield' || !app.range || app.rangeMode !== mode) app.range = [range[0], range[1]];
  else app.range = [range[0], Math.max(range[1], 0.95 * app.range[1] + 0.05 * range[1])];
  app.rangeMode = mode;
}

/// The frame's figures: frames drawn per second, time per step, simulated per real time (from
/// the simulated time of the frames drawn), the timings.
function record(app, wall, f, simMs, renderMs, drawn) {
  const st = app.stats;
  const now = performance.now();
  st.simMs = simMs;
  if (drawn) {
    st.renderMs = 0.8 * st.renderMs + 0.2 * renderMs;
    st.drawn.push(now);
  }
  while (st.drawn.length && st.drawn[0] < now - 1000) st.drawn.shift();
  st.fps = st.drawn.length;
  if (f) {
    const r = f.report;
    st.flushMs = 0.9 * (st.flushMs || 0) + 0.1 * (f.flushMs || 0);
    st.stepWallMs = (st.stepWallMs || 0) + r.wall_ms;
    st.substeps = r.substeps;
    if (r.substeps > 0) st.msPerStep = r.ms_per_step;
    st.fellBehind = r.fell_behind;
    st.stableDt = f.stableDt;
    // Simulated per real time over the last second of frames.
    st.seen.push([now, f.time]);
    while (st.seen.length > 2 && st.seen[0][0] < now - 1000) st.seen.shift();
    const [a, b] = [st.seen[0], st.seen[st.seen.length - 1]];
    st.ratio = b[0] > a[0] && b[1] >= a[1] ? (b[1] - a[1]) / ((b[0] - a[0]) / 1000) : 0;
    if (b[1] < a[1]) st.seen = [b]; // a restart
  } else if (!app.playing) {
    st.substeps = 0;
    st.ratio = 0;
    st.seen = [];
  }
  if (drawn) st.frames++;
  app.timings.push({ wall, sim: simMs, render: renderMs, drawn, substeps: f ? f.report.substeps : 0, simTime: f ? f.report.sim_time : 0 });
  if (app.timings.length > 600) app.timings.shift();
}

/// The plots, the HUD and the legend.
function refresh(app, f) {
  const s = app.session;
  app.energyPlot.draw(app.domain.length === 2 ? 'energy (J/m)' : 'energy (J)');
  app.stressPlot.draw();
  const rows = hudRows(app.stats, f.diagnostics, {
    particles: f.count, asleep: f.asleep, playing: app.playing, stableDt: f.stableDt, time: f.time,
    renderer: app.renderer.kind, quality: app.quality, thread: s.kind,
    resolution: s.quality, label: app.qualityLabel(s.quality.quality), dim: app.domain.length, why: app.levelWhy,
  });
  hud(rows, app.playing && app.stats.fellBehind, app.hudDetails);
  app.mohrPlot?.draw();
  app.lessonPanel.measured(f);
  legend(app.view.colour, s.scene, app.range);
}
