// The MPM playground page: loads the wasm solver, a scene, and runs the frame loop
// (simulate within a wall-clock budget, render from views into wasm memory, update the HUD
// and the teaching plots). Every parameter goes through the solver's own validation.

import init, { Playground, assetPaths, sandboxScene } from '../pkg/mpm.js';
import { Camera } from './camera.js';
import { GlRenderer } from './render-gl.js';
import { CanvasRenderer } from './render-2d.js';
import { BODY_COLOURS, YIELD_COLOURS, YIELD_LABELS, css, viridis } from './colours.js';
import { MODELS, OBJECTS, WORLD, materialParams, spec, format, formatTime } from './params.js';
import { EnergyPlot, StressPlot, ENERGY_SERIES } from './plots.js';
import { formatDrop, readHash, writeHash } from './hash.js';
import { el, paramSlider, segmented } from './widgets.js';

const $ = (id) => document.getElementById(id);
const SANDBOX = 'sandbox';
const TARGET_FPS = 30;

const app = {
  memory: null,
  pg: null,
  scenes: [], // [{base, name, paths: {2: path, 3: path}}]
  view: { scene: SANDBOX, dim: '3', colour: 'body', object: 'bunny', material: 'drucker_prager', time: '1' },
  size: 0.25,
  dropSpeed: 0,
  tool: 'drop',
  playing: true,
  failed: null,
  domain: [2, 1, 1],
  cellSize: 0.025,
  radius: 0.006,
  probeId: null,
  stats: { fps: 0, substeps: 0, msPerStep: 0, ratio: 0, simMs: 0, renderMs: 0, otherMs: 0, fellBehind: false, frames: 0 },
  quality: '', // what the renderer gave up to keep the frame rate (see governQuality)
  fixedQuality: false,
  timings: [],
  sliders: new Map(),
  lastFrame: 0,
  stepOnce: false,
  // The bodies dropped by clicks, in the URL hash so that a link replays them (hash.js):
  // { t, object, material, size, centre, velocity, appliedAt }, sorted by t, the simulated
  // time of the drop counted from dropOrigin. Those from a link are dropped when the
  // simulation reaches their time; drops[nextDrop] is the first still to come.
  drops: [],
  nextDrop: 0,
  dropOrigin: 0,
  cleared: false, // the scene's own bodies were removed (Clear) before the drops
};
window.mpm = app; // for tests, benchmarks and curious students
app.setQuality = (level) => setQuality(level);

// ---------- messages ----------

let toastTimer = 0;
function toast(msg) {
  const t = $('toast');
  t.textContent = msg;
  t.classList.add('show');
  clearTimeout(toastTimer);
  toastTimer = setTimeout(() => t.classList.remove('show'), 3500);
}

const banners = new Map();
function banner(key, kind, html, action) {
  if (!html) {
    banners.get(key)?.remove();
    banners.delete(key);
    return;
  }
  let b = banners.get(key);
  if (!b) {
    b = el('div', { class: `banner ${kind}` });
    banners.set(key, b);
    $('banners').append(b);
  }
  b.className = `banner ${kind}`;
  b.replaceChildren();
  b.append(html);
  if (action) b.append(el('button', { onclick: action.run }, action.label));
}

// ---------- scenes ----------

async function loadSceneList() {
  let files = [];
  try {
    const r = await fetch('www/pkg/scenes.json', { cache: 'no-cache' });
    if (r.ok) files = await r.json();
  } catch {
    files = [];
  }
  const byBase = new Map();
  for (const f of files) {
    const e = byBase.get(f.base) || { base: f.base, name: '', paths: {} };
    e.paths[f.dim] = f.path;
    e.name = (e.name || f.name || f.base).replace(/\s*\((2D|3D)\)\s*$/i, '');
    byBase.set(f.base, e);
  }
  app.scenes = [...byBase.values()];
  app.scenes.push({ base: SANDBOX, name: 'Sandbox (empty box)', paths: { 2: SANDBOX, 3: SANDBOX } });
  const select = $('scene');
  select.replaceChildren(...app.scenes.map((s) => el('option', { value: s.base }, s.name)));
}

function sceneEntry() {
  return app.scenes.find((s) => s.base === app.view.scene);
}

/// The scene's JSON and the texts of the files it references (or null when none).
async function sceneSource() {
  const key = app.view.scene;
  if (key === SANDBOX) return { text: sandboxScene(Number(app.view.dim)), assets: null };
  const path = key.endsWith('.json') ? key : sceneEntry()?.paths[app.view.dim];
  if (!path) throw new Error(`no ${app.view.dim}D version of scene “${key}”`);
  const text = await fetchText(path);
  const base = new URL(path, location.href);
  const files = assetPaths(text);
  if (!files.length) return { text, assets: null };
  const texts = await Promise.all(files.map((f) => fetchText(new URL(f, base).href)));
  return { text, assets: JSON.stringify(Object.fromEntries(files.map((f, i) => [f, texts[i]]))) };
}

async function fetchText(url) {
  const r = await fetch(url, { cache: 'no-cache' });
  if (!r.ok) throw new Error(`${url}: ${r.status} ${r.statusText}`);
  return r.text();
}

/// The shipped bunny for the drop tool (mesh in 3D, silhouette in 2D); without these files
/// the solver builds a bunny out of balls.
async function loadBunny() {
  const get = (f) => fetchText(`scenes/${f}`).catch(() => undefined);
  [app.bunnyObj, app.bunnyPolygon] = await Promise.all([get('bunny.obj'), get('bunny2d.txt')]);
}

/// Loads the scene of `app.view`, then applies `params` ([name, value] in order), removes
/// the scene's bodies if `cleared`, and replays `drops` (see hash.js) at their times.
/// `ignored` lists what the link held that cannot be used, for the message.
async function loadScene(params = [], { drops = [], cleared = false, ignored = [] } = {}) {
  const token = (app.loadToken = (app.loadToken || 0) + 1);
  let source;
  try {
    source = await sceneSource();
  } catch (e) {
    toast(`Cannot load the scene: ${e.message}. Showing the sandbox.`);
    app.view.scene = SANDBOX;
    source = { text: sandboxScene(Number(app.view.dim)), assets: null };
  }
  if (token !== app.loadToken) return; // a later choice overtook this one
  let pg;
  try {
    pg = new Playground(source.text, source.assets ?? undefined);
  } catch (e) {
    toast(`The scene is invalid: ${e.message}`);
    app.view.scene = SANDBOX;
    pg = new Playground(sandboxScene(Number(app.view.dim)));
  }
  try {
    pg.setBunny(app.bunnyObj, app.bunnyPolygon);
  } catch (e) {
    console.warn(`the shipped bunny did not load (${e.message}); dropping a bunny made of balls`);
  }
  app.pg?.free();
  app.pg = pg;
  const rejected = [...ignored];
  for (const [name, value] of params) {
    try {
      pg.setParameter(name, value);
    } catch (e) {
      rejected.push(e.message);
    }
  }
  const scene = JSON.parse(pg.sceneJson());
  app.view.dim = String(scene.dim);
  app.domain = scene.domain.size;
  app.cellSize = scene.cell_size;
  const ppc = scene.bodies.length ? Math.max(...scene.bodies.map((b) => b.particles_per_cell ?? 2)) : 2;
  app.radius = (0.55 * app.cellSize) / ppc;
  camera.setDomain(app.domain);
  renderer.setDomain(app.domain);
  const minSide = Math.min(...app.domain);
  app.sizeRange = [Math.max(3 * app.cellSize, 0.05 * minSide), 0.6 * minSide];
  const sz = Number(app.view.size);
  app.size = Number.isFinite(sz) && sz > 0 ? sz : Math.min(app.sizeRange[1], Math.max(app.sizeRange[0], 0.25 * minSide));
  // The link's Clear and drops, after what the scene itself sets (its bodies' particle size).
  if (cleared) pg.clear();
  app.cleared = cleared;
  app.dropOrigin = 0;
  app.drops = drops.map((d) => ({ ...d })).sort((a, b) => a.t - b.t);
  app.nextDrop = 0;
  for (const msg of ignored) console.warn(`ignored from the link: ${msg}`);
  rejected.push(...replayDrops());
  if (rejected.length) toast(`Ignored from the link: ${rejected.join('; ')}`);
  app.failed = null;
  app.probeId = null;
  stressPlot.clear();
  energyPlot.restart();
  banner('failed');
  banner('slow');
  banner('cfl');
  warnFlip();
  pg.setColourMode(app.view.colour);
  buildDropControls();
  syncControls();
  updateHash();
}

// ---------- parameters ----------

/// Applies a live parameter; returns '' or the solver's error message (state unchanged).
function applyParam(name, value) {
  const pg = app.pg;
  const prediction = JSON.parse(pg.predict(name, value, 1 / 60));
  const before = JSON.parse(pg.predict(name, pg.parameter(name), 1 / 60));
  try {
    pg.setParameter(name, value);
  } catch (e) {
    return e.message;
  }
  warnCost(name, value, prediction, before);
  if (name === 'drucker_prager.friction_angle') app.sliders.get('drucker_prager.dilatancy_angle')?.setMax(Math.max(0.5, value));
  updateHash();
  return '';
}

/// Says so when a value makes the simulation run in slow motion or near its stability limit.
function warnCost(name, value, p, before) {
  const s = spec(name);
  const slower = p.substeps_per_frame > 1.5 * before.substeps_per_frame;
  if (p.valid && slower && p.realtime_ratio > 0 && p.realtime_ratio < 0.25) {
    banner('slow', 'warn', `${s.label} ${format(value, s.unit)} needs ${Math.round(p.substeps_per_frame)} steps per frame ` +
      `(time step ${formatTime(p.stable_dt)}): expect slow motion, about ${(100 * p.realtime_ratio).toPrecision(2)} % of real time. ` +
      'Each frame stops at its time budget, so the page stays responsive.');
  } else if (!(p.realtime_ratio > 0 && p.realtime_ratio < 0.25)) banner('slow'); // fast enough again
  const cfl = app.pg.parameter('cfl');
  banner('cfl', 'warn', cfl > 0.6
    ? `CFL number ${cfl}: steps this close to the stability limit can make fast impacts jitter or blow up; 0.3–0.5 is safe.`
    : '');
  warnFlip();
}

/// FLIP ratios above 0.6 with the linear or GIMP kernel can add energy when an elastic or
/// von Mises body hits a wall or another body (docs/stability.md): say so.
function warnFlip() {
  const scene = JSON.parse(app.pg.sceneJson());
  const risky = scene.kernel !== 'quadratic_bspline' && ['elastic', 'von_mises'].filter((m) =>
    scene.bodies.some((b) => m in b.material) && app.pg.parameter(`${m}.flip`) > 0.6);
  banner('flip', 'warn', risky && risky.length
    ? `FLIP ratio above 0.6 for ${risky.join(' and ')} bodies with the ${scene.kernel} kernel: impacts on walls and between bodies can add energy ` +
      '(bounces grow). Up to 0.6 is safe; the quadratic B-spline kernel is safe at any ratio.'
    : '');
}

function syncControls() {
  const pg = app.pg;
  const values = JSON.parse(pg.parameters());
  for (const [name, s] of app.sliders) if (name in values) s.set(values[name]);
  const phi = values['drucker_prager.friction_angle'];
  app.sliders.get('drucker_prager.dilatancy_angle')?.setMax(Math.max(0.5, phi));
  $('colour').value = app.view.colour;
  $('timescale').value = app.view.time;
  const entry = sceneEntry();
  if (!entry && app.view.scene.endsWith('.json')) {
    // A scene file given by path in the link: list it too.
    const select = $('scene');
    if (![...select.options].some((o) => o.value === app.view.scene))
      select.append(el('option', { value: app.view.scene }, app.view.scene.split('/').pop()));
    select.value = app.view.scene;
  } else $('scene').value = entry ? entry.base : SANDBOX;
  for (const d of ['2', '3']) {
    const b = $(`dim${d}`);
    b.setAttribute('aria-pressed', String(app.view.dim === d));
    b.disabled = !!entry && !entry.paths[d];
  }
  pickObject(app.view.object, false);
  pickMaterial(app.view.material, false);
  pickTool(app.tool);
  $('play').textContent = app.playing ? 'Pause' : 'Play';
  $('hint').textContent = app.tool === 'drop'
    ? (app.domain.length === 3 ? 'Click on the floor to drop' : 'Click in the box to drop')
    : 'Click a particle to inspect its stress';
}

function updateHash() {
  const overrides = app.pg ? JSON.parse(app.pg.overrides()) : [];
  writeHash({ ...app.view, size: +app.size.toPrecision(3) }, overrides, app.drops, app.cleared);
}

// ---------- dropped bodies ----------

/// Simulated time since the scene started (or was cleared): the clock of the drops.
function dropClock() {
  return app.pg.time() - app.dropOrigin;
}

/// Drops a body ({ object, material, size, centre, velocity }); returns '' or the solver's
/// error message.
function dropBody(d) {
  try {
    app.pg.addObject(d.object, d.material, new Float64Array(d.centre), new Float64Array(d.velocity), d.size);
  } catch (e) {
    return e.message;
  }
  energyPlot.restart();
  if (app.failed) { app.failed = null; banner('failed'); }
  return '';
}

/// Drops the bodies of the link whose time has come (all of them into an empty box, where
/// time does not run). One the solver refuses is left out with a warning naming it; returns
/// those messages.
function replayDrops() {
  const refused = [];
  while (app.nextDrop < app.drops.length) {
    const d = app.drops[app.nextDrop];
    if (d.t > dropClock() + 1e-9 && app.pg.particleCount() > 0) break;
    const err = dropBody(d);
    if (err) {
      refused.push(`drop=${formatDrop(d)}: ${err}`);
      console.warn(`ignored from the link: ${refused.at(-1)}`);
      app.drops.splice(app.nextDrop, 1);
    } else {
      d.appliedAt = dropClock();
      app.nextDrop++;
    }
  }
  return refused;
}

/// Forgets the drops (Reset, Clear).
function forgetDrops() {
  app.drops = [];
  app.nextDrop = 0;
  app.dropOrigin = app.pg ? app.pg.time() : 0;
}

// ---------- controls ----------

let markObject, markMaterial, markTool;

function buildControls() {
  markObject = segmented($('objects'), OBJECTS, (id) => pickObject(id, true));
  markMaterial = segmented($('materials'), MODELS.map((m) => ({ ...m, hint: m.hint })), (id) => pickMaterial(id, true));
  const world = $('world-params');
  for (const s of WORLD) {
    const w = paramSlider({ ...s }, (v) => applyParam(s.name, v));
    app.sliders.set(s.name, w);
    world.append(w.root);
  }
  $('scene').addEventListener('change', () => {
    const entry = app.scenes.find((s) => s.base === $('scene').value);
    app.view.scene = entry ? entry.base : $('scene').value;
    if (entry && !entry.paths[app.view.dim]) app.view.dim = Object.keys(entry.paths)[0];
    app.view.size = undefined;
    loadScene(); // a new scene starts with its own parameters
  });
  for (const d of ['2', '3'])
    $(`dim${d}`).addEventListener('click', () => {
      if (app.view.dim === d) return;
      app.view.dim = d;
      app.view.size = undefined;
      loadScene(keptParams());
    });
  $('play').addEventListener('click', togglePlay);
  $('step').addEventListener('click', () => { app.playing = false; app.stepOnce = true; syncControls(); });
  $('reset').addEventListener('click', reset);
  $('clear').addEventListener('click', () => {
    app.pg.clear();
    forgetDrops();
    app.cleared = true;
    updateHash();
    app.failed = null;
    app.probeId = null;
    stressPlot.clear();
    energyPlot.restart();
    banner('failed');
  });
  $('toggle-plots').addEventListener('click', () => {
    const hidden = document.body.classList.toggle('no-plots');
    $('toggle-plots').setAttribute('aria-pressed', String(!hidden));
  });
  if (window.innerWidth < 1500) {
    document.body.classList.add('no-plots');
    $('toggle-plots').setAttribute('aria-pressed', 'false');
  }
  $('timescale').addEventListener('change', () => { app.view.time = $('timescale').value; updateHash(); });
  $('colour').addEventListener('change', () => {
    app.view.colour = $('colour').value;
    app.pg.setColourMode(app.view.colour);
    updateHash();
  });
  $('share').addEventListener('click', async () => {
    updateHash();
    try {
      await navigator.clipboard.writeText(location.href);
      toast('Link copied: it opens this scene with these parameters and drops the same bodies.');
    } catch {
      toast('Copy the address bar: it holds this scene, its parameters and the bodies dropped.');
    }
  });
  for (const b of document.querySelectorAll('[data-tool]')) b.addEventListener('click', () => pickTool(b.dataset.tool));
  $('energy-legend').replaceChildren(...ENERGY_SERIES.map((s) => el('span', {}, el('i', { style: `background:${s.colour}` }), s.label)));
  window.addEventListener('keydown', (e) => {
    if (e.target.closest('input, select, textarea') || e.ctrlKey || e.metaKey || e.altKey) return;
    const k = e.key.toLowerCase();
    if (k === ' ') { e.preventDefault(); togglePlay(); }
    else if (k === 's') { app.playing = false; app.stepOnce = true; syncControls(); }
    else if (k === 'r') reset();
    else if (k === 'd') pickTool('drop');
    else if (k === 'i') pickTool('inspect');
  });
  window.addEventListener('hashchange', () => {
    const { view, params, drops, cleared, errors } = readHash();
    Object.assign(app.view, view);
    loadScene(params, { drops, cleared, ignored: errors });
  });
}

/// The parameters changed so far, kept when switching between the 2D and 3D versions.
function keptParams() {
  return app.pg ? JSON.parse(app.pg.overrides()) : [];
}

function togglePlay() {
  app.playing = !app.playing;
  syncControls();
}

function reset() {
  try {
    app.pg.reset();
  } catch (e) {
    toast(e.message);
  }
  forgetDrops();
  app.cleared = false;
  updateHash();
  app.failed = null;
  app.probeId = null;
  stressPlot.clear();
  energyPlot.restart();
  banner('failed');
  syncControls();
}

function pickTool(tool) {
  app.tool = tool;
  markTool = markTool || ((id) => { for (const b of document.querySelectorAll('[data-tool]')) b.setAttribute('aria-pressed', String(b.dataset.tool === id)); });
  markTool(tool);
  $('hint').textContent = tool === 'drop'
    ? (app.domain.length === 3 ? 'Click on the floor to drop' : 'Click in the box to drop')
    : 'Click a particle to inspect its stress';
}

function pickObject(id, user) {
  app.view.object = id;
  markObject(id);
  if (user) updateHash();
}

function pickMaterial(id, user) {
  app.view.material = id;
  markMaterial(id);
  const m = MODELS.find((x) => x.id === id);
  $('material-title').textContent = `Material: ${m.label}`;
  $('material-note').textContent = `${m.hint}. Applies to every ${m.label.toLowerCase()} body and to the next one you drop.`;
  const box = $('material-params');
  box.replaceChildren();
  for (const key of [...app.sliders.keys()]) if (key.includes('.')) app.sliders.delete(key);
  const values = app.pg ? JSON.parse(app.pg.parameters()) : {};
  for (const s of materialParams(id)) {
    const w = paramSlider({ ...s }, (v) => applyParam(s.name, v));
    app.sliders.set(s.name, w);
    box.append(w.root);
    if (s.name in values) w.set(values[s.name]);
  }
  if (id === 'drucker_prager' && values['drucker_prager.friction_angle'] !== undefined)
    app.sliders.get('drucker_prager.dilatancy_angle').setMax(Math.max(0.5, values['drucker_prager.friction_angle']));
  if (user) updateHash();
}

function buildDropControls() {
  const box = $('drop-params');
  box.replaceChildren();
  const [lo, hi] = app.sizeRange;
  const size = paramSlider({ name: 'drop.size', label: 'Size', symbol: 'L', unit: 'm', min: +lo.toPrecision(2), max: +hi.toPrecision(2), step: 0.01 }, (v) => {
    if (!(v >= app.cellSize * 2 && v <= Math.min(...app.domain) - 2 * app.cellSize))
      return `size = ${v}: must be in [${2 * app.cellSize}, ${+(Math.min(...app.domain) - 2 * app.cellSize).toPrecision(3)}] (m)`;
    app.size = v;
    updateHash();
    return '';
  });
  size.set(app.size);
  const speed = paramSlider({ name: 'drop.speed', label: 'Drop speed', symbol: 'v', unit: 'm/s', min: 0, max: 10, step: 0.1 }, (v) => {
    if (!(v >= 0 && v <= 50)) return `drop speed = ${v}: must be in [0, 50] (m/s)`;
    app.dropSpeed = v;
    return '';
  });
  speed.set(app.dropSpeed);
  box.append(size.root, speed.root);
}

// ---------- pointer: orbit, zoom, drop, inspect ----------

function setupPointer(canvas) {
  let down = null;
  canvas.addEventListener('pointerdown', (e) => {
    down = { x: e.clientX, y: e.clientY, lastX: e.clientX, lastY: e.clientY, moved: false };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener('pointermove', (e) => {
    if (!down) return;
    const dx = e.clientX - down.lastX, dy = e.clientY - down.lastY;
    if (Math.hypot(e.clientX - down.x, e.clientY - down.y) > 5) down.moved = true;
    if (down.moved) {
      canvas.classList.add('dragging');
      camera.orbit(dx, dy);
    }
    down.lastX = e.clientX;
    down.lastY = e.clientY;
  });
  canvas.addEventListener('pointerup', (e) => {
    canvas.classList.remove('dragging');
    if (down && !down.moved) {
      const r = canvas.getBoundingClientRect();
      click(e.clientX - r.left, e.clientY - r.top);
    }
    down = null;
  });
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    camera.zoomBy(Math.exp(e.deltaY * 0.001));
  }, { passive: false });
}

function click(px, py) {
  camera.matrices(canvasEl.clientWidth, canvasEl.clientHeight);
  if (app.tool === 'inspect') return inspect(px, py);
  const p = camera.unproject(px, py);
  const [W, H, D] = app.domain;
  const dim = app.domain.length;
  const inside = p && p[0] >= 0 && p[0] <= W && (dim === 2 ? p[1] >= 0 && p[1] <= H : p[2] >= 0 && p[2] <= D);
  if (!inside) {
    toast(dim === 3 ? 'Click on the floor (inside the box) to drop.' : 'Click inside the box to drop.');
    return;
  }
  const size = app.size, h = app.cellSize;
  const surface = app.pg.surfaceHeight(p[0], dim === 3 ? p[2] : 0, 0.6 * size);
  const gap = Math.max(2 * h, 0.05 * H);
  let y = dim === 3 ? Math.max(surface + 0.5 * size + gap, 0.55 * H) : Math.max(p[1], surface + 0.5 * size + gap);
  y = Math.min(y, H - h - 0.5 * size);
  // Rounded as the link records them (mm, cm/s, 0.1 ms), so that the link drops the same body.
  const round = (x, digits) => +x.toFixed(digits) || 0;
  const drop = {
    t: Math.floor(dropClock() * 1e4) / 1e4,
    object: app.view.object,
    material: app.view.material,
    size: +size.toPrecision(3),
    centre: (dim === 3 ? [p[0], y, p[2]] : [p[0], y]).map((x) => round(x, 3)),
    velocity: (dim === 3 ? [0, -app.dropSpeed, 0] : [0, -app.dropSpeed]).map((v) => round(v, 2)),
  };
  const err = dropBody(drop);
  if (err) return toast(err);
  // Before the drops of a link still to come (their times are later).
  drop.appliedAt = dropClock();
  app.drops.splice(app.nextDrop, 0, drop);
  app.nextDrop++;
  updateHash();
}

/// Picks the particle nearest the click on screen (and nearest the eye among close ones).
function inspect(px, py) {
  const pg = app.pg;
  const n = pg.particleCount();
  const dim = app.domain.length;
  const pos = new Float32Array(app.memory.buffer, pg.positionsPtr(), pg.positionsLen());
  const stride = pg.positionsStride();
  let best = -1, bestScore = Infinity;
  const reach = 14;
  for (let i = 0; i < n; i++) {
    const s = camera.project(pos[i * stride], pos[i * stride + 1], dim === 3 ? pos[i * stride + 2] : 0);
    if (!s) continue;
    const d = Math.hypot(s[0] - px, s[1] - py);
    if (d > reach) continue;
    const score = s[2] + d * 1e-4;
    if (score < bestScore) { bestScore = score; best = i; }
  }
  if (best < 0) {
    app.probeId = null;
    stressPlot.clear();
    toast('No particle there: click on one.');
    return;
  }
  app.probeId = pg.particleId(best);
  stressPlot.clear();
  $('pq-note').textContent = '';
}

// ---------- frame loop ----------

function frame(ts) {
  requestAnimationFrame(frame);
  const pg = app.pg;
  if (!pg) return;
  const wall = app.lastFrame ? Math.min(250, ts - app.lastFrame) : 1000 / 60;
  app.lastFrame = ts;
  const st = app.stats;
  st.fps = st.fps ? 0.9 * st.fps + 0.1 * (1000 / Math.max(1, wall)) : 1000 / Math.max(1, wall);
  let report = null;
  const t0 = performance.now();
  if ((app.playing || app.stepOnce) && !app.failed) {
    try {
      if (app.stepOnce) {
        pg.step();
        report = { substeps: 1, sim_time: 0, wall_ms: 0, fell_behind: false, ms_per_step: performance.now() - t0, requested: 0 };
        report.wall_ms = report.ms_per_step;
      } else {
        let simTime = (Math.min(wall, 100) / 1000) * Number(app.view.time);
        // Stop at the time of the next drop of a link, to drop it when it was dropped.
        const next = app.drops[app.nextDrop];
        if (next) simTime = Math.min(simTime, Math.max(0, next.t - dropClock()));
        // The frame's time budget for stepping: what the rest of the frame (rendering,
        // compositing) leaves of 1/30 s, and at least one step.
        const budget = Math.min(40, Math.max(4, 1000 / TARGET_FPS - st.otherMs - 2));
        report = JSON.parse(pg.frame(simTime, budget));
      }
    } catch (e) {
      fail(e.message);
    }
    app.stepOnce = false;
    const refused = app.failed ? [] : replayDrops();
    if (refused.length) {
      toast(`Ignored from the link: ${refused.join('; ')}`);
      updateHash();
    }
  }
  const t1 = performance.now();
  const range = pg.updateColours();
  const n = pg.particleCount();
  const positions = new Float32Array(app.memory.buffer, pg.positionsPtr(), pg.positionsLen());
  const values = new Float32Array(app.memory.buffer, pg.coloursPtr(), pg.coloursLen());
  smoothRange(range);
  let marker = null;
  if (app.probeId !== null) {
    const i = pg.indexOf(app.probeId);
    if (i === undefined) {
      app.probeId = null;
      $('pq-note').textContent = 'The inspected particle is gone.';
    } else {
      const sp = JSON.parse(pg.stressPoint(i));
      marker = sp.position;
      if (report || !stressPlot.point) stressPlot.push(sp);
      $('pq-note').textContent = `particle #${sp.id} of body ${sp.body + 1} (${sp.model.replace('_', ' ')}): ` +
        `p = ${format(sp.p, 'Pa')}, q = ${format(sp.q, 'Pa')}, plastic strain ${sp.plastic_strain.toPrecision(2)}`;
    }
  }
  camera.matrices(canvasEl.clientWidth, canvasEl.clientHeight);
  renderer.draw({ camera, positions, stride: pg.positionsStride(), values, count: n, mode: app.view.colour, range: app.range, radius: app.radius, marker });
  if (app.syncRender) renderer.finish(); // benchmarks: count the GPU's work in renderMs
  const t2 = performance.now();
  st.simMs = t1 - t0;
  st.renderMs = 0.8 * st.renderMs + 0.2 * (t2 - t1);
  governQuality(wall);
  if (report) {
    st.substeps = report.substeps;
    if (report.substeps > 0) st.msPerStep = report.ms_per_step;
    st.fellBehind = report.fell_behind;
    const ratio = report.sim_time / (wall / 1000);
    st.ratio = st.ratio ? 0.9 * st.ratio + 0.1 * ratio : ratio;
  } else if (!app.playing) {
    st.substeps = 0;
    st.ratio = 0;
  }
  st.frames++;
  app.timings.push({ wall, sim: t1 - t0, render: t2 - t1, substeps: report ? report.substeps : 0, simTime: report ? report.sim_time : 0 });
  if (app.timings.length > 600) app.timings.shift();
  const d = JSON.parse(pg.diagnostics());
  if (report && n > 0) energyPlot.push(d);
  if (st.frames % 6 === 0) {
    energyPlot.draw(app.domain.length === 2 ? 'energy (J/m)' : 'energy (J)');
    stressPlot.draw();
    hud(d, n);
    legend();
  }
}

// Rendering quality adapts to the machine: without a GPU (Chromium's SwiftShader, a
// blocklisted driver) drawing tens of thousands of sprites is what limits the frame rate, so
// the contact shadows go first, then the resolution, and both come back when frames are
// quick again. The time a frame spends outside the simulation is what is measured.
const QUALITY = [
  { shadows: true, sphereDepth: true, scale: 1, label: '' },
  { shadows: false, sphereDepth: true, scale: 1, label: 'no shadows' },
  { shadows: false, sphereDepth: false, scale: 1, label: 'flat depth' },
  { shadows: false, sphereDepth: false, scale: 0.75, label: '¾ resolution' },
  { shadows: false, sphereDepth: false, scale: 0.5, label: '½ resolution' },
];
const quality = { level: 0, samples: [], changed: 0 };

function governQuality(wall) {
  const st = app.stats;
  const other = Math.max(0, wall - st.simMs);
  quality.samples.push(other);
  if (quality.samples.length > 20) quality.samples.shift();
  const sorted = [...quality.samples].sort((a, b) => a - b);
  st.otherMs = sorted[sorted.length >> 1];
  const now = performance.now();
  if (quality.samples.length < 20 || now - quality.changed < 1500 || app.fixedQuality) return;
  let level = quality.level;
  if (st.otherMs > 0.6 * (1000 / TARGET_FPS) && level < QUALITY.length - 1) level++;
  else if (st.otherMs < 0.2 * (1000 / TARGET_FPS) && level > 0 && now - quality.changed > 6000) level--;
  if (level !== quality.level) setQuality(level);
}

function setQuality(level) {
  quality.level = level;
  quality.changed = performance.now();
  quality.samples.length = 0;
  if ('shadows' in renderer) renderer.shadows = QUALITY[level].shadows;
  if ('scale' in renderer) renderer.scale = QUALITY[level].scale;
  if ('sphereDepth' in renderer) renderer.sphereDepth = QUALITY[level].sphereDepth;
  app.quality = QUALITY[level].label;
}

function smoothRange(range) {
  const mode = app.view.colour;
  if (mode === 'body' || mode === 'yield' || !app.range || app.rangeMode !== mode) app.range = [range[0], range[1]];
  else app.range = [range[0], Math.max(range[1], 0.95 * app.range[1] + 0.05 * range[1])];
  app.rangeMode = mode;
}

function fail(message) {
  app.failed = message;
  app.playing = false;
  syncControls();
  banner('failed', 'bad', `The simulation became unstable (${message}). A smaller CFL number or a softer material helps.`,
    { label: 'Reset', run: reset });
}

function hud(d, n) {
  const st = app.stats;
  const rows = [
    ['fps', st.fps.toFixed(0)],
    ['particles', n.toLocaleString('en')],
    ['steps / frame', String(st.substeps)],
    ['dt', formatTime(d.dt || app.pg.stableDt())],
    ['CFL', (d.cfl || 0).toFixed(2)],
    ['ms / step', st.msPerStep ? st.msPerStep.toPrecision(3) : '–'],
    ['sim / real', app.playing ? `${st.ratio.toFixed(2)}${st.fellBehind ? ' slow' : ''}` : 'paused'],
    ['sim time', formatTime(app.pg.time())],
    ['renderer', `${renderer.kind.replace(/ \(.*\)$/, '')}${app.quality ? `, ${app.quality}` : ''}`],
  ];
  const slow = app.playing && st.fellBehind;
  $('hud').replaceChildren(...rows.flatMap(([k, v]) => [
    el('span', { class: 'k' }, k),
    el('span', {
      class: `v${k === 'sim / real' && slow ? ' slow' : ''}`,
      'data-hud': k,
      title: k === 'sim / real' && slow ? 'Slow motion: each frame reached its time budget before it simulated a frame of time' : '',
    }, v),
  ]));
}

function legend() {
  const mode = app.view.colour;
  const box = $('legend');
  if (mode === 'body') {
    const scene = JSON.parse(app.pg.sceneJson());
    box.replaceChildren(...scene.bodies.slice(0, 8).map((b, i) =>
      el('span', { class: 'sw' }, el('i', { style: `background:${css(BODY_COLOURS[i % BODY_COLOURS.length])}` }), b.name || `body ${i + 1}`)));
    if (!scene.bodies.length) box.textContent = 'no bodies yet: drop one';
    return;
  }
  if (mode === 'yield') {
    box.replaceChildren(...YIELD_LABELS.map((l, i) => el('span', { class: 'sw' }, el('i', { style: `background:${css(YIELD_COLOURS[i])}` }), l)));
    return;
  }
  const [unit, scale, title] = {
    speed: ['m/s', 1, 'speed'], pressure: ['Pa', 1, 'pressure p'], plastic_strain: ['', 1, 'plastic strain'],
  }[mode];
  const stops = Array.from({ length: 9 }, (_, i) => css(viridis(i / 8))).join(', ');
  box.replaceChildren(
    el('div', {}, title),
    el('div', { class: 'ramp', style: `background: linear-gradient(90deg, ${stops})` }),
    el('div', { class: 'ends' }, el('span', {}, format(app.range[0] * scale, unit)), el('span', {}, format(app.range[1] * scale, unit))));
}

// ---------- start ----------

let camera, renderer, canvasEl, energyPlot, stressPlot;

async function main() {
  canvasEl = $('view');
  try {
    renderer = new GlRenderer(canvasEl);
  } catch (e) {
    console.warn(`WebGL2 unavailable (${e.message}); using the 2D canvas fallback`);
    renderer = new CanvasRenderer(canvasEl);
  }
  camera = new Camera([2, 1, 1]);
  app.camera = camera;
  app.renderer = renderer;
  energyPlot = new EnergyPlot($('energy'));
  stressPlot = new StressPlot($('pq'));
  try {
    const wasm = await init();
    app.memory = wasm.memory;
  } catch (e) {
    banner('failed', 'bad', `The solver did not load (${e.message}). Build it first: cargo xtask build (or cargo xtask serve).`);
    return;
  }
  await Promise.all([loadSceneList(), loadBunny()]);
  const { view, params, drops, cleared, errors } = readHash();
  if (!location.hash) {
    // First visit: a scene with sand, if the scene list has one.
    const pick = ['bunny_on_sand_ball', 'notched_sand_block', 'column_collapse'].find((b) => app.scenes.some((s) => s.base === b));
    if (pick) app.view.scene = pick;
  }
  Object.assign(app.view, view);
  buildControls();
  setupPointer(canvasEl);
  await loadScene(params, { drops, cleared, ignored: errors });
  requestAnimationFrame(frame);
}

main();
