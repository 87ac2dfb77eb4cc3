// The simulation behind the page, as the page sees it: the solver's Playground runs in a Web
// Worker (sim-worker.js, with sim-host.js), or on the page's own thread where no worker starts.
// Commands go out as messages and come back as promises of plain data (an error message is a
// string, '' for none); what the page reads between commands (the scene, the parameters, the
// session for the link, the quality) is the state the host sent last, and what it draws is the
// latest frame (positions and colour scalars, transferred or read in place).

import { paramTable } from './params.js';

/// How long the worker may take to load the solver before the page steps on its own thread (ms).
const WORKER_START_MS = 20_000;

export class Session {
  /// Starts the simulation host: in a worker, unless `worker` is false or none starts (then on
  /// this thread). Throws if the solver cannot load.
  static async start({ worker = true } = {}) {
    if (worker && typeof Worker !== 'undefined') {
      try {
        return await Session.inWorker();
      } catch (e) {
        console.warn(`no simulation worker (${e.message}); the simulation runs on the page's thread`);
      }
    }
    const s = new Session();
    const { SimHost } = await import('./sim-host.js');
    const host = await SimHost.create((m) => s.receive(m), false);
    s.host = host;
    s.send = (m) => queueMicrotask(() => host.handle(m));
    s.kind = 'main thread';
    await s.init();
    return s;
  }

  static async inWorker() {
    const s = new Session();
    const w = new Worker(new URL('./sim-worker.js', import.meta.url), { type: 'module' });
    w.onmessage = (e) => s.receive(e.data);
    s.send = (m, transfer = []) => w.postMessage(m, transfer);
    s.worker = w;
    s.kind = 'worker';
    try {
      await new Promise((resolve, reject) => {
        const timer = setTimeout(() => reject(new Error('it did not start')), WORKER_START_MS);
        const fail = (message) => { clearTimeout(timer); reject(new Error(message)); };
        w.addEventListener('error', (e) => fail(e.message || 'it failed to load'), { once: true });
        s.onFailed = fail;
        s.init().then(() => { clearTimeout(timer); resolve(); }, (e) => fail(e.message));
      });
    } catch (e) {
      w.terminate();
      throw e;
    }
    return s;
  }

  constructor() {
    this.nextId = 0;
    this.waiting = new Map();
    this.state = null; // the host's state: scene, parameters, session, quality, sizeRange, …
    this.frame = null; // the latest frame
    this.unseen = null; // a frame not drawn yet
    this.host = null; // on the page's thread: the host itself
    this.onFrame = null;
    // The host's count of starts (load, Clear, Reset, quality) when it last replied: a frame
    // of an earlier one is of the simulation as it was before, and is never shown.
    this.generation = 0;
  }

  async init() {
    const r = await this.request('init');
    this.table = paramTable(r.table);
    this.qualities = r.qualities;
    this.transfer = r.transfer;
  }

  /// A command; resolves with its result (rejects with the solver's message).
  request(cmd, args) {
    const id = this.nextId++;
    return new Promise((resolve, reject) => {
      this.waiting.set(id, { resolve, reject });
      this.send({ id, cmd, args });
    });
  }
  /// A command without an answer.
  tell(cmd, args, transfer) {
    this.send({ cmd, args }, transfer);
  }

  receive(m) {
    if (m.type === 'frame' && m.generation < this.generation) {
      if (this.transfer) this.tell('drawn', { buffers: buffersOf(m) }, buffersOf(m));
      return;
    }
    if (m.state) this.state = m.state;
    if (m.type === 'reply') {
      if (m.generation > this.generation) this.started(m.generation);
      const w = this.waiting.get(m.id);
      this.waiting.delete(m.id);
      if (m.error !== undefined) w?.reject(new Error(m.error));
      else w?.resolve(m.result);
    } else if (m.type === 'frame') {
      // A frame not drawn yet is replaced: its buffers go back at once.
      if (this.unseen && this.transfer) this.tell('drawn', { buffers: buffersOf(this.unseen) }, buffersOf(this.unseen));
      this.unseen = m;
      this.onFrame?.(m);
    } else if (m.type === 'failed') this.onFailed?.(m.error);
  }

  /// The host started the simulation again (generation `g`): the frames of the one before,
  /// drawn or not, are dropped (their buffers go back), so that nothing of it is shown, plotted
  /// or measured after the start: the next frame is the new start's.
  started(g) {
    this.generation = g;
    for (const f of [this.unseen, this.frame]) if (f && this.transfer) this.tell('drawn', { buffers: buffersOf(f) }, buffersOf(f));
    this.unseen = null;
    this.frame = null;
  }

  /// The frame to draw now: a new one if it came and `fresh` is wanted (the one drawn before
  /// goes back to the host), else the last one. On the page's thread, steps for up to
  /// `budgetMs` first.
  take(budgetMs = 0, fresh = true) {
    if (this.host) {
      this.host.slice(budgetMs);
      this.host.flush();
    }
    if (this.unseen && fresh) {
      const old = this.frame;
      this.frame = this.unseen;
      this.unseen = null;
      if (this.transfer) this.tell('drawn', { buffers: old ? buffersOf(old) : [] }, old ? buffersOf(old) : []);
      return { frame: this.frame, fresh: true };
    }
    return { frame: this.frame, fresh: false };
  }

  // --- what the page reads ------------------------------------------------------------------

  get scene() { return this.state.scene; }
  parameter(name) { return this.state.parameters[name]; }
  parameters() { return this.state.parameters; }
  session() { return this.state.session; }
  sizeRange() { return this.state.sizeRange; }
  /// The rates a pour may have here, and its spout: {unit, radius, height, exit_area, allowed,
  /// offered, default, speeds} (see `Playground::pour_rates`).
  pourRates() { return this.state.pourRates; }
  get quality() { return this.state.quality; }

  // --- commands -------------------------------------------------------------------------------

  /// The files scene `text` references, relative to it.
  assetPaths(text) { return this.request('assetPaths', { text }); }
  /// The shipped bunny ({obj, polygon}) for dropped bunnies.
  setBunny(bunny) { return this.request('bunny', bunny); }
  /// Loads scene `source` ({text, assets} or {sandbox: dim}; an invalid one falls back to the
  /// sandbox of dimension `dim`, or with `keep` leaves the simulation as it was) and replays
  /// `session` ({quality, params, cleared, drops, pours}); with `playing` false it starts paused (a
  /// lesson that asks first: not a step before Play). Resolves to what did not apply:
  /// {invalid, rejected, refused, kept}.
  load(source, session, dim, keep = false, playing = undefined) { return this.request('load', { source, session, dim, keep, playing }); }
  /// Validates a lesson (its text, its scene file's text or null, the scene's files as JSON);
  /// rejects with the message naming the field.
  checkLesson(text, scene, assets) { return this.request('checkLesson', { text, scene, assets }); }
  /// The session as a scene file (JSON text) the CLI runs: drops enter at their times.
  saveScene() { return this.request('saveScene'); }
  /// The current values of parameters `names` (null where one does not apply).
  values(names) { return this.request('values', { names }); }
  /// Sets a parameter: {error ('' or the message), prediction, before} (see
  /// `Playground::predict`).
  setParameter(name, value) { return this.request('setParameter', { name, value }); }
  /// Drops an object at a clicked point (see `Playground::drop_at`): '' or the message.
  dropAt(object, material, point, speed, size) { return this.message('dropAt', { object, material, point, speed, size }); }
  /// '' if `size` (m) is a size objects may be dropped at, else the message.
  checkSize(size) { return this.message('checkSize', { size }); }
  /// Starts pouring sand `material` at `rate` over floor point `point` until `stopPour` (see
  /// `Playground::start_pour`): '' or the message naming the field.
  startPour(point, material, rate) { return this.message('startPour', { point, material, rate }); }
  /// Stops the pour running (nothing when none runs): '' or the message.
  stopPour() { return this.message('stopPour'); }
  /// '' if `rate` is a rate a pour may have, else the message.
  checkRate(rate) { return this.message('checkRate', { rate }); }
  clear() { return this.message('clear'); }
  /// Restarts the scene with the current parameters ('' or the message), paused when
  /// `playing` is false.
  reset(playing = undefined) { return this.message('reset', { playing }); }
  /// What a time step of scene `source` at level `quality` costs here, stepped for `ms` of
  /// wall time apart from the simulation shown; resolves to {ratio, msPerStep, steps,
  /// particles} (the host's `cmd_levelProbe`).
  levelProbe(source, quality, ms) { return this.request('levelProbe', { source, quality, ms }); }
  /// Samples the scene again at quality level `quality`; resolves to the drops refused.
  setQuality(quality) { return this.request('setQuality', { quality }); }
  /// The stable id of the particle nearest `point`, or null.
  pick(point) { return this.request('pick', { point }); }
  /// What a ruler and a protractor read between points `a` and `b` (m), by the core.
  handMeasure(a, b) { return this.request('handMeasure', { a, b }); }

  play(playing) { this.tell('play', { playing }); }
  step() { this.tell('step'); }
  timeScale(scale) { this.tell('timeScale', { scale }); }
  colour(mode) { this.tell('colour', { mode }); }
  /// Material at rest sleeps (on) or is stepped every step (off); kept for scenes loaded after.
  sleeping(on) { this.tell('sleeping', { on }); }
  probe(id) { this.tell('probe', { id }); }

  /// A command whose answer is '' or the error message.
  message(cmd, args) {
    return this.request(cmd, args).then(() => '', (e) => e.message);
  }
}

function buffersOf(frame) {
  return [frame.positions.buffer, frame.values.buffer];
}
