// The simulation host: the solver's Playground (wasm) and what drives it — the page's
// commands, stepping in real time within a time budget, and the frames handed to the renderer.
// It runs in a Web Worker (sim-worker.js), so that the page draws while it steps; where no
// worker starts, on the page's own thread, driven by the frame loop (session.js). Either way it
// talks in messages: commands in ({id, cmd, args}), replies ({type: 'reply', id, result,
// state}) and frames ({type: 'frame', …}) out. Everything the simulation holds (parameters,
// drops, pours, Clear, quality, failure) is the Playground's; this file only moves it.
//
// Frames: the particle positions and colour scalars of the latest step. In a worker they are
// copied (one memcpy each) from wasm memory into buffers that are transferred to the page, which
// gives them back once it has drawn a newer frame (no per-particle copy in JS, no allocation
// per frame); a frame is only sent when the page has drawn the one before. On the page's thread
// the frame is a view into wasm memory (no copy at all), valid until the next command.

import init, { Playground, assetPaths, checkLesson, handMeasure, parameterTable, qualityLevels, sandboxScene } from '../pkg/mpm.js';

/// The longest a slice of stepping takes (ms): a command waits at most this plus one step.
export const SLICE_MS = 8;
/// Wall-clock time owed to the simulation is capped (ms): a simulation slower than real time
/// runs in slow motion instead of piling up a debt.
const MAX_OWED_MS = 100;
/// Steps timed together by the level probe (`cmd_levelProbe`).
const PROBE_WINDOW = 4;

export class SimHost {
  /// Loads the solver; `post(message, transfer)` sends to the page; `transfer`: whether frames
  /// cross to another thread (copied into transferable buffers) or are read in place.
  static async create(post, transfer) {
    const wasm = await init();
    return new SimHost(wasm.memory, post, transfer);
  }

  constructor(memory, post, transfer) {
    Object.assign(this, { memory, post, transfer });
    this.pg = null;
    this.bunny = { obj: undefined, polygon: undefined };
    this.playing = true;
    this.stepOnce = false;
    this.scale = 1; // simulated per real time asked for
    this.colour = 'body';
    this.sleeping = true; // material at rest sleeps (kept through loads, Clear, Reset)
    this.probe = null; // stable id of the inspected particle
    this.wanted = true; // the page drew the last frame sent and takes another
    this.dirty = true; // something to show that was not sent
    this.stateChanged = false;
    this.behind = false; // the last slice ran out of time before it caught up
    this.failed = '';
    this.last = performance.now();
    this.owed = 0; // simulated time owed to real time (s)
    this.pool = []; // free buffers
    this.seq = 0;
    // Counts the starts (load, Clear, Reset, quality): every reply and frame carries it, so
    // that the page can tell a frame of the simulation before a start from one after it.
    this.generation = 0;
    this.flushMs = 0;
    this.pending = fresh();
  }

  /// A command from the page.
  handle({ id, cmd, args = {} }) {
    let result, error;
    try {
      result = this[`cmd_${cmd}`](args);
    } catch (e) {
      error = e.message;
    }
    if (id !== undefined) {
      const state = this.stateChanged && this.pg ? this.state() : undefined;
      this.stateChanged = false;
      this.post({ type: 'reply', id, result, error, state, generation: this.generation });
    }
    this.flush();
  }

  // --- commands -------------------------------------------------------------------------

  cmd_init() {
    return { table: parameterTable(), qualities: JSON.parse(qualityLevels()), transfer: this.transfer };
  }
  cmd_bunny({ obj, polygon }) {
    this.bunny = { obj, polygon };
    this.pg?.setBunny(obj, polygon);
  }
  cmd_assetPaths({ text }) {
    return assetPaths(text);
  }
  /// Validates a lesson with its scene file's text (none when inline) and the scene's files
  /// (JSON keyed by path as written); throws naming the field.
  cmd_checkLesson({ text, scene, assets }) {
    checkLesson(text, scene ?? undefined, assets ?? undefined);
  }
  /// The session as a scene file the CLI runs (see `Playground.saveScene`).
  cmd_saveScene() {
    return this.pg.saveScene();
  }
  /// The current values of live parameters `names` (also `bodies[i].<model>.<field>`); null
  /// for one that does not apply.
  cmd_values({ names }) {
    return names.map((n) => {
      try {
        return this.pg.parameter(n);
      } catch {
        return null;
      }
    });
  }
  /// Loads scene `source` ({text, assets} or {sandbox: dim}; an invalid one falls back to the
  /// sandbox of dimension `dim`, or with `keep` leaves the simulation as it was) at quality
  /// `session.quality` (the current one, else the default) and replays `session`. Returns what
  /// did not apply: {invalid, rejected, refused} (with `keep` and an invalid scene, only
  /// {invalid, kept: true}).
  cmd_load({ source, session = {}, dim, keep = false, playing }) {
    const levels = JSON.parse(qualityLevels());
    const current = this.pg ? JSON.parse(this.pg.quality()).quality : levels.default;
    const asked = session.quality ?? current;
    const quality = levels.levels.some((l) => l.id === asked) ? asked : current;
    let pg, invalid = '';
    try {
      const text = source.sandbox ? sandboxScene(Number(source.sandbox)) : source.text;
      pg = new Playground(text, source.assets ?? undefined, quality);
    } catch (e) {
      invalid = e.message;
      if (keep && this.pg) return { invalid, kept: true, rejected: [], refused: [] };
      pg = new Playground(sandboxScene(Number(dim)), undefined, quality);
    }
    try {
      pg.setBunny(this.bunny.obj, this.bunny.polygon);
    } catch (e) {
      console.warn(`the shipped bunny did not load (${e.message}); dropping a bunny made of balls`);
    }
    this.pg?.free();
    this.pg = pg;
    if (playing !== undefined) this.playing = playing;
    const out = JSON.parse(pg.replay(JSON.stringify({ ...session, quality: session.quality ?? quality })));
    this.restarted();
    return { invalid, ...out };
  }
  /// The level probe: what a time step of scene `source` sampled at level `quality` costs
  /// here. The scene is stepped from its start (its bodies falling and landing: the busy case,
  /// as after a drop) in windows of PROBE_WINDOW steps for `ms` ms of wall time; the steps and
  /// their sizes are the solver's own, the same on every machine, and only their cost is
  /// measured. The cost is that of the fastest tenth of the windows: the engine's optimised code
  /// (wasm tiers up while it runs) undisturbed by other work, which a slower window only adds
  /// to. Returns {ratio: the simulated seconds a real second steps at that cost, msPerStep,
  /// steps, particles}.
  cmd_levelProbe({ source, quality, ms = 1000 }) {
    const text = source.sandbox ? sandboxScene(Number(source.sandbox)) : source.text;
    const pg = new Playground(text, source.assets ?? undefined, quality);
    try {
      pg.setSleeping(this.sleeping);
      const t0 = performance.now();
      const windows = [];
      let sim = 0, steps = 0;
      while (performance.now() - t0 < ms && !pg.failure()) {
        const w0 = performance.now(), s0 = pg.time();
        for (let k = 0; k < PROBE_WINDOW; k++) pg.step();
        windows.push((performance.now() - w0) / PROBE_WINDOW);
        sim += pg.time() - s0;
        steps += PROBE_WINDOW;
      }
      windows.sort((a, b) => a - b);
      const msPerStep = windows[Math.floor(windows.length / 10)];
      return { ratio: sim / steps / (msPerStep / 1000), msPerStep, steps, particles: pg.particleCount() };
    } finally {
      pg.free();
    }
  }
  /// Sets a parameter; returns {error, prediction, before} (the cost of the new value and of
  /// the old one, see `Playground::predict`; null on error), the state unchanged on error.
  cmd_setParameter({ name, value }) {
    let costs;
    try {
      costs = JSON.parse(this.pg.setParameter(name, value, 1 / 60));
    } catch (e) {
      return { error: e.message, prediction: null, before: null };
    }
    this.changed();
    return { error: '', ...costs };
  }
  cmd_dropAt({ object, material, point, speed, size }) {
    this.pg.dropAt(object, material, new Float64Array(point), speed, size);
    this.changed();
  }
  cmd_checkSize({ size }) {
    this.pg.checkSize(size);
  }
  /// Starts pouring (see `Playground::start_pour`); throws naming the field.
  cmd_startPour({ point, material, rate }) {
    this.pg.startPour(new Float64Array(point), material, rate);
    this.changed();
  }
  /// Stops the pour running; returns how long it ran (s), or null when none ran.
  cmd_stopPour() {
    const held = this.pg?.stopPour();
    this.changed();
    return held ?? null;
  }
  cmd_checkRate({ rate }) {
    this.pg.checkRate(rate);
  }
  cmd_clear() {
    this.pg.clear();
    this.restarted();
  }
  cmd_reset({ playing }) {
    if (playing !== undefined) this.playing = playing;
    try {
      this.pg.reset();
    } finally {
      this.restarted();
    }
  }
  /// Samples the scene again at another quality level; returns the drops it refused.
  cmd_setQuality({ quality }) {
    const refused = JSON.parse(this.pg.setQuality(quality));
    this.restarted();
    return refused;
  }
  cmd_play({ playing }) {
    this.playing = playing;
    this.last = performance.now();
  }
  cmd_step() {
    this.playing = false;
    this.stepOnce = true;
  }
  cmd_timeScale({ scale }) {
    this.scale = scale;
  }
  cmd_colour({ mode }) {
    this.pg?.setColourMode(mode);
    this.colour = mode;
    this.dirty = true;
  }
  /// Sleeping on or off (Playground.setSleeping); kept for every scene loaded after.
  cmd_sleeping({ on }) {
    this.sleeping = !!on;
    this.pg?.setSleeping(this.sleeping);
    this.changed();
  }
  cmd_probe({ id }) {
    this.probe = id;
    this.dirty = true;
  }
  /// What a ruler and a protractor read between points `a` and `b` (m): {length,
  /// inclination} (the core's `mpm::measure`).
  cmd_handMeasure({ a, b }) {
    return JSON.parse(handMeasure(new Float64Array(a), new Float64Array(b)));
  }
  /// The stable id of the particle nearest `point` (where the page saw the particle picked).
  cmd_pick({ point }) {
    const i = this.pg.nearestParticle(new Float64Array(point));
    return i === undefined ? null : this.pg.particleId(i);
  }
  /// The page drew a newer frame: the buffers of the one before come back.
  cmd_drawn({ buffers = [] }) {
    for (const b of buffers) if (b) this.pool.push(b);
    // Keep the four largest: smaller ones are left from before bodies were added.
    this.pool.sort((a, b) => b.byteLength - a.byteLength).length = Math.min(this.pool.length, 4);
    this.wanted = true;
  }

  // --- stepping and frames ----------------------------------------------------------------

  /// The state the page reads between commands (the scene as it stands, the parameters, the
  /// session for the link, the quality and what it costs in accuracy).
  state() {
    const pg = this.pg;
    return {
      scene: JSON.parse(pg.sceneJson()),
      parameters: JSON.parse(pg.parameters()),
      session: JSON.parse(pg.session()),
      quality: JSON.parse(pg.quality()),
      sizeRange: JSON.parse(pg.sizeRange()),
      pourRates: JSON.parse(pg.pourRates()),
      pouring: pg.pouring(),
      particles: pg.particleCount(),
      bodies: pg.bodyCount(),
      sleeping: pg.sleeping(),
      failure: this.failed,
    };
  }

  changed() {
    this.stateChanged = true;
    this.dirty = true;
  }

  /// A new start (load, Clear, Reset, quality): the failure is forgotten.
  restarted() {
    this.generation++;
    this.failed = '';
    this.probe = null; // the page inspects again after a start
    this.pg.setColourMode(this.colour);
    if (this.pg.sleeping() !== this.sleeping) this.pg.setSleeping(this.sleeping);
    this.pending = fresh();
    this.last = performance.now();
    this.owed = 0;
    this.changed();
  }

  /// Steps for up to `budgetMs`: the simulated time owed to real time (one step after Step).
  /// Returns whether it ran out of time before it caught up. The debt carries over between
  /// slices, capped at MAX_OWED_MS of real time: behind real time, each slice steps whole
  /// steps until its budget runs out; ahead, it lands on real time.
  slice(budgetMs) {
    const now = performance.now();
    this.owed = Math.min((MAX_OWED_MS / 1000) * this.scale, this.owed + ((now - this.last) / 1000) * this.scale);
    this.last = now;
    this.behind = false;
    const pg = this.pg;
    if (!pg || this.failed || !(this.playing || this.stepOnce)) {
      this.owed = 0;
      return false;
    }
    let report;
    try {
      report = JSON.parse(this.stepOnce ? pg.step() : pg.frame(this.owed, budgetMs));
    } catch (e) {
      this.failed = e.message;
      this.playing = false;
      this.changed();
      return false;
    }
    if (!this.stepOnce) this.owed = Math.max(0, this.owed - report.sim_time);
    this.stepOnce = false;
    const p = this.pending;
    p.substeps += report.substeps;
    p.sim_time += report.sim_time;
    p.wall_ms += report.wall_ms;
    p.fell_behind ||= report.fell_behind;
    if (report.substeps > 0) p.ms_per_step = report.ms_per_step;
    p.stable_dt = report.stable_dt;
    if (report.refused) {
      p.refused.push(...report.refused);
      this.stateChanged = true;
    }
    // A drop of the link landed, or a body of the scene entered (`appear_at`).
    if (this.pg.bodyCount() !== this.bodies || this.pg.particleCount() !== this.particles) this.stateChanged = true;
    if (report.substeps > 0 || report.refused) this.dirty = true;
    this.behind = report.fell_behind;
    return this.behind;
  }

  /// Sends a frame if there is something new and the page is ready for it.
  flush() {
    if (!this.pg || !this.dirty || !this.wanted) return;
    const t0 = performance.now();
    const pg = this.pg;
    const range = pg.updateColours();
    const count = pg.particleCount();
    const stride = pg.positionsStride();
    let positions = new Float32Array(this.memory.buffer, pg.positionsPtr(), pg.positionsLen());
    let values = new Float32Array(this.memory.buffer, pg.coloursPtr(), pg.coloursLen());
    const transfer = [];
    if (this.transfer) {
      const b = this.buffers(positions.length, values.length);
      b.positions.set(positions);
      b.values.set(values);
      positions = b.positions.subarray(0, positions.length);
      values = b.values.subarray(0, values.length);
      transfer.push(b.positions.buffer, b.values.buffer);
    }
    let stress = null;
    if (this.probe !== null) {
      const i = pg.indexOf(this.probe);
      stress = i === undefined ? { gone: true } : JSON.parse(pg.stressPoint(i));
    }
    const report = this.pending;
    this.pending = fresh();
    this.bodies = pg.bodyCount();
    this.particles = count;
    const message = {
      type: 'frame', seq: ++this.seq, generation: this.generation, positions, values, stride, count, range,
      time: pg.time(), stableDt: pg.stableDt(), report, stress, asleep: pg.asleep(),
      // each sand body's flank angles, run-out and the experiments' markers (mpm::measure)
      measures: JSON.parse(pg.measures()),
      diagnostics: JSON.parse(pg.diagnostics()),
      failure: this.failed,
      state: this.stateChanged ? this.state() : undefined,
      flushMs: this.flushMs, // what the frame before cost to send (colours, copies, records)
    };
    this.stateChanged = false;
    this.dirty = false;
    this.wanted = !this.transfer; // on the page's thread the page draws before the next slice
    this.post(message, transfer);
    this.flushMs = performance.now() - t0;
  }

  /// Two free buffers for `n` positions and `m` colour values (new ones when none is large
  /// enough).
  buffers(n, m) {
    const take = (floats) => {
      const i = this.pool.findIndex((b) => b.byteLength >= 4 * floats);
      return i >= 0 ? this.pool.splice(i, 1)[0] : new ArrayBuffer(4 * Math.ceil(1.25 * floats + 256));
    };
    return { positions: new Float32Array(take(n)), values: new Float32Array(take(m)) };
  }
}

/// What the slices since the last frame did, summed.
function fresh() {
  return { substeps: 0, sim_time: 0, wall_ms: 0, fell_behind: false, ms_per_step: 0, stable_dt: 0, refused: [] };
}
