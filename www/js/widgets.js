// Small DOM helpers: parameter sliders (with a typed-value box) and segmented buttons.

import { format, fromSlider, ticks, toSlider } from './params.js';

export function el(tag, attrs = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === 'class') e.className = v;
    else if (k.startsWith('on')) e.addEventListener(k.slice(2), v);
    else e.setAttribute(k, v);
  }
  for (const c of children) e.append(c);
  return e;
}

/// A slider for parameter `spec` ({name, label, symbol, unit, min, max, scale, step, help}).
/// `apply(value)` sets it and returns (or resolves to) an error message, or '' on success.
export function paramSlider(spec, apply) {
  const range = el('input', {
    type: 'range', min: '0', max: String(ticks(spec)), step: '1',
    'data-param': spec.name, 'aria-label': `${spec.label} (${spec.unit || 'no unit'})`,
  });
  const box = el('input', { type: 'text', inputmode: 'decimal', 'data-param-value': spec.name, 'aria-label': `${spec.label} value` });
  const error = el('div', { class: 'error', role: 'status' });
  const shown = (v) => (spec.unit === 'Pa' ? format(v, 'Pa').replace(/ ?[kMG]?Pa$/, '') : format(v));
  const unitOf = (v) => (spec.unit === 'Pa' ? format(v, 'Pa').replace(/^[-\d.e+]+ ?/, '') : spec.unit);
  const unit = el('span', { class: 'unit' });
  const lo = el('span', {}, format(spec.min, spec.unit));
  const hi = el('span', {}, format(spec.max, spec.unit));
  const root = el('div', { class: 'param', title: spec.help || '' },
    el('div', { class: 'row' },
      el('span', { class: 'name' }, el('span', { class: 'sym' }, spec.symbol || ''), spec.label),
      box, unit),
    range,
    el('div', { class: 'ends' }, lo, hi),
    error);
  let value = NaN;
  const show = (v) => {
    value = v;
    box.value = shown(v);
    unit.textContent = unitOf(v);
    range.max = String(ticks(spec));
    range.value = String(Math.round(toSlider(spec, v)));
  };
  const attempt = async (v) => {
    const msg = await apply(v);
    error.textContent = msg || '';
    if (!msg) show(v);
    return !msg;
  };
  range.addEventListener('input', () => {
    const v = fromSlider(spec, Number(range.value));
    box.value = shown(v);
    unit.textContent = unitOf(v);
    attempt(v);
  });
  range.addEventListener('change', () => show(value));
  const commit = async () => {
    const text = box.value.trim().replace(',', '.');
    const m = text.match(/^([-+]?[\d.]*(?:e[-+]?\d+)?)\s*([kMG]?)(?:Pa)?$/i);
    let v = m && m[1] !== '' ? Number(m[1]) : Number.NaN;
    if (spec.unit === 'Pa' && m) {
      // A bare number is in the unit shown beside the box; k, M, G and Pa may be typed.
      const prefix = m[2].toLowerCase();
      const explicit = prefix || /pa$/i.test(text);
      v *= explicit ? { '': 1, k: 1e3, m: 1e6, g: 1e9 }[prefix] : { Pa: 1, kPa: 1e3, MPa: 1e6, GPa: 1e9 }[unitOf(value)] || 1;
    }
    if (!(await attempt(v))) box.select();
  };
  box.addEventListener('keydown', (e) => { if (e.key === 'Enter') commit(); if (e.key === 'Escape') show(value); });
  box.addEventListener('change', commit);
  return {
    root,
    set: (v) => { show(v); error.textContent = ''; },
    setError: (msg) => { error.textContent = msg; },
    setMax: (m) => { spec.max = m; hi.textContent = format(m, spec.unit); show(value); },
  };
}

/// Segmented buttons: `items` [{id, label, hint}], `onPick(id)`.
export function segmented(container, items, onPick) {
  container.replaceChildren(...items.map((it) => el('button', {
    'data-id': it.id, title: it.hint || it.label, 'aria-pressed': 'false', onclick: () => onPick(it.id),
  }, it.label)));
  return (id) => {
    for (const b of container.children) b.setAttribute('aria-pressed', String(b.dataset.id === id));
  };
}
