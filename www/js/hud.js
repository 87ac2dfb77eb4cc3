// What the page tells the user over the view: the HUD of figures, the colour legend, banners
// (warnings that stay while they hold) and toasts (messages that fade).

import { BODY_COLOURS, SLEEP_COLOUR, YIELD_COLOURS, YIELD_LABELS, bodyNames, css, viridis } from './colours.js';
import { format, formatTime } from './params.js';
import { el } from './widgets.js';
import { accuracyNote, pct, speedWords } from './measure-view.js';

const $ = (id) => document.getElementById(id);

let toastTimer = 0;
/// A message that fades after a few seconds.
export function toast(msg) {
  const t = $('toast');
  t.textContent = msg;
  t.classList.add('show');
  clearTimeout(toastTimer);
  toastTimer = setTimeout(() => t.classList.remove('show'), 3500);
}

const banners = new Map();
/// Shows banner `key` (kind 'warn' or 'bad') with `html` and an optional button
/// `action` {label, run}; without `html`, removes it.
export function banner(key, kind, html, action) {
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

/// Warns when a parameter value makes the simulation run in slow motion (prediction `p`
/// against `before`, the current value's) and when the CFL number is near the stability limit.
/// (The FLIP ratio needs no warning: the solver caps it in steps where walls or contacts act,
/// and no FLIP ratio in [0, 1] gains energy at impacts; docs/stability.md.)
export function warnCost(spec, value, p, before, session) {
  const slower = p.substeps_per_frame > 1.5 * before.substeps_per_frame;
  const slow = p.realtime_ratio > 0 && p.realtime_ratio < 0.25;
  if (p.valid && slower && slow) {
    banner('slow', 'warn', `${spec.label} ${format(value, spec.unit)} needs ${Math.round(p.substeps_per_frame)} steps per frame ` +
      `(time step ${formatTime(p.stable_dt)}): expect slow motion, about ${(100 * p.realtime_ratio).toPrecision(2)} % of real time. ` +
      'Each frame stops at its time budget, so the page stays responsive.');
  } else if (!slow) banner('slow'); // fast enough again
  const cfl = session.parameter('cfl');
  banner('cfl', 'warn', cfl > 0.6
    ? `CFL number ${cfl}: steps this close to the stability limit can make fast impacts jitter or blow up; 0.3–0.5 is safe.`
    : '');
}

/// The HUD, in the strip above the view: `rows` {main, tech} of [label, value, title?]; the
/// class's figures always, the technical ones when `details` is on. The real-time figure is
/// marked when `slow`.
export function hud(rows, slow, details) {
  const item = ([k, v, title = ''], tech) => {
    const marked = k === 'speed' && slow && v.startsWith('slow motion');
    return el('span', { class: `row row-${k}${tech ? ' tech' : ''}` },
      el('span', { class: 'k' }, k),
      el('span', {
        class: `v${marked ? ' slow' : ''}`,
        'data-hud': k,
        title: marked ? 'Slow motion: the simulation steps slower than real time at this resolution' : title,
      }, v));
  };
  $('hud').replaceChildren(...rows.main.map((r) => item(r, false)), ...(details ? rows.tech.map((r) => item(r, true)) : []));
}

/// What a level does to a body dropped (the quality line's tooltip; src/playground/figures.rs).
const DROPS = 'A body dropped takes the scene\'s cells at this level; the empty sandbox keeps its own 2.5 cm cells at ' +
  'every level, where a dropped sand box rests as one dense heap with its flanks within 5° of the same drop at Fine';

/// The HUD's rows from the frame statistics `st`, diagnostics `d` and the rest. `main`, what
/// a class needs: the simulated time, the real-time factor in words, the quality level with
/// what its resolution costs in accuracy (the validation cases' errors at that cell size and
/// particles per cell, `resolution.accuracy`; in 3D the level's 3D sand figures,
/// `resolution.sand`) and, when given, why the page opened at that level (`why`). `tech`, behind Details: frame rate, particles,
/// particles asleep, steps per frame, time step, CFL number, cost per step, the resolution,
/// renderer, solver.
export function hudRows(st, d, { particles, asleep = 0, playing, stableDt, time, renderer, quality, thread, resolution, label, dim, why = '' }) {
  const a = resolution.accuracy;
  const sand = dim === 3 ? resolution.sand : null;
  return {
    main: [
      ['time', formatTime(time)],
      ['speed', speedWords(st.ratio, playing)],
      ['quality', `${accuracyNote(label, a, sand)}${why ? ` (${why})` : ''}`, sand
        ? 'What this level\'s grid costs for sand, measured on the shipped 3D column collapse (a = 2) sampled at this level and run to ' +
          `rest (docs/playground.md): run-out where the deposit is one grain thick ${pct(sand.runout)} against Lube et al. (2004)'s ` +
          `axisymmetric experiments, whose marks the page draws (farthest particle ${pct(sand.farthest)}); flank ${sand.flank.toFixed(1)}°` +
          `. ${DROPS}`
        : 'The errors at this resolution, measured on the validation cases at the same cell factor and particles per cell ' +
          `(docs/playground.md): column collapse run-out ${pct(a.column_runout)} and height ${pct(a.column_height)} against ` +
          `Lube et al. (2005)'s experiments, vibrating bar period ${pct(a.bar_period)} (L2 ${pct(a.bar_l2)}), resting column settlement ${pct(a.resting_settlement)}` +
          `. ${DROPS}`],
    ],
    tech: [
      ['fps', st.fps.toFixed(0)],
      ['particles', particles.toLocaleString('en')],
      ['asleep', asleep.toLocaleString('en'), 'Particles at rest that are not stepped until something touches them (Sleep at rest, under More)'],
      ['steps / frame', String(st.substeps)],
      ['dt', formatTime(d.dt || stableDt)],
      ['CFL', (d.cfl || 0).toFixed(2)],
      ['ms / step', st.msPerStep ? st.msPerStep.toPrecision(3) : '–'],
      ['sim / real', playing ? st.ratio.toFixed(2) : 'paused'],
      ['cells', `h ${+(100 * resolution.cell_size).toPrecision(3)} cm, ${Array(dim).fill(resolution.particles_per_cell).join('×')} per cell`,
        `Cells ${+(resolution.cell_size / resolution.scene_cell_size).toPrecision(3)} × the scene file's; particles per cell per axis ${resolution.particles_per_cell}`],
      ['renderer', `${renderer.replace(/ \(.*\)$/, '')}${quality ? `, ${quality}` : ''}`],
      ['solver', `wasm, ${thread}`],
    ],
  };
}

/// The legend of colour mode `mode`: the bodies of `scene`, the yield states, or a ramp over
/// `range`.
export function legend(mode, scene, range) {
  const box = $('legend');
  if (mode === 'body') {
    const names = bodyNames(scene.bodies);
    box.replaceChildren(...scene.bodies.slice(0, 8).map((b, i) =>
      el('span', { class: 'sw' }, el('i', { style: `background:${css(BODY_COLOURS[i % BODY_COLOURS.length])}` }), names[i])));
    if (!scene.bodies.length) box.textContent = 'no bodies yet: drop one';
    return;
  }
  if (mode === 'sleeping') {
    box.replaceChildren(el('span', { class: 'sw' }, el('i', { style: `background:${css(BODY_COLOURS[0])}` }), 'awake (body colour)'),
      el('span', { class: 'sw' }, el('i', { style: `background:${css(SLEEP_COLOUR)}` }), 'asleep'));
    return;
  }
  if (mode === 'yield') {
    box.replaceChildren(...YIELD_LABELS.map((l, i) => el('span', { class: 'sw' }, el('i', { style: `background:${css(YIELD_COLOURS[i])}` }), l)));
    return;
  }
  const [unit, title] = { speed: ['m/s', 'speed'], pressure: ['Pa', 'pressure p'], plastic_strain: ['', 'plastic strain'] }[mode];
  const stops = Array.from({ length: 9 }, (_, i) => css(viridis(i / 8))).join(', ');
  box.replaceChildren(
    el('div', {}, title),
    el('div', { class: 'ramp', style: `background: linear-gradient(90deg, ${stops})` }),
    el('div', { class: 'ends' }, el('span', {}, format(range[0], unit)), el('span', {}, format(range[1], unit))));
}
