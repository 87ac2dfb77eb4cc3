// The page's state and what the user can do with it. What the user chose for the view (scene,
// dimension, colours, drop tool, time scale: the view part of the link) and the playback
// live here; the simulation's state (quality, parameters, bodies dropped and poured, Clear) lives in the
// solver's Playground behind `session` (session.js: in a Web Worker), which also records it
// for the link. Commands to the simulation are asynchronous: an action awaits the answer
// before it shows the result.

import { banner, toast, warnCost } from './hud.js';
import { readHash, writeHash, formatDrop, formatPour } from './hash.js';
import { LEVELS, QualityGovernor, applyQuality } from './quality.js';
import { insideBox, nearestParticle } from './pointer.js';
import { OPENED, SANDBOX, sceneSource } from './scenes.js';
import { buildDropControls, buildPourControl, leadPlot, showHint, showPlots, syncControls } from './controls.js';
import { format } from './params.js';
import { NARROW } from './fold.js';
import { LessonPanel, bodyParam, fetchLesson } from './lessons.js';
import { Recorder } from './record.js';

/// Frames per second the page aims at (the frame's stepping budget and the quality governor).
export const TARGET_FPS = 30;
/// Where the page remembers the user's quality level (localStorage).
export const LEVEL_KEY = 'mpm.quality';
/// How often at most the link follows a pour that runs (ms; see `App.stateChanged`).
const HASH_POURING_MS = 500;
/// Why a lesson opens at the solver's default level, for the HUD.
const LESSON_LEVEL = 'the level the lessons are measured at';

export class App {
  constructor({ session, renderer, camera, canvas, energyPlot, stressPlot, mohrPlot, overlay, scenes, lessons = [], bunny }) {
    Object.assign(this, { session, renderer, camera, canvas, energyPlot, stressPlot, mohrPlot, overlay, scenes, lessons, bunny });
    this.hudDetails = false; // the HUD's technical figures
    this.readouts = true; // the measures drawn on the view
    this.hand = null; // the hand tool's line: {a, b, reading} (m)
    // `lesson`: the id of the lesson open (its scene is the one shown), else undefined.
    this.view = { lesson: undefined, scene: SANDBOX, dim: '3', colour: 'body', object: 'bunny', material: 'drucker_prager', time: '1' };
    // What a link naming no scene nor lesson opens, and where an unusable one falls back to:
    // a scene with sand, if the scene list has one.
    this.defaultScene = ['bunny_on_sand_heap', 'bunny_on_sand_ball', 'notched_sand_block', 'column_collapse'].find((b) => scenes.some((s) => s.base === b)) ?? SANDBOX;
    this.lesson = null; // the lesson open, as its file has it
    this.lessonColours = false; // the lesson about to open sets the colours
    this.opened = null; // the scene file opened from disk: {key, source}
    this.lessonPanel = new LessonPanel(this);
    this.recorder = new Recorder(canvas);
    this.size = 0.25; // of dropped objects (m)
    this.dropSpeed = 0;
    this.rate = 0; // of a pour (m³/s; m²/s in 2D): set by the rate control (`buildPourControl`)
    this.pour = null; // the pour the user holds: {material, rate}
    this.hashAt = -Infinity; // when the link was last written (performance.now(), ms)
    this.tool = 'drop';
    this.playing = true;
    this.probeId = null; // the stable id of the inspected particle
    this.sliders = new Map();
    this.stats = {
      fps: 0, substeps: 0, msPerStep: 0, ratio: 0, simMs: 0, renderMs: 0, otherMs: 0, fellBehind: false, frames: 0,
      stableDt: 0, drawn: [], seen: [],
    };
    this.timings = []; // per frame, for benchmarks
    this.governor = new QualityGovernor(1000 / TARGET_FPS);
    this.quality = ''; // what the renderer gave up to keep the frame rate
    this.syncRender = false; // benchmarks: wait for the GPU in each frame
  }

  // For tests, benchmarks and curious students (window.mpm): the simulation's state as the
  // page last heard it, and the frame drawn last.
  get sim() { return this.session.state; }
  get frame() { return this.session.frame; }
  get simTime() { return this.session.frame?.time ?? 0; }
  get particleCount() { return this.session.state.particles; }
  get drops() { return this.session.session().drops; }
  get domain() { return this.session.scene.domain.size; }
  get cellSize() { return this.session.scene.cell_size; }
  set fixedQuality(on) { this.governor.fixed = on; }

  /// Sets the rendering quality level (0 full … `LEVELS.length - 1` lowest).
  setQuality(level) {
    this.governor.set(level, performance.now());
    this.quality = applyQuality(this.renderer, level);
  }

  /// Whether the view changed since this was last asked (camera, size, colours, rendering
  /// quality, the inspected particle): a frame with no news is then drawn again.
  viewChanged() {
    this.camera.matrices(this.canvas.clientWidth, this.canvas.clientHeight);
    const key = [...this.camera.viewProj, this.canvas.clientWidth, this.canvas.clientHeight,
      this.view.colour, this.quality, this.probeId, window.devicePixelRatio].join();
    const changed = key !== this.viewKey;
    this.viewKey = key;
    return changed;
  }

  /// Records a frame's time outside the simulation; lowers or raises the quality.
  governQuality(wall) {
    const level = this.governor.record(Math.max(0, wall - this.stats.simMs), performance.now());
    this.stats.otherMs = this.governor.otherMs;
    if (level !== null) this.quality = applyQuality(this.renderer, level);
  }

  /// Loads the scene of `this.view` (a lesson's, a scene of the list, a path, a file opened)
  /// and replays `session` ({quality, params, cleared, drops}, from a link or kept across a
  /// 2D/3D switch); `ignored` lists what the link held that cannot be used, for the message.
  async loadScene(session = {}, ignored = []) {
    const token = (this.loadToken = (this.loadToken || 0) + 1);
    if (!this.view.lesson && this.levelWhy === LESSON_LEVEL) this.levelWhy = ''; // a scene after a lesson
    let source, lesson = null;
    try {
      if (this.view.lesson) ({ lesson, source } = await fetchLesson(this.view.lesson, this.lessons, this.session));
      else if (this.view.scene.startsWith(OPENED)) source = this.openedSource(this.view.scene);
      else source = await sceneSource(this.view.scene, this.view.dim, this.scenes, this.session);
    } catch (e) {
      if (token !== this.loadToken) return;
      return this.loadScene(session, this.fallBack(e.message, ignored));
    }
    if (token !== this.loadToken) return; // a later choice overtook this one
    // A lesson starts paused: not a step before the reader presses Play.
    const out = await this.session.load(source, session, this.view.dim, false, lesson ? false : undefined);
    if (token !== this.loadToken) return; // a later choice is loading; it shows itself
    if (out.invalid) {
      // The host shows the sandbox meanwhile; the default scene follows unless it was this one.
      const more = this.fallBack(`invalid: ${out.invalid}`, ignored);
      if (this.view.scene !== SANDBOX) return this.loadScene(session, more);
      ignored = more;
      lesson = null;
    }
    await this.loaded(out, ignored, lesson);
    // a soil-lab lesson runs its tests in the Lab panel; another scene leaves it
    if (lesson?.lab) this.lab?.openLesson(lesson, source.text);
    else if (this.lab?.lessonRun) this.lab.close();
  }

  /// The scene or lesson of the view cannot open (`why`): a lesson says so in its banner, a
  /// scene joins the messages of the link (`ignored`, returned with it); the view falls back
  /// to the default scene, or to the sandbox if that was the one.
  fallBack(why, ignored) {
    const fallback = this.view.lesson || this.view.scene !== this.defaultScene ? this.defaultScene : SANDBOX;
    const instead = fallback === SANDBOX ? 'the empty sandbox instead' : 'the default scene instead';
    if (this.view.lesson) {
      banner('lesson', 'bad', `The lesson cannot open: ${why}. Showing ${instead.replace(' instead', '')}.`, { label: 'Close', run: () => banner('lesson') });
      console.warn(`lesson=${this.view.lesson}: ${why}; ${instead}`);
    } else ignored = [...ignored, `scene=${this.view.scene}: ${why}; ${instead}`];
    this.view.lesson = undefined;
    this.view.scene = fallback;
    return ignored;
  }

  /// The source of a scene file opened from disk (`key` is `file:NAME`).
  openedSource(key) {
    if (this.opened?.key === key) return this.opened.source;
    throw new Error(`${key.slice(OPENED.length)} was opened from a file: open it again with Open scene`);
  }

  /// Opens lesson `id` of the list in the view it asks for, at the solver's default level (Live):
  /// the level its captions' figures are measured and tested at.
  openLesson(id) {
    this.view.lesson = id;
    this.lessonColours = true;
    this.view.size = undefined;
    this.levelWhy = LESSON_LEVEL;
    return this.loadScene({ quality: this.session.qualities.default });
  }

  /// Opens scene file `name` (`source`: {text, assets}) at the current quality level; resolves
  /// to '' or the solver's message naming the field (the simulation then goes on as it was).
  async openScene(name, source) {
    const token = (this.loadToken = (this.loadToken || 0) + 1);
    const out = await this.session.load(source, { quality: this.session.quality.quality }, this.view.dim, true);
    if (out.kept) return out.invalid;
    if (token !== this.loadToken) return '';
    this.opened = { key: `${OPENED}${name}`, source };
    Object.assign(this.view, { lesson: undefined, scene: this.opened.key, size: undefined });
    banner('open');
    await this.loaded(out, [], null);
    toast(`Opened ${name}: ${this.session.state.bodies} bodies, ${this.session.state.particles.toLocaleString('en')} particles.`);
    return '';
  }

  /// After a scene loaded: the messages of what did not apply, the camera, the controls, and
  /// a lesson's view (colours, plot, sliders, the particle inspected).
  async loaded(out, ignored, lesson) {
    for (const msg of [...ignored, ...out.rejected]) console.warn(`ignored from the link: ${msg}`);
    const refused = this.refused(out.refused);
    const messages = [...ignored, ...out.rejected, ...refused];
    if (messages.length) toast(`Ignored from the link: ${messages.join('; ')}`);
    const scene = this.session.scene;
    this.view.dim = String(scene.dim);
    this.camera.setDomain(this.domain);
    this.renderer.setDomain(this.domain);
    const sizes = this.session.sizeRange();
    this.sizeRange = sizes.offered;
    const sz = Number(this.view.size);
    this.size = Number.isFinite(sz) && sz > 0 ? sz : sizes.default;
    this.lesson = lesson;
    const lv = lesson?.view ?? {};
    if (lesson && this.lessonColours) this.view.colour = lv.colour ?? 'body';
    this.lessonColours = false;
    // The material of the lesson's first slider, so that its slider shows among the controls.
    const model = (lv.params ?? []).map((n) => (bodyParam(n)?.name ?? n).split('.')).find((p) => p.length === 2)?.[0];
    if (lesson && model) this.view.material = model;
    this.restarted();
    // A lesson waits for Play from its first frame.
    if (lesson) this.playing = false;
    this.session.timeScale(Number(this.view.time));
    this.session.sleeping(this.view.sleep !== '0');
    this.session.colour(this.view.colour);
    this.session.play(this.playing);
    buildDropControls(this);
    syncControls(this);
    leadPlot(lesson ? lv.plot : 'energy');
    if (lesson) {
      showPlots(lv.plot !== 'none');
      await this.lessonPanel.show(lesson);
      if (lv.inspect) this.setProbe(await this.session.pick(lv.inspect));
    } else this.lessonPanel.close();
    this.updateHash();
  }

  /// The particles' drawn radius: half a particle spacing, a little more (m).
  get radius() {
    return (0.55 * this.cellSize) / (this.session.quality?.particles_per_cell ?? 2);
  }

  /// Samples the scene again at quality level `id` ('live', 'balanced', 'fine'): it starts
  /// again with the parameters, the Clear and the drops so far.
  async setQuality(id) {
    let refused;
    try {
      refused = await this.session.setQuality(id);
    } catch (e) {
      toast(e.message);
      syncControls(this, false);
      return;
    }
    const msgs = this.refused(refused);
    const q = this.session.quality;
    // The user's choice wins over the probe's from now on, here and on the next visit.
    try {
      localStorage.setItem(LEVEL_KEY, q.quality);
    } catch { /* storage refused: the link still carries it */ }
    this.levelWhy = 'your choice, remembered';
    toast(`${this.qualityLabel(q.quality)}: ${this.session.state.particles.toLocaleString('en')} particles, ` +
      `cells of ${+(100 * q.cell_size).toPrecision(3)} cm${msgs.length ? `; not dropped: ${msgs.join('; ')}` : ''}`);
    this.restarted();
    // The spout is as wide as a few cells of the new level: its rates change with them.
    buildPourControl(this);
    syncControls(this);
    this.updateHash();
  }

  /// The level a visit opens at when its link names none: the one the user chose last
  /// (remembered in localStorage), else the finest that runs live here by a probe in the
  /// worker: what a time step of the default scene of the view's dimension costs at Balanced,
  /// stepped from its start for a second (the session's `levelProbe`); Balanced when the rate
  /// that cost steps keeps up with real time in 2D or half of it in 3D, else Live. Resolves to
  /// {id, why}, `why` the HUD's words for it. A test forces the probe's answer with
  /// `window.mpmProbe = 'live'` or `'balanced'` set before the page loads.
  async pickLevel() {
    const levels = this.session.qualities.levels;
    const label = (id) => this.qualityLabel(id);
    let stored = null;
    try {
      stored = localStorage.getItem(LEVEL_KEY);
    } catch { /* storage refused (a private window): nothing remembered */ }
    if (levels.some((l) => l.id === stored)) return { id: stored, why: 'your choice, remembered' };
    const forced = globalThis.mpmProbe;
    if (levels.some((l) => l.id === forced)) return { id: forced, why: `the probe's answer set to ${label(forced)}` };
    const need = this.view.dim === '2' ? 1 : 0.5;
    try {
      const source = await sceneSource(this.defaultScene, this.view.dim, this.scenes, this.session);
      const { ratio, msPerStep } = await this.session.levelProbe(source, 'balanced', 1000);
      const r = ratio >= 10 ? ratio.toFixed(0) : ratio.toPrecision(2);
      const cost = `a Balanced step costs ${msPerStep.toPrecision(2)} ms here, ${r}× real time`;
      return ratio >= need
        ? { id: 'balanced', why: `picked here: ${cost}` }
        : { id: 'live', why: `picked here: ${cost}, too slow for Balanced` };
    } catch (e) {
      console.warn(`the level probe failed (${e.message}); opening at Live`);
      return { id: 'live', why: 'the level probe failed' };
    }
  }

  qualityLabel(id) {
    return this.session.qualities.levels.find((l) => l.id === id)?.label ?? id;
  }

  /// Loads what the link says (on the first visit, and when the hash changes).
  loadFromHash() {
    const t = this.session.table;
    const { view, session, errors } = readHash(location.hash, t.names, {
      object: t.objects.map((o) => o.id), material: t.models.map((m) => m.id),
      quality: this.session.qualities.levels.map((l) => l.id),
    });
    Object.assign(this.view, view);
    this.view.lesson = view.lesson;
    if (!view.lesson && !view.scene) this.view.scene = this.defaultScene; // a link of settings alone
    this.view.sleep = view.sleep === '0' ? '0' : undefined; // on unless the link says sleep=0
    this.lessonColours = !!view.lesson && !view.colour; // the lesson's, unless the link names others
    if (session.quality !== undefined) this.levelWhy = '';
    else if (view.lesson) {
      this.levelWhy = LESSON_LEVEL;
      return this.loadScene({ ...session, quality: this.session.qualities.default }, errors);
    } else if (!this.levelPicked) {
      // The first page of a visit whose link names no level: the user's last choice, else the probe's.
      this.levelPicked = true;
      return this.pickLevel().then(({ id, why }) => {
        this.levelWhy = why;
        return this.loadScene({ ...session, quality: id }, errors);
      });
    }
    return this.loadScene(session, errors);
  }

  /// The messages of drops and pours the solver refused ([{drop or pour, error}]), each warned
  /// about.
  refused(list = []) {
    return list.map(({ drop, pour, error }) => {
      const msg = drop ? `drop=${formatDrop(drop)}: ${error}` : `pour=${formatPour(pour)}: ${error}`;
      console.warn(`ignored from the link: ${msg}`);
      return msg;
    });
  }

  /// A frame brought a new state: the link follows it. While a pour runs every layer it pours
  /// changes the state (the pour's duration so far), so the link follows at most every
  /// HASH_POURING_MS: browsers limit how often a page may rewrite its address (a few hundred
  /// times in ten seconds), and a pour changes it with every frame. Its start and its stop are
  /// written at once.
  stateChanged() {
    const now = performance.now();
    if (this.session.state.pouring && now - this.hashAt < HASH_POURING_MS) return;
    this.updateHash();
  }

  /// The state of the link: the view, and the session the solver recorded.
  updateHash() {
    this.hashAt = performance.now();
    const view = { ...this.view, size: +this.size.toPrecision(3) };
    if (view.lesson) view.scene = view.dim = undefined; // the lesson's
    writeHash(view, this.session.session());
  }

  /// Draws the frame again at the next animation frame (for a snapshot).
  redraw() {
    this.viewKey = null;
  }

  /// Applies a live parameter; resolves to '' or the solver's error message (state unchanged).
  async applyParam(name, value) {
    const s = this.session;
    const { error, prediction, before } = await s.setParameter(name, value);
    if (error) return error;
    warnCost(s.table.spec(name), value, prediction, before, s);
    // The same parameter's slider elsewhere (the lesson's panel, the controls) follows.
    this.sliders.get(name)?.set(value);
    this.lessonPanel.changed(name, value);
    syncControls(this, false);
    this.updateHash();
    return '';
  }

  /// A click on the view at (px, py) CSS pixels: drops an object or inspects a particle.
  async click(px, py) {
    this.camera.matrices(this.canvas.clientWidth, this.canvas.clientHeight);
    if (this.tool === 'inspect') return this.inspect(px, py);
    const p = this.camera.unproject(px, py);
    if (!insideBox(p, this.domain)) {
      toast(this.domain.length === 3 ? 'Click on the floor (inside the box) to drop.' : 'Click inside the box to drop.');
      return;
    }
    const point = this.domain.length === 3 ? p : p.slice(0, 2);
    const error = await this.session.dropAt(this.view.object, this.view.material, point, this.dropSpeed, this.size);
    if (error) return toast(error);
    this.energyPlot.restart();
    this.updateHash();
  }

  /// The Pour tool pressed at (px, py) CSS pixels: pours the chosen sand at the rate set over
  /// the floor point there, from a spout held above it (the solver's rule), until `stopPour`.
  /// The hint says so while it pours.
  async startPour(px, py) {
    this.camera.matrices(this.canvas.clientWidth, this.canvas.clientHeight);
    const p = this.camera.unproject(px, py);
    if (!insideBox(p, this.domain)) {
      toast(this.domain.length === 3 ? 'Press on the floor (inside the box) to pour.' : 'Press inside the box to pour.');
      return;
    }
    const point = this.domain.length === 3 ? p : p.slice(0, 2);
    const pour = (this.pour = { material: this.view.material, rate: this.rate });
    const error = await this.session.startPour(point, pour.material, pour.rate);
    if (error) {
      if (this.pour === pour) this.pour = null;
      return toast(error);
    }
    this.energyPlot.restart();
    this.updateHash();
    if (this.pour !== pour) return; // released meanwhile: its stop followed
    const label = this.session.table.models.find((m) => m.id === pour.material)?.label ?? pour.material;
    const spout = this.session.session().pours?.at(-1)?.spout;
    const from = spout ? ` from ${+spout[1].toFixed(2)} m up` : '';
    const paused = this.playing ? '' : ' — paused: press Play to see it pour';
    showHint(this, `Pouring ${label}: ${format(pour.rate)} ${this.session.pourRates().unit}${from} (release to stop)${paused}`, true);
  }

  /// Stops the pour the user holds (released, cancelled, or the pointer left the view). A
  /// pour the solver runs is stopped even when the page let go of it first (a Reset answered
  /// while the press that followed it was starting one).
  async stopPour() {
    const held = this.pour;
    this.pour = null;
    if (held) showHint(this);
    else if (!this.session.state?.pouring) return;
    const error = await this.session.stopPour();
    if (error) toast(error);
    this.updateHash();
  }

  /// Picks the particle nearest the click on screen (and nearest the eye among close ones) in
  /// the frame drawn; the simulation finds it by where it was.
  async inspect(px, py) {
    const dim = this.domain.length;
    const f = this.session.frame;
    const i = f ? nearestParticle(f, dim, (x, y, z) => this.camera.project(x, y, z), px, py) : -1;
    this.stressPlot.clear();
    if (i < 0) {
      this.setProbe(null);
      toast('No particle there: click on one.');
      return;
    }
    const point = Array.from(f.positions.subarray(i * f.stride, i * f.stride + dim));
    this.setProbe(await this.session.pick(point));
    document.getElementById('pq-note').textContent = '';
    this.revealStressPlot();
  }

  /// Shows the stress path and Mohr circles of the particle just inspected: the plots when
  /// hidden, scrolled into their column, or on narrow screens (below the view) a word where.
  revealStressPlot() {
    const hidden = document.body.classList.contains('no-plots');
    if (hidden) showPlots(true);
    if (window.matchMedia(`(max-width: ${NARROW - 0.02}px)`).matches) {
      if (hidden) toast('Its stress path and Mohr circles: in the plots below the view.');
    } else document.getElementById('pq').closest('.card').scrollIntoView({ block: 'nearest' });
  }

  /// The hand tool: a drag from screen point `from` to `to` (CSS pixels on the view) measures
  /// the length and the angle to the horizontal between the world points under them (in 3D
  /// the particles drawn there, else the floor), as the core reads them.
  async measureDrag(from, to, done) {
    this.camera.matrices(this.canvas.clientWidth, this.canvas.clientHeight);
    const dim = this.domain.length;
    const world = ([px, py]) => {
      if (dim === 2) return this.camera.unproject(px, py);
      const f = this.session.frame;
      const i = f ? nearestParticle(f, dim, (x, y, z) => this.camera.project(x, y, z), px, py) : -1;
      if (i >= 0) return Array.from(f.positions.subarray(i * f.stride, i * f.stride + 3));
      return this.camera.unproject(px, py);
    };
    const a = world(from), b = world(to);
    if (!a || !b) return;
    // the reading shown stays the last one until this line's comes back (`measured`)
    const hand = { a, b, reading: this.hand?.reading ?? null, done, measured: false };
    this.hand = hand;
    this.redraw();
    if (!done && this.measuring) return; // one request at a time while dragging
    this.measuring = true;
    try {
      hand.reading = await this.session.handMeasure(a, b);
      hand.measured = true;
    } catch (e) {
      toast(e.message);
    } finally {
      this.measuring = false;
    }
    this.redraw();
  }

  /// Follows the particle of stable id `id` (null: none) in the p–q plot.
  setProbe(id) {
    this.probeId = id;
    this.session.probe(id);
  }

  /// Removes every body (the link records it).
  async clear() {
    await this.session.clear();
    this.restarted();
    this.updateHash();
  }

  /// Restarts the scene with the current parameters; the drops and a Clear are forgotten.
  async reset() {
    // A lesson starts again paused, its question (if any) asked again.
    if (this.lesson) this.playing = false;
    const error = await this.session.reset(this.lesson ? false : undefined);
    if (error) toast(error);
    this.restarted();
    this.updateHash();
    syncControls(this);
    if (this.lesson?.view?.inspect) this.setProbe(await this.session.pick(this.lesson.view.inspect));
    if (this.lesson?.question) this.lessonPanel.ask(this.lesson.question);
  }

  /// What a new start forgets: the inspected particle, the plots, the failure banner, and the
  /// pour held (the solver ended it: the press pours no more until it is made again).
  restarted() {
    if (this.pour) {
      this.pour = null;
      showHint(this);
    }
    this.setProbe(null);
    document.getElementById('pq-note').textContent = '';
    this.stressPlot.clear();
    this.mohrPlot?.clear();
    this.energyPlot.restart();
    this.hand = null;
    banner('failed');
    banner('slow');
    banner('cfl');
  }

  togglePlay() {
    this.setPlaying(!this.playing);
  }

  setPlaying(on) {
    this.playing = on;
    this.session.play(on);
    syncControls(this, false);
  }

  step() {
    this.playing = false;
    this.session.step();
    syncControls(this, false);
  }

  /// The simulation stopped (non-finite state, or a body crushed beyond what its material
  /// can store): pause and say so, with a way back. The solver's message names the cause and
  /// what helps.
  fail(message) {
    this.playing = false;
    this.session.play(false);
    syncControls(this, false);
    banner('failed', 'bad', `The simulation stopped: ${message}.`, { label: 'Reset', run: () => this.reset() });
  }
}

export { LEVELS };
