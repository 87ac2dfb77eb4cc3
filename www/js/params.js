// The live parameters as the page shows them. Their names, labels, symbols, units, slider
// ranges, defaults and help texts come from the solver's parameter table (`parameterTable()`
// of the wasm module, `src/params.rs`); the values are validated in Rust exactly like scene
// files, so a slider's range is only what it offers, not what is allowed. Here: looking the
// table up, slider scaling and number formatting (pure, tested under `node --test`).

/// The table of `parameterTable()` (JSON text or parsed) with lookups: `params` in display
/// order, `world` (the world's), `models` [{id, label, hint}], `objects` [{id, label}].
export function paramTable(json) {
  const t = typeof json === 'string' ? JSON.parse(json) : json;
  const byName = new Map(t.params.map((p) => [p.name, p]));
  return {
    params: t.params,
    models: t.models,
    objects: t.objects,
    world: t.params.filter((p) => !p.model),
    names: t.params.map((p) => p.name),
    /// The spec of parameter `name`; undefined if there is none.
    spec: (name) => byName.get(name),
    /// The parameters of material model `model`, in display order.
    ofModel: (model) => t.params.filter((p) => p.model === model),
  };
}

/// The upper bound of a parameter whose range depends on another (ψ ≤ φ): `values` holds the
/// current values by name. Returns the slider maximum to show.
export function boundedMax(spec, values) {
  if (!spec.at_most) return spec.max;
  const bound = values[`${spec.model}.${spec.at_most}`];
  return bound === undefined ? spec.max : Math.max(0.5, bound);
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
