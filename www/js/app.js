// The page's state and what the user can do with it. What the user chose for the view (scene,
// dimension, colours, drop tool, time scale: the view part of the link) and the playback
// live here; the simulation's state (parameters, bodies dropped, Clear) lives in the solver's
// Playground behind `session` (session.js), which also records it for the link.

import { banner, toast, warnCost, warnFlip } from './hud.js';
import { readHash, writeHash, formatDrop } from './hash.js';
import { LEVELS, QualityGovernor, applyQuality } from './quality.js';
import { insideBox, nearestParticle } from './pointer.js';
import { SANDBOX, sceneSource } from './scenes.js';
import { Session } from './session.js';
import { buildDropControls, syncControls } from './controls.js';

/// Frames per second the page aims at (the frame's stepping budget and the quality governor).
export const TARGET_FPS = 30;

export class App {
  constructor({ session, renderer, camera, canvas, energyPlot, stressPlot, scenes, bunny }) {
    Object.assign(this, { session, renderer, camera, canvas, energyPlot, stressPlot, scenes, bunny });
    this.view = { scene: SANDBOX, dim: '3', colour: 'body', object: 'bunny', material: 'drucker_prager', time: '1' };
    this.size = 0.25; // of dropped objects (m)
    this.dropSpeed = 0;
    this.tool = 'drop';
    this.playing = true;
    this.stepOnce = false;
    this.probeId = null; // the stable id of the inspected particle
    this.sliders = new Map();
    this.stats = { fps: 0, substeps: 0, msPerStep: 0, ratio: 0, simMs: 0, renderMs: 0, otherMs: 0, fellBehind: false, frames: 0 };
    this.timings = []; // per frame, for benchmarks
    this.governor = new QualityGovernor(1000 / TARGET_FPS);
    this.quality = ''; // what the renderer gave up to keep the frame rate
    this.syncRender = false; // benchmarks: wait for the GPU in each frame
  }

  // For tests, benchmarks and curious students (window.mpm).
  get pg() { return this.session.pg; }
  get memory() { return this.session.memory; }
  get drops() { return this.session.session().drops; }
  get domain() { return this.session.scene.domain.size; }
  get cellSize() { return this.session.scene.cell_size; }
  set fixedQuality(on) { this.governor.fixed = on; }

  /// Sets the rendering quality level (0 full … `LEVELS.length - 1` lowest).
  setQuality(level) {
    this.governor.set(level, performance.now());
    this.quality = applyQuality(this.renderer, level);
  }

  /// Records a frame's time outside the simulation; lowers or raises the quality.
  governQuality(wall) {
    const level = this.governor.record(Math.max(0, wall - this.stats.simMs), performance.now());
    this.stats.otherMs = this.governor.otherMs;
    if (level !== null) this.quality = applyQuality(this.renderer, level);
  }

  /// Loads the scene of `this.view` and replays `session` ({params, cleared, drops}, from a
  /// link or kept across a 2D/3D switch); `ignored` lists what the link held that cannot be
  /// used, for the message.
  async loadScene(session = {}, ignored = []) {
    const token = (this.loadToken = (this.loadToken || 0) + 1);
    let source;
    try {
      source = await sceneSource(this.view.scene, this.view.dim, this.scenes);
    } catch (e) {
      toast(`Cannot load the scene: ${e.message}. Showing the sandbox.`);
      this.view.scene = SANDBOX;
      source = Session.sandbox(this.view.dim);
    }
    if (token !== this.loadToken) return; // a later choice overtook this one
    const out = this.session.load(source, this.bunny, session, this.view.dim);
    if (out.invalid) {
      toast(`The scene is invalid: ${out.invalid}`);
      this.view.scene = SANDBOX;
    }
    for (const msg of ignored) console.warn(`ignored from the link: ${msg}`);
    const refused = this.refused(out.refused);
    const messages = [...ignored, ...out.rejected, ...refused];
    if (messages.length) toast(`Ignored from the link: ${messages.join('; ')}`);
    const scene = this.session.scene;
    this.view.dim = String(scene.dim);
    this.camera.setDomain(this.domain);
    this.renderer.setDomain(this.domain);
    const ppc = scene.bodies.length ? Math.max(...scene.bodies.map((b) => b.particles_per_cell ?? 2)) : 2;
    this.radius = (0.55 * this.cellSize) / ppc;
    const sizes = this.session.sizeRange();
    this.sizeRange = sizes.offered;
    const sz = Number(this.view.size);
    this.size = Number.isFinite(sz) && sz > 0 ? sz : sizes.default;
    this.restarted();
    warnFlip(this.session);
    buildDropControls(this);
    syncControls(this);
    this.updateHash();
  }

  /// Loads what the link says (on the first visit, and when the hash changes).
  loadFromHash() {
    const { view, session, errors } = readHash(location.hash, this.session.table.names);
    Object.assign(this.view, view);
    return this.loadScene(session, errors);
  }

  /// The messages of drops the solver refused ([{drop, error}]), each warned about.
  refused(list = []) {
    return list.map(({ drop, error }) => {
      const msg = `drop=${formatDrop(drop)}: ${error}`;
      console.warn(`ignored from the link: ${msg}`);
      return msg;
    });
  }

  /// The state of the link: the view, and the session the solver recorded.
  updateHash() {
    writeHash({ ...this.view, size: +this.size.toPrecision(3) }, this.session.session());
  }

  /// Applies a live parameter; returns '' or the solver's error message (state unchanged).
  applyParam(name, value) {
    const s = this.session;
    const prediction = s.predict(name, value);
    const before = s.predict(name, s.parameter(name));
    const error = s.setParameter(name, value);
    if (error) return error;
    warnCost(s.table.spec(name), value, prediction, before, s);
    syncControls(this, false);
    this.updateHash();
    return '';
  }

  /// A click on the view at (px, py) CSS pixels: drops an object or inspects a particle.
  click(px, py) {
    this.camera.matrices(this.canvas.clientWidth, this.canvas.clientHeight);
    if (this.tool === 'inspect') return this.inspect(px, py);
    const p = this.camera.unproject(px, py);
    if (!insideBox(p, this.domain)) {
      toast(this.domain.length === 3 ? 'Click on the floor (inside the box) to drop.' : 'Click inside the box to drop.');
      return;
    }
    const point = this.domain.length === 3 ? p : p.slice(0, 2);
    const error = this.session.dropAt(this.view.object, this.view.material, point, this.dropSpeed, this.size);
    if (error) return toast(error);
    this.energyPlot.restart();
    this.updateHash();
  }

  /// Picks the particle nearest the click on screen (and nearest the eye among close ones).
  inspect(px, py) {
    const dim = this.domain.length;
    const i = nearestParticle(this.session.view(this.view.colour), dim, (x, y, z) => this.camera.project(x, y, z), px, py);
    this.stressPlot.clear();
    if (i < 0) {
      this.probeId = null;
      toast('No particle there: click on one.');
      return;
    }
    this.probeId = this.session.particleId(i);
    document.getElementById('pq-note').textContent = '';
  }

  /// Removes every body (the link records it).
  clear() {
    this.session.clear();
    this.restarted();
    this.updateHash();
  }

  /// Restarts the scene with the current parameters; the drops and a Clear are forgotten.
  reset() {
    const error = this.session.reset();
    if (error) toast(error);
    this.restarted();
    this.updateHash();
    syncControls(this);
  }

  /// What a new start forgets: the inspected particle, the plots, the failure banner.
  restarted() {
    this.probeId = null;
    this.stressPlot.clear();
    this.energyPlot.restart();
    banner('failed');
    banner('slow');
    banner('cfl');
  }

  togglePlay() {
    this.playing = !this.playing;
    syncControls(this, false);
  }

  step() {
    this.playing = false;
    this.stepOnce = true;
    syncControls(this, false);
  }

  /// The simulation stopped (non-finite state): pause and say so, with a way back.
  fail(message) {
    this.playing = false;
    syncControls(this, false);
    banner('failed', 'bad', `The simulation became unstable (${message}). A smaller CFL number or a softer material helps.`,
      { label: 'Reset', run: () => this.reset() });
  }
}

export { LEVELS };
