// Colour maps shared by the renderers and the legend.

/// The legend's names of `bodies` (each `{name}`): its name, or `body N` without one; a
/// name already used gets its count (`bunny`, `bunny 2`), so that no two entries read alike.
export function bodyNames(bodies) {
  const seen = new Map();
  return bodies.map((b, i) => {
    const name = b.name || `body ${i + 1}`;
    const n = (seen.get(name) ?? 0) + 1;
    seen.set(name, n);
    return n === 1 ? name : `${name} ${n}`;
  });
}

/// Categorical colours of bodies (by index, repeating).
export const BODY_COLOURS = [
  [0.89, 0.64, 0.27], // sand
  [0.27, 0.53, 0.84], // blue
  [0.85, 0.33, 0.31], // red
  [0.36, 0.70, 0.40], // green
  [0.61, 0.40, 0.74], // purple
  [0.95, 0.77, 0.10], // yellow
  [0.10, 0.69, 0.62], // teal
  [0.55, 0.55, 0.58], // grey
];

/// Sleeping particles (colour mode `sleeping`; awake ones take their body's colour).
export const SLEEP_COLOUR = [0.40, 0.43, 0.50];

/// Elastic, on the yield surface, flowing.
export const YIELD_COLOURS = [
  [0.55, 0.66, 0.80],
  [0.96, 0.71, 0.0],
  [0.86, 0.20, 0.16],
];
export const YIELD_LABELS = ['elastic', 'at yield', 'flowing'];

// Viridis, as a polynomial fit (the same in GLSL below).
const V = [
  [0.2777273272234177, 0.005407344544966578, 0.3340998053353061],
  [0.1050930431085774, 1.404613529898575, 1.384590162594685],
  [-0.3308618287255563, 0.214847559468213, 0.09509516302823659],
  [-4.634230498983486, -5.799100973351585, -19.33244095627987],
  [6.228269936347081, 14.17993336680509, 56.69055260068105],
  [4.776384997670288, -13.74514537774601, -65.35303263337234],
  [-5.435455855934631, 4.645852612178535, 26.3124352495832],
];

export function viridis(t) {
  t = Math.min(1, Math.max(0, t));
  const out = [0, 0, 0];
  for (let c = 0; c < 3; c++) {
    let s = V[6][c];
    for (let k = 5; k >= 0; k--) s = V[k][c] + t * s;
    out[c] = Math.min(1, Math.max(0, s));
  }
  return out;
}

export const VIRIDIS_GLSL = `
vec3 viridis(float t) {
  t = clamp(t, 0.0, 1.0);
  const vec3 c0 = vec3(${V[0].join(', ')});
  const vec3 c1 = vec3(${V[1].join(', ')});
  const vec3 c2 = vec3(${V[2].join(', ')});
  const vec3 c3 = vec3(${V[3].join(', ')});
  const vec3 c4 = vec3(${V[4].join(', ')});
  const vec3 c5 = vec3(${V[5].join(', ')});
  const vec3 c6 = vec3(${V[6].join(', ')});
  return clamp(c0 + t * (c1 + t * (c2 + t * (c3 + t * (c4 + t * (c5 + t * c6))))), 0.0, 1.0);
}`;

/// The colour of scalar `v` in colour mode `mode` over `range` (CPU side, for the fallback
/// renderer and the legend).
export function colourOf(mode, v, range) {
  if (mode === 'body') return BODY_COLOURS[Math.round(v) % BODY_COLOURS.length];
  if (mode === 'sleeping') return v < 0 ? SLEEP_COLOUR : BODY_COLOURS[Math.round(v) % BODY_COLOURS.length];
  if (mode === 'yield') return YIELD_COLOURS[Math.min(2, Math.max(0, Math.round(v * 2)))];
  return viridis((v - range[0]) / Math.max(1e-30, range[1] - range[0]));
}

export function css(rgb, alpha = 1) {
  const [r, g, b] = rgb.map((c) => Math.round(c * 255));
  return alpha === 1 ? `rgb(${r},${g},${b})` : `rgba(${r},${g},${b},${alpha})`;
}
