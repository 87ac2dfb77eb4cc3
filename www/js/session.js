// The simulation behind the page: the solver's Playground (src/playground/, through wasm),
// which holds the scene, the parameters set, the bodies dropped and the Clear. Every command
// the page sends goes through this class and gets plain data back (an error message is a
// string, '' for none), so that it can move into a Web Worker with the page only rendering
// what it reports.

import init, { Playground, assetPaths, parameterTable, sandboxScene } from '../pkg/mpm.js';
import { paramTable } from './params.js';

export class Session {
  /// Loads the solver; throws if it cannot.
  static async start() {
    const wasm = await init();
    return new Session(wasm.memory);
  }

  constructor(memory) {
    this.memory = memory;
    this.table = paramTable(parameterTable());
    this.pg = null;
    this.scene = null;
  }

  /// The source of the empty box of dimension `dim`.
  static sandbox(dim) {
    return { text: sandboxScene(Number(dim)), assets: null };
  }

  /// The files scene `text` references, relative to it.
  static assetPaths(text) {
    return assetPaths(text);
  }

  /// Loads scene `source` ({text, assets}; an invalid one falls back to the sandbox of
  /// dimension `dim`), with the shipped `bunny` ({obj, polygon}) for dropped bunnies, and
  /// replays `session` ({params, cleared, drops}). Returns what did not apply: { invalid:
  /// the scene's error or '', rejected: [message], refused: [{drop, error}] }.
  load(source, bunny, session, dim) {
    let pg, invalid = '';
    try {
      pg = new Playground(source.text, source.assets ?? undefined);
    } catch (e) {
      invalid = e.message;
      pg = new Playground(Session.sandbox(dim).text);
    }
    try {
      pg.setBunny(bunny.obj, bunny.polygon);
    } catch (e) {
      console.warn(`the shipped bunny did not load (${e.message}); dropping a bunny made of balls`);
    }
    this.pg?.free();
    this.pg = pg;
    const out = JSON.parse(pg.replay(JSON.stringify(session)));
    this.changed();
    return { invalid, ...out };
  }

  /// The scene as it stands (world and bodies), kept until something changes it.
  changed() {
    this.scene = JSON.parse(this.pg.sceneJson());
  }

  parameter(name) {
    return this.pg.parameter(name);
  }
  /// Every parameter's value, by name.
  parameters() {
    return JSON.parse(this.pg.parameters());
  }
  /// What setting `name` to `value` would cost (see `Playground::predict`).
  predict(name, value) {
    return JSON.parse(this.pg.predict(name, value, 1 / 60));
  }
  /// Sets a parameter; returns '' or the solver's message (state unchanged).
  setParameter(name, value) {
    return this.run(() => this.pg.setParameter(name, value));
  }
  /// Drops an object at a clicked point (see `Playground::drop_at`); '' or the message.
  dropAt(object, material, point, speed, size) {
    return this.run(() => this.pg.dropAt(object, material, new Float64Array(point), speed, size));
  }
  /// '' if `size` (m) is a size objects may be dropped at, else the message.
  checkSize(size) {
    return this.run(() => this.pg.checkSize(size), false);
  }
  sizeRange() {
    return JSON.parse(this.pg.sizeRange());
  }
  clear() {
    this.pg.clear();
    this.changed();
  }
  /// Restarts the scene with the current parameters; '' or the message.
  reset() {
    return this.run(() => this.pg.reset());
  }
  /// The parameters set, the Clear and the drops so far ({params, cleared, drops}).
  session() {
    return JSON.parse(this.pg.session());
  }

  /// Advances by up to `simTime` s within `budgetMs` (or by one step when `simTime` is null);
  /// returns the report of `Playground::frame`. Throws when the simulation fails.
  advance(simTime, budgetMs) {
    const report = JSON.parse(simTime === null ? this.pg.step() : this.pg.frame(simTime, budgetMs));
    if (report.refused) this.changed();
    return report;
  }

  /// Views into wasm memory of what the renderer draws, the colour scalars of `mode` just
  /// computed: { positions, stride, values, count, range }. Valid until the next command.
  view(mode) {
    const pg = this.pg;
    pg.setColourMode(mode);
    const range = pg.updateColours();
    return {
      positions: new Float32Array(this.memory.buffer, pg.positionsPtr(), pg.positionsLen()),
      stride: pg.positionsStride(),
      values: new Float32Array(this.memory.buffer, pg.coloursPtr(), pg.coloursLen()),
      count: pg.particleCount(),
      range,
    };
  }

  /// The stress point of the particle with stable id `id`, or null when it is gone.
  stressPoint(id) {
    const i = this.pg.indexOf(id);
    return i === undefined ? null : JSON.parse(this.pg.stressPoint(i));
  }
  particleId(index) {
    return this.pg.particleId(index);
  }
  diagnostics() {
    return JSON.parse(this.pg.diagnostics());
  }
  failure() {
    return this.pg.failure();
  }

  /// Runs a command; returns '' or its error message. `changes`: whether it may change the
  /// scene.
  run(command, changes = true) {
    try {
      command();
    } catch (e) {
      return e.message;
    }
    if (changes) this.changed();
    return '';
  }
}
