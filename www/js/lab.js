// The soil lab: the direct shear box and the biaxial test (plane strain) of scenes/lab/, run
// live by the solver in this page (wasm `LabTest`, which reads `mpm::lab` from the forces the
// solver computes). While a test runs it plots τ–δ and the lid's rise (shear box) or q–ε_a and
// ε_v–ε_a (biaxial); each finished test adds its failure point or circle to a Mohr plot, and
// from two runs of a kind the page fits the envelope (`fitEnvelope`) and reads back φ and c
// beside the sliders' values. Opened by the Lab button or a link (`#lab`). A soil-lab lesson
// (`lab` in its file: docs/lessons.md) opens here: its caption and question, then, on Run, its
// runs at their loads (then the compared test's, `lab.compare`, at the same loads); once the last
// has run its duration the question is answered with the quantity the solver's reader reports
// (`LabTest.quantity`, combined by `labAnswer`), or with the difference of the two tests'
// envelopes the page fitted (`angle_difference`: `lessonValue`).

import init, { LabTest, davisEnvelope, fitEnvelope, labAnswer, labSceneAt, lessonLabScene } from '../pkg/mpm.js';
import { axes, setup } from './plots.js';
import { el } from './widgets.js';
import { answerIndex } from './measure-view.js';

const $ = (id) => document.getElementById(id);
/// Simulated duration of each test (s), as the soil-lab table of docs/validation.md runs them
/// (the shear box 2 mm of travel at 0.02 m/s).
export const DURATION = { shear_box: 0.1, biaxial: 0.3 };
/// Seconds between readings.
const EVERY = 0.002;
/// Milliseconds of stepping per display frame. The test steps on the page's thread and the
/// browser's frame costs about as much again whatever the stepping (its compositing, the wait
/// for the display), so a longer share per frame runs the test faster: at 14 ms the solver
/// had 0.58–0.63 of the wall clock in headless Chromium, at 48 ms (about 20 plot updates a
/// second) 0.71–0.74 (`www/bench/lab-page.mjs`, docs/validation.md's *Speed*).
export const FRAME_BUDGET_MS = 48;

/// The scene file of a test and material.
export function sceneFile(test, model) {
  if (test === 'shear_box') return 'scenes/lab/shear_box_mc_2d.json';
  return model === 'drucker_prager' ? 'scenes/lab/biaxial_dp_2d.json' : 'scenes/lab/biaxial_mc_2d.json';
}

/// The test's scene with the sliders' values: the sample's material (`model`, φ, ψ in degrees,
/// c in Pa) and its load (`load`, Pa: for the shear box the lid's load, its weight over the
/// box's length, while σ_n on the shear plane is read; for the biaxial test the confining
/// traction σ3: the solver's `labSceneAt`).
export function labScene(base, test, { model, phi, psi, c, load }) {
  const scene = structuredClone(base);
  const sample = scene.bodies[0];
  const [old] = Object.keys(sample.material);
  const m = { ...sample.material[old], friction_angle: phi, dilatancy_angle: psi, cohesion: c };
  if (model === 'drucker_prager') m.friction_match = 'plane_strain';
  else delete m.friction_match;
  sample.material = { [model]: m };
  return JSON.parse(labSceneAt(JSON.stringify(scene), load));
}

const KPA = (v) => `${+(v / 1e3).toPrecision(3)}`;
/// A lab question's measured value in words: ratios of shear strengths as "1.93×", a rise in
/// mm, the difference of the two tests' angles in degrees.
export function labShown(quantity, value, runs) {
  if (quantity === 'lid_rise') return `the lid rose ${(value * 1e3).toFixed(2)} mm`;
  if (quantity === 'angle_difference') {
    return `the shear box's envelope ${Math.abs(value).toFixed(1)}° ${value < 0 ? 'lower' : 'higher'} than the biaxial test's`;
  }
  return runs.length === 2 ? `shear strength τ ${value.toFixed(2)}× as large` : `shear strength τ ${KPA(value)} kPa`;
}

/// A soil-lab question's answer once its runs have ended: the runs' quantities it names
/// (`values`, in the order of the runs) combined by `labAnswer`, or for `angle_difference` the
/// angle of the shear box's fitted envelope less the biaxial test's (`fits`, as `fitEnvelope`
/// read them; `mpm::lesson::angle_difference`); undefined when they fix none.
export function lessonValue(q, values, fits) {
  if (q.measure.quantity === 'angle_difference') {
    return fits.shear_box && fits.biaxial ? fits.shear_box.friction_angle - fits.biaxial.friction_angle : undefined;
  }
  const named = q.measure.runs.map((r) => values[r] ?? null);
  return named.includes(null) ? undefined : labAnswer(new Float64Array(named));
}

/// The sentence that says why the two tests read different angles, with the page's numbers.
export function whyDifferent(material, fits) {
  const davis = JSON.parse(davisEnvelope(material.phi, material.psi, material.c));
  const own = material.model === 'drucker_prager' ? 'its plane-strain matched cone, φ_ps = φ' : 'its Mohr–Coulomb envelope, φ';
  const read = fits.biaxial ? `the biaxial test reads ${fits.biaxial.friction_angle.toFixed(1)}°` : '';
  const sb = fits.shear_box;
  // both figures side by side, and how far apart: the page claims no agreement it does not show
  const against = sb
    ? `The shear box read ${sb.friction_angle.toFixed(1)}°; Davis's closed form gives ${davis.friction_angle.toFixed(1)}°`
      + ` for these sliders, ${Math.abs(sb.friction_angle - davis.friction_angle).toFixed(1)}° apart. ` : '';
  return `${against}${read ? `Here ${read}. ` : ''}The two tests need not agree: the shear box makes the sample slip on`
    + ` its horizontal mid-plane, where Davis (1968) puts the ratio τ/σ_n at failure at tan φ_ds = sin φ cos ψ / (1 − sin φ sin ψ),`
    + ` ${davis.friction_angle.toFixed(1)}° for φ = ${material.phi}°, ψ = ${material.psi}°; the biaxial test's circles touch`
    + ` the material's own envelope (${own} = ${material.phi}°).`;
}

/// A line plot of `series` ([{x, y}] readings) on `canvas`.
function linePlot(canvas, points, xlabel, ylabel, fx, fy) {
  const { ctx, w, h } = setup(canvas);
  if (w < 80 || h < 60) return;
  const box = { x0: 56, y0: 8, x1: w - 10, y1: h - 34 };
  const xs = points.map((p) => p.x), ys = points.map((p) => p.y);
  let [xa, xb] = [Math.min(0, ...xs), Math.max(1e-12, ...xs)];
  let [ya, yb] = [Math.min(0, ...ys), Math.max(1e-12, ...ys)];
  if (yb - ya < 1e-12) yb = ya + 1;
  if (xb - xa < 1e-12) xb = xa + 1;
  axes(ctx, box, [xa, xb], [ya, yb], xlabel, ylabel, fx, fy);
  const X = (v) => box.x0 + ((v - xa) / (xb - xa)) * (box.x1 - box.x0);
  const Y = (v) => box.y1 - ((v - ya) / (yb - ya)) * (box.y1 - box.y0);
  ctx.strokeStyle = '#1c7ed6';
  ctx.lineWidth = 2;
  ctx.beginPath();
  points.forEach((p, i) => (i ? ctx.lineTo(X(p.x), Y(p.y)) : ctx.moveTo(X(p.x), Y(p.y))));
  ctx.stroke();
}

const kPa = (v) => `${+(v / 1e3).toPrecision(3)}`;
const mm = (v) => `${+(v * 1e3).toPrecision(3)}`;
const pct = (v) => `${+(v * 100).toPrecision(3)}`;

export class Lab {
  constructor(app) {
    this.app = app;
    this.root = $('lab');
    this.runs = []; // finished tests: {test, failure: [a, b]}
    this.readings = [];
    this.test = null;
    this.fits = { shear_box: null, biaxial: null };
    this.bases = {};
    this.frameBudget = FRAME_BUDGET_MS;
    this.lessonRun = null; // a soil-lab lesson open here: {lesson, text, scene, picked, values, answer}
    this.ready = init();
    $('lab-open').addEventListener('click', () => this.open());
    $('lab-close').addEventListener('click', () => this.close());
    $('lab-run').addEventListener('click', () => this.run());
    $('lab-clear').addEventListener('click', () => this.clearRuns());
    $('lab-test').addEventListener('change', () => this.syncLoad());
    for (const id of ['lab-model', 'lab-phi', 'lab-psi', 'lab-c']) {
      $(id).addEventListener('input', () => { this.showValues(); this.clearRuns(); });
    }
    $('lab-load').addEventListener('input', () => this.showValues());
    this.syncLoad();
    if (location.hash === '#lab') this.open();
  }

  /// Opens the lab and pauses the page's own scene (the lab's test has the core to itself).
  open() {
    this.app?.setPlaying(false);
    this.root.hidden = false;
    this.draw();
  }
  close() {
    this.root.hidden = true;
    this.running = false;
    this.lessonRun = null;
    $('lab-lesson').hidden = true;
  }

  /// Opens soil-lab lesson `lesson` (as the page fetched it, with its `id`) on its scene's
  /// text: its caption and question; Run runs its loads in turn.
  async openLesson(lesson, sceneText) {
    const { id, compareScene, ...file } = lesson;
    const q = lesson.question ?? null;
    const kind = JSON.parse(sceneText).bodies.some((b) => b.traction) ? 'biaxial' : 'shear_box';
    // the scene's runs, then the compared test's (the other kind) at the same loads
    const tests = [[sceneText, kind], ...(compareScene ? [[compareScene, kind === 'biaxial' ? 'shear_box' : 'biaxial']] : [])];
    this.lessonRun = { id, lesson, text: JSON.stringify(file), scene: sceneText, tests, picked: -1, values: [], answer: null };
    this.clearRuns();
    $('lab-test').value = kind;
    this.syncLoad();
    $('lab-lesson-title').textContent = lesson.title;
    $('lab-lesson-caption').textContent = lesson.caption;
    const box = $('lab-lesson-question');
    box.replaceChildren();
    if (q) {
      const buttons = q.choices.map((c, i) => el('button', {
        'data-choice': String(i), 'aria-pressed': 'false',
        onclick: () => {
          if (this.lessonRun?.answer || this.lessonRun?.busy) return; // the prediction stands once running
          this.lessonRun.picked = i;
          for (const b of buttons) b.setAttribute('aria-pressed', String(b === buttons[i]));
          verdict.textContent = 'Now press Run and watch.';
        },
      }, c.text));
      const verdict = el('div', { class: 'verdict', id: 'lab-lesson-verdict' }, 'Predict first: pick an answer, then press Run.');
      box.replaceChildren(el('div', { class: 'ask' }, q.ask), el('div', { class: 'choices' }, ...buttons), verdict);
      this.lessonRun.buttons = buttons;
      this.lessonRun.verdict = verdict;
    }
    $('lab-lesson').hidden = false;
    // the controls show the lesson's first run: its sand and load (what the Davis sentence quotes)
    await this.ready;
    const first = JSON.parse(lessonLabScene(this.lessonRun.text, sceneText, 0)).bodies.find((b) => b.material.mohr_coulomb || b.material.drucker_prager);
    const [model] = Object.keys(first.material);
    const m = first.material[model];
    $('lab-model').value = model;
    Object.entries({ 'lab-phi': m.friction_angle, 'lab-psi': m.dilatancy_angle ?? 0, 'lab-c': (m.cohesion ?? 0) / 1e3, 'lab-load': lesson.lab.loads[0] / 1e3 })
      .forEach(([id, v]) => { $(id).value = String(v); });
    this.showValues();
    const loads = lesson.lab.loads.map((l) => `${KPA(l)} kPa`).join(', ');
    const what = tests.length > 1 ? 'shear box and biaxial test each' : lesson.lab.loads.length === 1 ? 'test' : 'tests';
    $('lab-status').textContent = `Run runs the lesson's ${what} at ${loads}.`;
    this.open();
  }

  /// The sliders' material: {model, phi, psi, c (Pa)}.
  material() {
    return { model: $('lab-model').value, phi: +$('lab-phi').value, psi: +$('lab-psi').value, c: +$('lab-c').value * 1e3 };
  }

  syncLoad() {
    const shear = $('lab-test').value === 'shear_box';
    $('lab-load-label').textContent = shear ? 'lid load (kPa)' : 'σ3 (kPa)';
    this.showValues();
  }

  showValues() {
    for (const id of ['lab-phi', 'lab-psi', 'lab-c', 'lab-load']) $(`${id}-value`).textContent = $(id).value;
  }

  clearRuns() {
    this.runs = [];
    this.fits = { shear_box: null, biaxial: null };
    this.draw();
  }

  async run() {
    await this.ready;
    if (this.lessonRun) return this.lessonRun.busy ? undefined : this.runLesson();
    const test = $('lab-test').value;
    const material = this.material();
    const file = sceneFile(test, material.model);
    this.bases[file] ??= await (await fetch(file, { cache: 'no-cache' })).json();
    const scene = labScene(this.bases[file], test, { ...material, load: +$('lab-load').value * 1e3 });
    return this.runScene(scene, test);
  }

  /// The open lesson's runs in turn, each for its duration; then its question is answered
  /// from what the solver's reader reports of the runs it names (never before the last ends).
  async runLesson() {
    const run = this.lessonRun;
    run.values = [];
    run.answer = null;
    run.busy = true;
    for (const b of run.buttons ?? []) b.classList.remove('answer');
    this.clearRuns();
    try {
      await this.lessonRuns(run);
    } finally {
      run.busy = false;
    }
  }

  async lessonRuns(run) {
    const q = run.lesson.question;
    for (const [sceneText, kind] of run.tests) {
      $('lab-test').value = kind;
      this.syncLoad();
      for (let i = 0; i < run.lesson.lab.loads.length; i++) {
        const scene = JSON.parse(lessonLabScene(run.text, sceneText, i));
        const ended = await this.runScene(scene, kind, run.lesson.duration);
        if (!ended || this.lessonRun !== run) return;
        if (sceneText === run.scene) run.values.push(q ? this.test.quantity(q.measure.quantity) ?? null : null);
      }
    }
    if (!q) return;
    const value = lessonValue(q, run.values, this.fits);
    if (value === undefined) return;
    const i = answerIndex(q, value);
    // the two angles: why they differ, with the figures just measured
    const why = q.measure.quantity === 'angle_difference' ? ` ${whyDifferent(this.material(), this.fits)}` : '';
    run.answer = { value, index: i, why: Boolean(why) };
    if (i >= 0) run.buttons[i].classList.add('answer');
    const mine = run.picked < 0 ? '' : run.picked === i ? ' Your prediction was right.' : ` You predicted “${q.choices[run.picked].text}”.`;
    run.verdict.textContent = `Measured by the page: ${labShown(q.measure.quantity, value, q.measure.runs)}`
      + `${i >= 0 ? ` → “${q.choices[i].text}”.` : ' (outside every choice).'}${mine}${why}`;
    this.showFit();
  }

  /// Runs `scene` (a lab test of kind `test`) for `end` s of simulated time (the test's
  /// default when absent), plotting as it goes; resolves true when it ran to its end.
  runScene(scene, test, end = DURATION[test]) {
    this.test?.free();
    try {
      this.test = new LabTest(JSON.stringify(scene));
    } catch (e) {
      $('lab-status').textContent = `The test did not start: ${e.message}`;
      return Promise.resolve(false);
    }
    this.kind = test;
    this.readings = [];
    this.running = true;
    $('lab-run').disabled = true;
    $('lab-status').textContent = 'Running…';
    const started = performance.now();
    let done;
    const ended = new Promise((resolve) => { done = resolve; });
    const frame = () => {
      if (!this.running) { $('lab-run').disabled = false; done(false); return; }
      const t0 = performance.now();
      try {
        while (this.test.time() < end - 1e-9 && performance.now() - t0 < this.frameBudget) {
          this.readings.push(...JSON.parse(this.test.advance(Math.min(EVERY, end - this.test.time()), EVERY)));
        }
      } catch (e) {
        this.running = false;
        $('lab-status').textContent = `The test stopped: ${e.message}`;
        done(false);
      }
      this.draw();
      if (this.running && this.test.time() >= end - 1e-9) {
        this.running = false;
        this.speed = end / ((performance.now() - started) / 1e3);
        this.finish();
        done(true);
      }
      if (this.running) requestAnimationFrame(frame);
      else $('lab-run').disabled = false;
    };
    requestAnimationFrame(frame);
    return ended;
  }

  finish() {
    const failure = JSON.parse(this.test.failure());
    if (!failure) return;
    this.runs.push({ test: this.kind, failure });
    for (const kind of ['shear_box', 'biaxial']) {
      const mine = this.runs.filter((r) => r.test === kind).map((r) => r.failure);
      this.fits[kind] = mine.length >= 2
        ? JSON.parse(fitEnvelope(kind === 'shear_box' ? 'points' : 'circles', new Float64Array(mine.flat())))
        : null;
    }
    const [a, b] = failure;
    $('lab-status').textContent = (this.kind === 'shear_box'
      ? `τ = ${kPa(b)} kPa at σ_n = ${kPa(a)} kPa on the shear plane (the mean over the last quarter of the travel)`
      : `Failure circle σ1 = ${kPa(a)} kPa, σ3 = ${kPa(b)} kPa`)
      + ` (${this.speed.toFixed(2)}× real time).`;
    this.draw();
  }

  draw() {
    if (this.root.hidden) return;
    this.drawSample();
    const r = this.readings;
    if (this.kind === 'biaxial') {
      linePlot($('lab-plot1'), r.map((q) => ({ x: q.axial_strain, y: q.deviator })), 'axial strain ε_a (%)', 'q = σ1 − σ3 (kPa)', pct, kPa);
      linePlot($('lab-plot2'), r.map((q) => ({ x: q.axial_strain, y: q.volumetric_strain })), 'axial strain ε_a (%)', 'ε_v (%)', pct, pct);
    } else {
      linePlot($('lab-plot1'), r.map((q) => ({ x: q.displacement, y: q.shear_stress })), 'displacement δ (mm)', 'τ (kPa)', mm, kPa);
      linePlot($('lab-plot2'), r.map((q) => ({ x: q.displacement, y: q.lid_rise })), 'displacement δ (mm)', 'lid rise (mm)', mm, mm);
    }
    this.drawMohr();
    this.showFit();
  }

  drawSample() {
    const { ctx, w, h } = setup($('lab-view'));
    if (!this.test) return;
    const p = this.test.particles();
    const colours = ['#d9a441', '#6c7a89', '#9aa6b2', '#495057'];
    const s = Math.min(w, h) / 0.3; // both scenes' domains are 0.3 m wide
    for (let i = 0; i < p.length; i += 3) {
      ctx.fillStyle = colours[p[i + 2]] ?? '#333';
      ctx.fillRect(p[i] * s, h - p[i + 1] * s - 2, 2.5, 2.5);
    }
  }

  drawMohr() {
    const { ctx, w, h } = setup($('lab-mohr'));
    if (w < 80 || h < 60) return;
    const live = this.running && this.kind === 'biaxial' && this.readings.length
      ? [{ test: 'biaxial', failure: [this.readings.at(-1).sigma1, this.readings.at(-1).sigma3], live: true }] : [];
    const runs = [...this.runs, ...live];
    const sMax = Math.max(1e3, ...runs.map(({ test, failure: [a, b] }) => 1.15 * (test === 'biaxial' ? a : Math.max(a, b / 0.55))));
    const box = { x0: 56, y0: 8, x1: w - 10, y1: h - 34 };
    const s = Math.min((box.x1 - box.x0) / sMax, (box.y1 - box.y0) / (sMax * 0.6));
    axes(ctx, box, [0, (box.x1 - box.x0) / s], [0, (box.y1 - box.y0) / s], 'normal stress σ (kPa)', 'τ (kPa)', kPa, kPa);
    const X = (v) => box.x0 + v * s, Y = (t) => box.y1 - t * s;
    for (const r of runs) {
      if (r.test === 'biaxial') {
        const [s1, s3] = r.failure;
        ctx.strokeStyle = r.live ? '#91a7ff' : '#1c7ed6';
        ctx.lineWidth = 2;
        ctx.beginPath();
        ctx.arc(X((s1 + s3) / 2), Y(0), Math.max(0.5, ((s1 - s3) / 2) * s), Math.PI, 2 * Math.PI);
        ctx.stroke();
      } else {
        ctx.fillStyle = '#d81b8c';
        ctx.beginPath();
        ctx.arc(X(r.failure[0]), Y(r.failure[1]), 4, 0, 2 * Math.PI);
        ctx.fill();
      }
    }
    const colour = { shear_box: '#d81b8c', biaxial: '#1c7ed6' };
    for (const kind of ['shear_box', 'biaxial']) {
      const f = this.fits[kind];
      if (!f) continue;
      const t = Math.tan((f.friction_angle * Math.PI) / 180);
      const end = (box.x1 - box.x0) / s;
      ctx.strokeStyle = colour[kind];
      ctx.setLineDash([6, 4]);
      ctx.beginPath();
      ctx.moveTo(X(0), Y(f.cohesion));
      ctx.lineTo(X(end), Y(f.cohesion + t * end));
      ctx.stroke();
      ctx.setLineDash([]);
    }
  }

  showFit() {
    const m = this.material();
    const n = { shear_box: 0, biaxial: 0 };
    for (const r of this.runs) n[r.test] += 1;
    const row = (kind, label) => {
      const f = this.fits[kind];
      return f
        ? `${label} (${n[kind]} runs): φ read ${f.friction_angle.toFixed(1)}°, c read ${kPa(f.cohesion)} kPa`
        : `${label}: ${n[kind]} run${n[kind] === 1 ? '' : 's'} (two at different loads fit an envelope)`;
    };
    $('lab-fit').textContent = `Sliders: φ ${m.phi}°, ψ ${m.psi}°, c ${kPa(m.c)} kPa. `
      + `${row('shear_box', 'Shear box')}. ${row('biaxial', 'Biaxial test')}.`;
    // once a lesson's verdict says why (angle_difference), it is said there only
    const said = this.lessonRun?.answer?.why;
    $('lab-why').textContent = !said && (this.fits.shear_box || this.fits.biaxial) ? whyDifferent(m, this.fits) : '';
  }
}
