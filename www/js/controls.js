// The page's controls: the scene picker, 2D/3D, playback, the drop tool's object, material,
// size and speed, the pour tool's rate, the sliders of the parameter table (the chosen
// material's and the world's), colours, the click tool, the plots, the link, and the keys.

import { ENERGY_SERIES } from './plots.js';
import { boundedMax, format } from './params.js';
import { OPENED, SANDBOX } from './scenes.js';
import { toast } from './hud.js';
import { el, paramSlider, segmented } from './widgets.js';

const $ = (id) => document.getElementById(id);
let markObject, markMaterial;

/// Builds the controls once the solver's table is known.
export function buildControls(app) {
  const table = app.session.table;
  $('scene').replaceChildren(...app.scenes.map((s) => el('option', { value: s.base }, s.name)));
  $('quality').replaceChildren(...app.session.qualities.levels.map((q) => el('option', { value: q.id, title: q.hint }, q.label)));
  $('quality').addEventListener('change', () => app.setQuality($('quality').value));
  markObject = segmented($('objects'), table.objects, (id) => pickObject(app, id));
  markMaterial = segmented($('materials'), table.models, (id) => pickMaterial(app, id, true));
  $('world-params').replaceChildren(...table.world.map((s) => slider(app, s)));
  $('energy-legend').replaceChildren(...ENERGY_SERIES.map((s) => el('span', {}, el('i', { style: `background:${s.colour}` }), s.label)));

  $('scene').addEventListener('change', () => {
    const value = $('scene').value;
    if (value.startsWith('lesson:')) return app.openLesson(value.slice('lesson:'.length));
    const entry = app.scenes.find((s) => s.base === value);
    app.view.lesson = undefined;
    app.view.scene = entry ? entry.base : value;
    if (entry && !entry.paths[app.view.dim]) app.view.dim = Object.keys(entry.paths)[0];
    app.view.size = undefined;
    // A new scene starts with its own parameters, at the quality chosen.
    app.loadScene({ quality: app.session.quality.quality });
  });
  for (const d of ['2', '3'])
    $(`dim${d}`).addEventListener('click', () => {
      if (app.view.dim === d) return;
      app.view.dim = d;
      app.view.size = undefined;
      // The quality and the parameters changed so far are kept; the drops are not.
      const { quality, params } = app.session.session();
      app.loadScene({ quality, params });
    });
  $('play').addEventListener('click', () => app.togglePlay());
  $('step').addEventListener('click', () => app.step());
  $('reset').addEventListener('click', () => app.reset());
  $('clear').addEventListener('click', () => app.clear());
  $('toggle-plots').addEventListener('click', () => showPlots(document.body.classList.contains('no-plots')));
  // Wide screens show the plots beside the view; narrower ones on demand, beneath it.
  if (window.innerWidth < 1500) showPlots(false);
  $('timescale').addEventListener('change', () => {
    app.view.time = $('timescale').value;
    app.session.timeScale(Number(app.view.time));
    app.updateHash();
  });
  $('sleeping').addEventListener('change', () => {
    app.view.sleep = $('sleeping').checked ? undefined : '0'; // on, the default, stays out of the link
    app.session.sleeping($('sleeping').checked);
    app.updateHash();
  });
  $('colour').addEventListener('change', () => {
    app.view.colour = $('colour').value;
    app.session.colour(app.view.colour);
    app.updateHash();
  });
  $('share').addEventListener('click', async () => {
    app.updateHash();
    try {
      await navigator.clipboard.writeText(location.href);
      toast('Link copied: it opens this scene with these parameters and drops the same bodies.');
    } catch {
      toast('Copy the address bar: it holds this scene, its parameters and the bodies dropped.');
    }
  });
  for (const b of document.querySelectorAll('[data-tool]')) b.addEventListener('click', () => pickTool(app, b.dataset.tool));
  window.addEventListener('keydown', (e) => {
    if (e.target.closest('input, select, textarea') || e.ctrlKey || e.metaKey || e.altKey) return;
    const k = e.key.toLowerCase();
    if (k === ' ') { e.preventDefault(); app.togglePlay(); }
    else if (k === 's') app.step();
    else if (k === 'r') app.reset();
    else if (k === 'd') pickTool(app, 'drop');
    else if (k === 'p') pickTool(app, 'pour');
    else if (k === 'i') pickTool(app, 'inspect');
  });
  window.addEventListener('hashchange', () => app.loadFromHash());
}

/// Shows or hides the plots (beside the view on wide screens, beneath it on narrower ones:
/// never over it).
export function showPlots(on) {
  document.body.classList.toggle('no-plots', !on);
  $('toggle-plots').setAttribute('aria-pressed', String(on));
}

/// Puts the plot a lesson talks about (`stress_path`, or `energy`) first in the plots' column,
/// so that it shows without scrolling beside the view; outside a lesson, the energy first.
export function leadPlot(plot) {
  $('plots').prepend(plot === 'stress_path' ? $('pq-card') : $('energy-card'));
}

/// A slider for parameter `spec` of the table, registered in `app.sliders`.
function slider(app, spec) {
  const w = paramSlider({ ...spec }, (v) => app.applyParam(spec.name, v));
  w.spec = spec;
  app.sliders.set(spec.name, w);
  return w.root;
}

/// Shows the state: the sliders' values (`values`: also after a reset or a new scene), their
/// bounds that depend on other parameters (ψ ≤ φ), the pickers, playback and the tool.
export function syncControls(app, values = true) {
  const current = app.session.parameters();
  for (const [name, w] of app.sliders) {
    if (values && name in current) w.set(current[name]);
    if (w.spec.at_most) w.setMax(boundedMax(w.spec, current));
  }
  $('colour').value = app.view.colour;
  $('sleeping').checked = app.view.sleep !== '0';
  $('timescale').value = app.view.time;
  $('quality').value = app.session.quality.quality;
  const q = app.session.quality;
  $('quality').title = `${app.session.qualities.levels.find((l) => l.id === q.quality)?.hint ?? ''}. ` +
    'Another level samples the scene again and starts it over, with the parameters and drops so far.';
  const lesson = app.view.lesson && app.lessons.find((l) => l.id === app.view.lesson);
  const entry = lesson ? null : app.scenes.find((s) => s.base === app.view.scene);
  const select = $('scene');
  for (const o of [...select.options]) if (o.dataset.extra) o.remove();
  if (entry || app.view.scene === SANDBOX && !lesson) select.value = entry ? entry.base : SANDBOX;
  else {
    // A lesson, a scene file given by path in the link, a file opened: listed while shown.
    const [value, label] = lesson ? [`lesson:${lesson.id}`, `Lesson: ${lesson.title}`]
      : [app.view.scene, app.view.scene.startsWith(OPENED) ? `${app.view.scene.slice(OPENED.length)} (opened)` : app.view.scene.split('/').pop()];
    const o = el('option', { value }, label);
    o.dataset.extra = '1';
    select.append(o);
    select.value = value;
  }
  for (const d of ['2', '3']) {
    const b = $(`dim${d}`);
    b.setAttribute('aria-pressed', String(app.view.dim === d));
    // A scene of the list has the dimensions it has files for; a lesson or a file one only.
    b.disabled = entry ? !entry.paths[d] : app.view.scene !== SANDBOX || !!lesson ? app.view.dim !== d : false;
  }
  markObject(app.view.object);
  if (values) pickMaterial(app, app.view.material, false);
  pickTool(app, app.tool);
  $('play').textContent = app.playing ? 'Pause' : 'Play';
}

function pickTool(app, tool) {
  app.tool = tool;
  for (const b of document.querySelectorAll('[data-tool]')) b.setAttribute('aria-pressed', String(b.dataset.tool === tool));
  // The Drop card: the object, size and speed for a drop; the rate for a pour (the material
  // menu serves both).
  const pour = tool === 'pour';
  $('drop-title').textContent = pour ? 'Pour' : 'Drop';
  $('objects').hidden = pour;
  $('drop-params').hidden = pour;
  $('pour-params').hidden = !pour;
  if (!app.pour) showHint(app);
}

/// The hint under the view: what the tool does, or `text` (`pouring`: a pour is running,
/// shown on every screen).
export function showHint(app, text, pouring = false) {
  const tool = app.tool, d3 = app.domain.length === 3;
  $('hint').textContent = text ?? (tool === 'drop'
    ? (d3 ? 'Click on the floor to drop' : 'Click in the box to drop')
    : tool === 'pour'
      ? `${d3 ? 'Press and hold on the floor' : 'Press and hold in the box'} to pour sand from a spout above it; release to stop`
      : tool === 'measure' ? 'Drag to measure a length and its angle'
        : 'Click a particle to inspect its stress');
  $('hint').classList.toggle('pouring', pouring);
}

function pickObject(app, id) {
  app.view.object = id;
  markObject(id);
  app.updateHash();
}

/// Shows the sliders of material model `id` (the page's choice for the next drop, too).
function pickMaterial(app, id, user) {
  app.view.material = id;
  markMaterial(id);
  const table = app.session.table;
  const m = table.models.find((x) => x.id === id);
  $('material-title').textContent = `Material: ${m.label}`;
  $('material-note').textContent = `${m.hint}. Applies to every ${m.label.toLowerCase()} body and to the next one you drop.`;
  for (const key of [...app.sliders.keys()]) if (app.sliders.get(key).spec.model) app.sliders.delete(key);
  $('material-params').replaceChildren(...table.ofModel(id).map((s) => slider(app, s)));
  const current = app.session.parameters();
  for (const [name, w] of app.sliders) {
    if (!w.spec.model) continue;
    w.set(current[name]);
    if (w.spec.at_most) w.setMax(boundedMax(w.spec, current));
  }
  app.lessonPanel?.mark();
  if (user) app.updateHash();
}

/// The drop tool's size and speed sliders and the pour tool's rate, for the scene just loaded.
export function buildDropControls(app) {
  const [lo, hi] = app.sizeRange;
  const size = paramSlider({ name: 'drop.size', label: 'Size', symbol: 'L', unit: 'm', min: +lo.toPrecision(2), max: +hi.toPrecision(2), step: 0.01 }, async (v) => {
    const error = await app.session.checkSize(v);
    if (error) return error;
    app.size = v;
    app.updateHash();
    return '';
  });
  size.set(app.size);
  const speed = paramSlider({ name: 'drop.speed', label: 'Drop speed', symbol: 'v', unit: 'm/s', min: 0, max: 10, step: 0.1 }, (v) => {
    if (!(v >= 0 && v <= 50)) return `drop speed = ${v}: must be in [0, 50] (m/s)`;
    app.dropSpeed = v;
    return '';
  });
  speed.set(app.dropSpeed);
  $('drop-params').replaceChildren(size.root, speed.root);
  buildPourControl(app);
}

/// The pour tool's rate, for the scene as sampled now (the spout is a few cells wide, so its
/// rates change with the scene and the quality level): the rate set so far is kept where it is
/// still allowed (in the same unit), else the scene's default is taken.
export function buildPourControl(app) {
  const r = app.session.pourRates();
  const d3 = app.domain.length === 3;
  const [lo, hi] = r.allowed;
  if (app.rateUnit !== r.unit || !(app.rate >= lo && app.rate <= hi)) app.rate = r.default;
  app.rateUnit = r.unit;
  const cm = (m) => +(100 * m).toPrecision(3);
  const rate = paramSlider({
    name: 'pour.rate', label: 'Pour rate', symbol: 'Q', unit: r.unit, min: r.offered[0], max: r.offered[1], scale: 'log',
    help: `The volume of sand the spout lets out per second (${r.unit}${d3 ? '' : ', per metre of depth'}): ` +
      `its exit, ${cm(2 * r.radius)} cm ${d3 ? 'across' : 'wide'}, is held ${r.height} m above the floor (higher over sand already there). ` +
      `The default, ${format(r.default)} ${r.unit}, leaves it at ${r.speeds.default} m/s; the slider runs from a trickle ` +
      `(${r.speeds.offered[0]} m/s) to ${r.speeds.offered[1]} m/s, and any rate from ${format(lo)} to ${format(hi)} ${r.unit} may be typed ` +
      `(${r.speeds.allowed[0]} to ${r.speeds.allowed[1]} m/s). Pick Pour, then press and hold on the floor.`,
  }, async (v) => {
    const error = await app.session.checkRate(v);
    if (error) return error;
    app.rate = v;
    return '';
  });
  rate.set(app.rate);
  $('pour-params').replaceChildren(rate.root, el('p', { class: 'note', id: 'pour-range' },
    `Rates from ${format(lo)} to ${format(hi)} ${r.unit} may be typed; the slider offers ${format(r.offered[0])} to ${format(r.offered[1])}.`));
}
