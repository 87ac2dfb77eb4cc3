// Lessons: guided experiments of `lessons/*.json` (listed by the build in
// www/pkg/lessons.json; the format is docs/lessons.md). Opening one loads its scene, validated
// with the lesson by the solver (errors name the field), sets its view (colours, plot, the
// particle to inspect) and shows its title, caption and the one to three sliders it asks to
// move in a small panel above the view, which can be closed. A lesson opens from the Lessons
// menu or a link (`#lesson=friction_angle`). The sliders' specs are pure (tested under
// `node --test`).

import { banner } from './hud.js';
import { fetchText } from './scenes.js';
import { el, paramSlider } from './widgets.js';
import { answerIndex, questionValue, quantityUnit } from './measure-view.js';

const $ = (id) => document.getElementById(id);

/// [{id, path, title}] of every lesson, in file-name order (none if the list is missing).
export async function loadLessonList() {
  try {
    const r = await fetch('www/pkg/lessons.json', { cache: 'no-cache' });
    return r.ok ? await r.json() : [];
  } catch {
    return [];
  }
}

/// A material parameter of one body, `bodies[i].<model>.<field>`: {body, name}, else null.
export function bodyParam(name) {
  const m = /^bodies\[(\d+)\]\.([a-z_]+\.[a-z_]+)$/.exec(name);
  return m ? { body: Number(m[1]), name: m[2] } : null;
}

/// The slider spec of parameter `name` of a lesson (one of the table's names, or a parameter
/// of one body: then labelled with the body's name in `scene`), or null if there is none.
export function lessonSpec(name, table, scene) {
  const one = bodyParam(name);
  const spec = table.spec(one ? one.name : name);
  if (!spec) return null;
  if (!one) return { ...spec };
  const body = scene.bodies[one.body];
  return { ...spec, name, model: undefined, label: `${spec.label}: ${body?.name || `body ${one.body + 1}`}` };
}

/// The lesson `id` of `list` with its scene: {lesson, source: {text, assets}}; its files are
/// fetched relative to the lesson file (or to its scene file), and the solver validates it.
/// Throws a message naming the file or the field.
export async function fetchLesson(id, list, session) {
  const entry = list.find((l) => l.id === id);
  if (!entry) throw new Error(`no lesson “${id}”${list.length ? ` (there are ${list.map((l) => l.id).join(', ')})` : ''}`);
  const url = new URL(entry.path, location.href);
  const text = await fetchText(url.href);
  let lesson;
  try {
    lesson = JSON.parse(text);
  } catch (e) {
    throw new Error(`${entry.path}: not JSON (${e.message})`);
  }
  let sceneFile = null, base = url;
  if (typeof lesson.scene === 'string') {
    base = new URL(lesson.scene, url);
    sceneFile = await fetchText(base.href);
  }
  const sceneText = sceneFile ?? JSON.stringify(lesson.scene ?? null);
  let paths = [];
  try {
    paths = await session.assetPaths(sceneText);
  } catch {
    // An invalid scene: the lesson's check names the field.
  }
  const texts = await Promise.all(paths.map((p) => fetchText(new URL(p, base).href)));
  const assets = paths.length ? JSON.stringify(Object.fromEntries(paths.map((p, i) => [p, texts[i]]))) : null;
  // a soil-lab lesson's compared test (lab.compare): its scene file, relative to the lesson's,
  // checked with it (keyed as written) and run by the Lab after the scene's runs
  const compare = typeof lesson.lab?.compare === 'string' ? lesson.lab.compare : null;
  const compareScene = compare ? await fetchText(new URL(compare, url).href) : null;
  const checked = compare ? JSON.stringify({ ...JSON.parse(assets ?? '{}'), [compare]: compareScene }) : assets;
  try {
    await session.checkLesson(text, sceneFile, checked);
  } catch (e) {
    throw new Error(`${entry.path}: ${e.message}`);
  }
  return { lesson: { id, ...lesson, ...(compare ? { compareScene } : {}) }, source: { text: sceneText, assets } };
}

/// The lesson panel above the view: title, caption, the lesson's sliders; closing hides it.
export class LessonPanel {
  constructor(app) {
    this.app = app;
    this.sliders = new Map();
    this.root = $('lesson');
    $('lesson-close').addEventListener('click', () => this.hide());
  }

  /// Shows `lesson` (of the scene just loaded) and marks its sliders in the controls.
  async show(lesson) {
    const app = this.app;
    this.lesson = lesson;
    $('lesson-title').textContent = lesson.title;
    $('lesson-caption').textContent = lesson.caption;
    this.sliders.clear();
    // a soil-lab lesson's runs take their parameters from its file: no slider here moves them
    const names = lesson.lab ? [] : lesson.view?.params ?? [];
    const rows = [];
    for (const name of names) {
      const spec = lessonSpec(name, app.session.table, app.session.scene);
      if (!spec) continue;
      const w = paramSlider(spec, (v) => app.applyParam(name, v));
      this.sliders.set(name, w);
      rows.push(w.root);
    }
    $('lesson-params').replaceChildren(...rows);
    // a soil-lab lesson asks and answers in the Lab panel, from its runs
    this.ask(lesson.lab ? null : lesson.question);
    for (const e of document.querySelectorAll('.param.lesson-param')) e.classList.remove('lesson-param');
    this.root.hidden = false;
    this.root.classList.remove('folded');
    banner('lesson');
    await this.sync();
  }

  /// Shows the lesson's question (if any) before the run: the simulation waits paused for
  /// Play; a choice is the student's prediction. After the lesson's duration the page's own
  /// measure answers it (`measured`).
  ask(question) {
    const box = $('lesson-question');
    this.question = question ?? null;
    this.picked = -1;
    this.answer = null;
    if (!question) {
      box.hidden = true;
      box.replaceChildren();
      return;
    }
    this.app.setPlaying(false);
    const buttons = question.choices.map((c, i) => el('button', {
      'data-choice': String(i), 'aria-pressed': 'false',
      onclick: () => {
        if (this.answer) return; // answered: the prediction stands
        this.picked = i;
        for (const b of buttons) b.setAttribute('aria-pressed', String(b === buttons[i]));
        verdict.textContent = 'Now press Play and watch.';
      },
    }, c.text));
    const verdict = el('div', { class: 'verdict', id: 'lesson-verdict' }, 'Predict first: pick an answer, then press Play.');
    box.replaceChildren(el('div', { class: 'ask' }, question.ask), el('div', { class: 'choices' }, ...buttons), verdict);
    box.hidden = false;
    this.verdict = verdict;
    this.buttons = buttons;
  }

  /// A frame was shown: once the lesson's duration has run, its question is answered with
  /// the frame's measures (the readouts on the view).
  measured(f) {
    const q = this.question;
    if (!q || this.answer || !this.lesson || f.time < this.lesson.duration) return;
    const dim = this.app.domain.length;
    const value = questionValue(q, f.measures ?? [], dim);
    const i = answerIndex(q, value);
    if (value === null) return;
    this.answer = { value, index: i, time: f.time };
    const unit = quantityUnit(q.measure.quantity);
    const shown = unit === '°' ? `${value.toFixed(1)}°` : `${value.toFixed(2)} ${unit}`;
    if (i >= 0) this.buttons[i].classList.add('answer');
    const what = q.measure.bodies.length === 2 ? 'the difference measured on the view' : 'measured on the view';
    const mine = this.picked < 0 ? '' : this.picked === i ? ' Your prediction was right.' : ` You predicted “${q.choices[this.picked].text}”.`;
    this.verdict.textContent = `At t = ${f.time.toFixed(2)} s, ${what}: ${shown}${i >= 0 ? ` → “${q.choices[i].text}”.` : ' (outside every choice).'}${mine}`;
  }

  /// The sliders' values from the solver (after a load, a reset or a change elsewhere), and
  /// the mark on the same sliders in the controls.
  async sync() {
    if (!this.lesson || !this.sliders.size) return;
    const names = [...this.sliders.keys()];
    const values = await this.app.session.values(names);
    names.forEach((n, i) => { if (values[i] !== null) this.sliders.get(n)?.set(values[i]); });
    this.mark();
  }

  /// Marks the lesson's sliders among the controls (those of the material shown).
  mark() {
    for (const n of this.sliders.keys()) this.app.sliders.get(n)?.root.classList.add('lesson-param');
  }

  /// Parameter `name` was set to `value` (here or in the controls).
  changed(name, value) {
    this.sliders.get(name)?.set(value);
  }

  hide() {
    this.root.hidden = true;
  }

  /// The lesson is left (another scene): no panel, no marks.
  close() {
    this.lesson = null;
    this.ask(null);
    this.sliders.clear();
    this.hide();
    for (const e of document.querySelectorAll('.param.lesson-param')) e.classList.remove('lesson-param');
  }
}

/// The Lessons menu: every lesson of `list`; picking one opens it.
export function buildLessonMenu(app, list) {
  const select = $('lessons');
  select.replaceChildren(el('option', { value: '' }, list.length ? 'Lessons…' : 'No lessons'),
    ...list.map((l) => el('option', { value: l.id }, l.title)));
  select.disabled = !list.length;
  select.addEventListener('change', () => {
    const id = select.value;
    select.value = '';
    if (id) app.openLesson(id);
  });
}
