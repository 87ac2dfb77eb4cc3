// The live parameters the page offers: labels, units and slider ranges. The names are those
// of the wasm API (`gravity`, `wall_friction`, `cfl`, `<model>.<field>`); the values are
// validated in Rust exactly like scene files, so the slider ranges here are only what the
// sliders offer, not what is allowed (a typed value outside them gets the scene-file check).

export const MODELS = [
  { id: 'elastic', label: 'Elastic', hint: 'jelly: bounces back' },
  { id: 'von_mises', label: 'Plastic', hint: 'clay/metal: von Mises' },
  { id: 'drucker_prager', label: 'Sand', hint: 'granular: Drucker–Prager' },
];

export const OBJECTS = [
  { id: 'bunny', label: 'Bunny' },
  { id: 'ball', label: 'Ball' },
  { id: 'box', label: 'Box' },
];

// scale: 'lin' or 'log'; unit shown after the value.
const FIELDS = {
  youngs_modulus: { label: "Young's modulus", symbol: 'E', unit: 'Pa', min: 1e3, max: 1e8, scale: 'log' },
  poisson_ratio: { label: 'Poisson ratio', symbol: 'ν', unit: '', min: 0, max: 0.49, step: 0.01 },
  density: { label: 'Density', symbol: 'ρ', unit: 'kg/m³', min: 100, max: 8000, scale: 'log' },
  yield_stress: { label: 'Yield stress', symbol: 'σ_y', unit: 'Pa', min: 1e2, max: 1e6, scale: 'log' },
  friction_angle: { label: 'Friction angle', symbol: 'φ', unit: '°', min: 0, max: 60, step: 0.5 },
  dilatancy_angle: { label: 'Dilatancy angle', symbol: 'ψ', unit: '°', min: 0, max: 60, step: 0.5, maxFrom: 'friction_angle' },
  cohesion: { label: 'Cohesion', symbol: 'c', unit: 'Pa', min: 0, max: 5000, step: 10 },
  flip: { label: 'FLIP ratio', symbol: 'α', unit: '', min: 0, max: 1, step: 0.01, hint: '0 = PIC (damped), 1 = FLIP (lively, noisy)' },
};

export const MODEL_FIELDS = {
  elastic: ['youngs_modulus', 'poisson_ratio', 'density', 'flip'],
  von_mises: ['yield_stress', 'youngs_modulus', 'poisson_ratio', 'density', 'flip'],
  drucker_prager: ['friction_angle', 'dilatancy_angle', 'cohesion', 'youngs_modulus', 'poisson_ratio', 'density', 'flip'],
};

export const WORLD = [
  { name: 'gravity', label: 'Gravity', symbol: 'g', unit: 'm/s²', min: 0, max: 30, step: 0.01 },
  { name: 'wall_friction', label: 'Wall friction', symbol: 'μ', unit: '', min: 0, max: 1.5, step: 0.01 },
  { name: 'cfl', label: 'CFL number', symbol: 'C', unit: '', min: 0.05, max: 1, step: 0.01, hint: 'time step = C · h / (wave speed + |v|max)' },
];

/// The spec of parameter `name`.
export function spec(name) {
  const world = WORLD.find((p) => p.name === name);
  if (world) return world;
  const [model, field] = name.split('.');
  return { ...FIELDS[field], name, model, field };
}

export function materialParams(model) {
  return MODEL_FIELDS[model].map((f) => spec(`${model}.${f}`));
}

// Slider positions are integers in [0, ticks(s)]: one tick per step on a linear scale, 200
// ticks on a log scale (values rounded to three significant figures), so that every tick
// (and every arrow key press) changes the value.
export function ticks(s) {
  if (s.scale === 'log') return 200;
  return Math.max(1, Math.round((s.max - s.min) / (s.step || 0.01)));
}

export function toSlider(s, v) {
  const n = ticks(s);
  if (s.scale === 'log') return (n * Math.log(Math.max(v, s.min) / s.min)) / Math.log(s.max / s.min);
  return (n * (v - s.min)) / (s.max - s.min);
}

export function fromSlider(s, pos) {
  const t = Math.min(1, Math.max(0, pos / ticks(s)));
  if (s.scale === 'log') return Number((s.min * (s.max / s.min) ** t).toPrecision(3));
  const step = s.step || 0.01;
  return Number((s.min + Math.round((t * (s.max - s.min)) / step) * step).toFixed(6));
}

/// A value with SI prefixes for Pa, plain otherwise.
export function format(v, unit = '') {
  if (!Number.isFinite(v)) return String(v);
  if (unit === 'Pa') {
    const a = Math.abs(v);
    const [d, p] = a >= 1e9 ? [1e9, 'G'] : a >= 1e6 ? [1e6, 'M'] : a >= 1e3 ? [1e3, 'k'] : [1, ''];
    return `${+(v / d).toPrecision(3)} ${p}Pa`;
  }
  const s = Math.abs(v) >= 100 ? v.toFixed(0) : +v.toPrecision(3);
  return unit ? `${s} ${unit}` : `${s}`;
}

/// A duration in s, ms or µs.
export function formatTime(t) {
  if (!Number.isFinite(t)) return '–';
  if (t >= 1) return `${t.toFixed(2)} s`;
  if (t >= 1e-3) return `${(t * 1e3).toPrecision(3)} ms`;
  return `${(t * 1e6).toPrecision(3)} µs`;
}
