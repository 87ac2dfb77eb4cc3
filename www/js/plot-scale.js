// The scales of the teaching plots (pure, tested under `node --test`): round tick values, the
// window of the energy plot, and the window of the p–q plot with the yield surface the solver
// reports (`StressPoint.surface` of the wasm API: q = slope · p + intercept from apex_p).

/// Round tick values covering [lo, hi], about `n` of them (steps of 1, 2 or 5 × 10^k).
export function ticks(lo, hi, n = 4) {
  // a range of round-off width (an empty plot's) is read as none: ticks a unit apart
  const span = Math.abs(hi - lo) > 1e-12 ? hi - lo : 1;
  const raw = span / n;
  const p = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 5, 10].map((m) => m * p).find((s) => s >= raw);
  const out = [];
  for (let t = Math.ceil(lo / step) * step; t <= hi + 1e-9 * span; t += step) out.push(Number(t.toPrecision(12)));
  return out;
}

/// The time range of `samples` [{time, …}] and a value range holding every series `keys`
/// and zero, padded by 5 %.
export function energyWindow(samples, keys) {
  const xr = [samples[0].time, samples[samples.length - 1].time];
  let lo = 0, hi = 0;
  for (const s of samples) for (const k of keys) { lo = Math.min(lo, s[k]); hi = Math.max(hi, s[k]); }
  const pad = 0.05 * (hi - lo || 1);
  return { xr, yr: [lo - pad, hi + pad] };
}

/// The window of a stress path `path` [[p, q], …] (Pa) against yield surface `surface`: in kPa
/// (`k` = 1e-3) unless every stress is below 1 kPa, p from the lowest pressure (or the cone's
/// apex, within a quarter of the largest p) to 15 % past the largest, q from 0 to 15 % past
/// the largest q or the surface there.
export function pqWindow(path, surface) {
  let big = Math.abs(surface.intercept) >= 1e3;
  for (const [p, q] of path) big ||= Math.max(Math.abs(p), q) >= 1e3;
  const k = big ? 1e-3 : 1;
  let pMax = 0, qMax = 0, pMin = 0;
  for (const [p, q] of path) { pMax = Math.max(pMax, p * k); pMin = Math.min(pMin, p * k); qMax = Math.max(qMax, q * k); }
  if (surface.kind !== 'none') qMax = Math.max(qMax, (surface.slope * pMax + surface.intercept * k));
  if (hasApex(surface)) pMin = Math.min(pMin, Math.max(surface.apex_p * k, -0.25 * (pMax || 1)));
  return {
    k,
    unit: big ? 'kPa' : 'Pa',
    pMin: pMin < 0 ? pMin * 1.15 : 0,
    pMax: Math.max(pMax * 1.15, big ? 0.1 : 10),
    qMax: Math.max(qMax * 1.15, big ? 0.1 : 10),
  };
}

/// Whether a surface closes at an apex (a cone or pyramid; `apex_p` is −1e300 without one).
const hasApex = (surface) => surface.kind !== 'none' && surface.apex_p > -1e299;

/// The drawn part of the yield surface in window `w` (scaled units): from the apex (or the
/// window's left edge) to its right edge, as [[p0, q0], [p1, q1]]; null without a surface.
/// `inner`: its inner meridian (`surface.lower`, [slope, intercept], of a surface whose
/// meridian depends on the Lode angle), null if it has none.
export function surfaceLine(surface, w, inner = false) {
  if (surface.kind === 'none' || (inner && !surface.lower)) return null;
  const [slope, intercept] = inner ? surface.lower : [surface.slope, surface.intercept];
  const p0 = hasApex(surface) ? Math.max(w.pMin, surface.apex_p * w.k) : w.pMin;
  const q = (p) => slope * p + intercept * w.k;
  return [[p0, Math.max(0, q(p0))], [w.pMax, q(w.pMax)]];
}
