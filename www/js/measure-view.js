// What the page makes of the core's measures (pure, tested under `node --test`): the class's
// words for the real-time factor and the quality's accuracy, whether a heap stands at its
// angle of repose or collapsed, the numbers a lesson's question is answered with, the Mohr
// circles of a stress, and the angles of the readouts' arcs. The measures themselves are the
// core's (`mpm::measure`, through the worker's frames).

/// A signed percentage: +1.2 %, −14 %.
export function pct(x) {
  return `${x > 0 ? '+' : x < 0 ? '−' : ''}${(100 * Math.abs(x)).toPrecision(2)} %`;
}

/// The real-time factor `ratio` (simulated per real time) in words: how the simulated time
/// runs against the clock. Within 5 % below and 10 % above 1 it is real time; below, slow
/// motion, the figure said ("1 s takes 1.1 s") always above 1; above, faster than real time.
/// (Whether the steps fell behind their budget does not change the words: the ratio says it.)
export function speedWords(ratio, playing) {
  if (!playing) return 'paused';
  if (!(ratio > 0)) return 'starting';
  if (ratio > 1.1) return `faster than real time (${ratio.toFixed(1)}×)`;
  if (ratio >= 0.95) return 'real time';
  return `slow motion: 1 s takes ${(1 / ratio).toPrecision(2)} s`;
}

/// What the quality level costs, in a sentence: the column test's errors against the
/// experiments at this resolution (docs/playground.md): in 2D the plane column's (`a`, the
/// resolution's `accuracy`), in 3D the level's 3D sand figures (`sand`, the resolution's
/// `sand`: the shipped 3D column's run-out where its deposit is one grain thick against Lube
/// et al. (2004), and its flank).
export function accuracyNote(label, a, sand = null) {
  if (sand) return `${label}: 3D column run-out ${pct(sand.runout)} against experiments, flank ${sand.flank.toFixed(1)}°`;
  return `${label}: column run-out ${pct(a.column_runout)}, height ${pct(a.column_height)} against experiments`;
}

/// A deposit's flank angle: the mean of its fitted flanks (degrees), or null.
export function flankAngle(d) {
  const f = d.heap.flanks.filter(Boolean).map((x) => x.angle);
  return f.length ? f.reduce((a, b) => a + b, 0) / f.length : null;
}

/// Whether a sand deposit is a heap its angle of repose bounds: poured from a spout, released
/// by the walls lifted from around it, or built as a heap at rest, whose flanks stand at any
/// slope up to that angle (the core's `poured`, `held` and `heaped`). Any other (a body
/// dropped, a column released at once) is a collapse: its momentum spreads it below that
/// angle, and its run-out hardly depends on the friction angle (Lube et al. 2005).
export function atRepose(d) {
  return !!(d.poured || d.held || d.heaped);
}

/// A deposit's run-out beyond its footprint (m): the farther side in 2D, the mean over the
/// sectors in 3D; null without a footprint.
export function runout(d, dim) {
  if (!d.runout) return null;
  return dim === 2 ? Math.max(d.runout.runout[0], d.runout.runout[1]) : d.runout.runout[0];
}

/// The value of `quantity` for body `body` among `deposits`, or null.
export function quantityOf(quantity, body, deposits, dim) {
  const d = deposits.find((x) => x.body === body);
  if (!d) return null;
  if (quantity === 'flank_angle') return flankAngle(d);
  const r = runout(d, dim);
  if (r === null) return null;
  // L0 as the experiments take it (a column against a wall is half of a symmetric one)
  return quantity === 'runout_ratio' ? r / (d.column?.column.half_width ?? d.runout.footprint) : r;
}

/// The measured answer to a lesson's question: the first body's quantity, less the second's
/// when two are named; null when one cannot be measured.
export function questionValue(question, deposits, dim) {
  const [a, b] = question.measure.bodies.map((i) => quantityOf(question.measure.quantity, i, deposits, dim));
  if (a === null || a === undefined || (question.measure.bodies.length === 2 && (b === null || b === undefined))) return null;
  return question.measure.bodies.length === 2 ? a - b : a;
}

/// The choice whose range [low, high) holds `value` (the last one's high end included), or -1.
export function answerIndex(question, value) {
  if (value === null || !Number.isFinite(value)) return -1;
  const n = question.choices.length;
  return question.choices.findIndex(({ range: [lo, hi] }, i) => value >= lo && (value < hi || (i === n - 1 && value <= hi)));
}

/// The unit a question's quantity is shown in.
export function quantityUnit(quantity) {
  return { flank_angle: '°', runout: 'm', runout_ratio: 'L0' }[quantity];
}

/// The Mohr circles of stress point `sp` (its principal stresses, compression positive):
/// in 3D the three principal circles, in 2D plane strain the in-plane circle (and the
/// out-of-plane stress as a point); each {centre, radius}. With a granular material, the
/// Mohr–Coulomb envelope τ = c + σ tan φ (a Mohr–Coulomb material's own yield surface) and,
/// for a Drucker–Prager cone (`plane_strain_angle` given), the cone's trace: in plane strain
/// the line at φ_ps; in 3D the circle the cone allows in triaxial compression at the
/// particle's pressure p (q = σ1 − σ3 on the cone, centre p + q/6).
export function mohr(sp, dim) {
  const s = sp.principal;
  const circle = (a, b) => ({ centre: (a + b) / 2, radius: Math.abs(a - b) / 2 });
  const circles = dim === 2 ? [circle(s[0], s[1])] : [circle(s[0], s[2]), circle(s[0], s[1]), circle(s[1], s[2])];
  const out = { circles, points: dim === 2 ? [s[2]] : [], envelope: null, cone: null };
  const mc = sp.mohr_coulomb;
  if (mc) {
    out.envelope = { angle: mc.friction_angle, cohesion: mc.cohesion, own: mc.plane_strain_angle === undefined };
    if (out.envelope.own) {
      // Mohr–Coulomb: the envelope is the yield surface, there is no cone
    } else if (dim === 2) {
      // c' of the plane-strain match: the cone's circles touch a line at φ_ps through the
      // apex of the Mohr–Coulomb line at φ (σ = −c / tan φ)
      const t = Math.tan((mc.friction_angle * Math.PI) / 180);
      const apex = t > 0 ? -mc.cohesion / t : 0;
      const tps = Math.tan((mc.plane_strain_angle * Math.PI) / 180);
      out.cone = { kind: 'line', angle: mc.plane_strain_angle, cohesion: -apex * tps };
    } else {
      const { slope, intercept } = sp.surface;
      const q = Math.max(0, slope * sp.p + intercept);
      out.cone = { kind: 'circle', centre: sp.p + q / 6, radius: q / 2 };
    }
  }
  return out;
}

/// The window of a Mohr plot: σ from the least to the largest principal stress (and zero),
/// padded; τ from 0 up to the largest circle, at the same scale as σ where the box allows.
export function mohrWindow(m) {
  let lo = 0, hi = 0;
  for (const c of m.circles) { lo = Math.min(lo, c.centre - c.radius); hi = Math.max(hi, c.centre + c.radius); }
  if (m.cone?.kind === 'circle') hi = Math.max(hi, m.cone.centre + m.cone.radius);
  for (const p of m.points) { lo = Math.min(lo, p); hi = Math.max(hi, p); }
  const span = hi - lo || 1;
  return { sMin: lo - 0.08 * span, sMax: hi + 0.08 * span, tMax: 0.6 * (span * 1.16) };
}

/// The screen angles (radians, canvas convention: y down) of a flank's arc at its foot: from
/// the horizontal pointing away from the heap to the flank rising towards its top. `foot` and
/// `top` are screen points [x, y].
export function arcAngles(foot, top) {
  const along = Math.atan2(top[1] - foot[1], top[0] - foot[0]);
  const horizontal = top[0] >= foot[0] ? 0 : Math.PI;
  // the short way round
  let a0 = horizontal, a1 = along;
  let d = a1 - a0;
  while (d > Math.PI) d -= 2 * Math.PI;
  while (d < -Math.PI) d += 2 * Math.PI;
  return d < 0 ? [a0 + d, a0] : [a0, a0 + d];
}
