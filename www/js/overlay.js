// The measuring overlay, drawn on a transparent canvas over the view (it takes no pointer
// events): for each sand body the angle of its flanks (the core's least-squares fit, drawn as
// the fitted line with an arc and its value; in 3D on the radial profile, in the vertical
// plane through the heap's axis that faces the view), its run-out from its initial footprint as a ruler
// on the floor, and where the experiments apply the published laws as floor markers naming
// their source (a column's run-out and final height, Lube et al.; against a heap poured or
// released by lifted walls, the line at the sand's angle of repose, the steepest slope on which
// its flowing layer stops: φ_ps of the cone, Davis's angle of Mohr–Coulomb (and against a heap
// built at rest, which stands at any slope up to it); against any other
// 2D deposit, a collapse, a note that its momentum spread it below that angle); and the hand
// tool's line with what the core reads of
// it. Every number drawn is the core's (`mpm::measure`, `mpm::laws`).

import { arcAngles, atRepose } from './measure-view.js';

/// The note on a collapse's deposit, longest first (the first that fits is written).
export const COLLAPSE_NOTE = [
  'a collapse: spread by its momentum, below the angle of repose — pour to measure it',
  'a collapse: spread below the angle of repose — pour to measure it',
  'a collapse: pour to measure the angle of repose',
];

const INK = '#0b5394';
const LAW = '#2b8a3e';
const HAND = '#d81b8c';

/// The name of a heap's angle-of-repose line: the angle, and whose it is (a Mohr–Coulomb
/// sand's is Davis's angle, below φ).
export function reposeLabel(d) {
  const whose = d.model === 'mohr_coulomb' ? 'Mohr–Coulomb (Davis)' : 'Drucker–Prager';
  return `angle of repose ${d.repose_angle.toFixed(1)}°, ${whose}`;
}

export class Overlay {
  constructor(canvas) {
    this.canvas = canvas;
    this.ctx = canvas.getContext('2d');
    this.labels = []; // what was drawn last, for tests: [{kind, text, x, y}]
    this.materialOf = () => null;
  }

  /// Draws `measures` (the frame's deposits) and `hand` ({a, b, reading} in world
  /// coordinates, or null) with `camera`; `show` {readouts, laws}. `particles` {positions,
  /// stride, count, radius} (as drawn; radius in m) are what the labels keep clear of.
  draw({ camera, dim, measures = [], hand = null, show = { readouts: true, laws: true }, particles = null }) {
    const c = this.canvas;
    const dpr = Math.min(2, window.devicePixelRatio || 1);
    const w = c.clientWidth, h = c.clientHeight;
    if (c.width !== Math.round(w * dpr) || c.height !== Math.round(h * dpr)) {
      c.width = Math.round(w * dpr);
      c.height = Math.round(h * dpr);
    }
    const ctx = this.ctx;
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.clearRect(0, 0, w, h);
    this.labels = [];
    // where the particles lie, built when the first label asks (a frame without labels costs
    // no projection of its particles)
    this.material = null;
    this.materialOf = particles && measures.length && show.readouts
      ? () => (this.material ??= occupancy(camera, dim, particles, w, h)) : () => null;
    const P = (x, y, z = 0) => camera.project(x, y, dim === 3 ? z : 0);
    // 3D: the radial profile (the mean over every azimuth) drawn in the vertical plane through
    // the heap's axis that faces the view, along the screen's right: on the heap's silhouette,
    // beside what rests on its top rather than over it
    const right = dim === 3 ? [Math.cos(camera.yaw), -Math.sin(camera.yaw)] : [1, 0];
    for (const d of measures) {
      const at = (r, y) => (dim === 3 ? P(d.axis[0] + r * right[0], y, d.axis[1] + r * right[1]) : P(r, y));
      if (show.laws && d.column) this.column(d, dim, P);
      if (show.readouts) {
        this.flanks(d, dim, at, show.laws);
        if (d.runout) this.ruler(d, dim, P, right);
      }
    }
    if (hand?.a && hand?.b) this.hand(hand, dim, P);
  }

  /// The width of `text` as a label writes it (CSS pixels).
  textWidth(text) {
    this.ctx.font = '600 13px system-ui, sans-serif';
    return this.ctx.measureText(text).width;
  }

  /// Writes `text` (or of a list, longest first, the first that fits the view's width) at `p`
  /// (aligned `align`), kept whole on the view, clear of the labels written before it and, where
  /// it can be, of the particles drawn: moved in from the edges, then up or down a line at a
  /// time (up to eight), then out sideways (away from what a left- or right-aligned label
  /// names), to the first place clear of both; failing that, the nearest clear of the labels
  /// (a run-out's figure is left out instead: its ruler stays), and where there is none (a
  /// crowded narrow view) it is left out. The readouts are written most telling first: the
  /// experiments' markers, the flanks and their line, then the rulers. A label moved off its
  /// point gets a thin leader line to it.
  label(kind, text, p, colour, align = 'left') {
    if (!p) return;
    const ctx = this.ctx;
    const W = this.canvas.clientWidth, Hc = this.canvas.clientHeight;
    if (Array.isArray(text)) text = text.find((t) => this.textWidth(t) + 8 <= W) ?? text[text.length - 1];
    const w = this.textWidth(text) + 4, h = 16;
    const at = (dx) => {
      const left = align === 'left' ? p[0] + dx : align === 'right' ? p[0] - w - dx : p[0] - w / 2;
      return Math.max(2, Math.min(W - w - 2, left));
    };
    const clear = (b) => b.y >= 0 && b.y + b.h <= Hc &&
      this.labels.every((l) => b.x >= l.box.x + l.box.w || l.box.x >= b.x + b.w || b.y >= l.box.y + l.box.h || l.box.y >= b.y + b.h);
    const places = [];
    for (let k = 0; k <= 8; k++) for (const dy of k ? [-k * h, k * h] : [0]) places.push([0, dy]);
    if (align !== 'center') for (let k = 1; k <= 8; k++) for (const dy of [0, -h, h]) places.push([k * 24, dy]);
    let b = null, nearest = null;
    for (const [dx, dy] of places) {
      const c = { x: at(dx), y: p[1] - h / 2 + dy, w, h };
      if (!clear(c)) continue;
      nearest ??= c;
      if (!this.materialOf()?.covers(c)) {
        b = c;
        break;
      }
    }
    // a ruler's figure may be left out where it would cover the material (its line stays);
    // any label where it would cover another
    b ??= kind === 'runout' ? null : nearest;
    if (!b) return;
    if (p[1] < b.y - 2 || p[1] > b.y + h + 2) {
      // a leader from the box's nearer edge to the point it names
      const lx = Math.max(b.x, Math.min(b.x + w, p[0]));
      this.line([lx, p[1] < b.y ? b.y : b.y + h], p, colour, 1);
    }
    const [x, y] = [b.x + 2, b.y + h / 2];
    ctx.textAlign = 'left';
    ctx.textBaseline = 'middle';
    ctx.lineWidth = 3;
    ctx.strokeStyle = 'rgba(255,255,255,0.9)';
    ctx.strokeText(text, x, y);
    ctx.fillStyle = colour;
    ctx.fillText(text, x, y);
    this.labels.push({ kind, text, x, y, box: b });
  }

  line(a, b, colour, width = 2, dash = []) {
    if (!a || !b) return;
    const ctx = this.ctx;
    ctx.strokeStyle = colour;
    ctx.lineWidth = width;
    ctx.setLineDash(dash);
    ctx.beginPath();
    ctx.moveTo(a[0], a[1]);
    ctx.lineTo(b[0], b[1]);
    ctx.stroke();
    ctx.setLineDash([]);
  }

  /// Each fitted flank: the line, an arc at its foot and the angle; on a heap at its angle of
  /// repose (poured, released by lifted walls, or built at rest under it), also the line at the core's angle of
  /// repose from the same foot (in 3D in the plane of the radial profile: the slope is sheared
  /// in plane strain in either dimension), named once per heap (the two names of a narrow heap
  /// would overlap). A collapse's momentum spreads it below that angle (Lube et al. 2005 found
  /// collapses' run-outs nearly independent of friction): on a 2D collapse, instead, a note
  /// above its top says so, shortened where it would reach far past the heap (to read as that
  /// heap's beside another) or the view is narrow.
  flanks(d, dim, at, laws) {
    let named = false;
    const repose = atRepose(d);
    const tops = [], feet = [];
    d.heap.flanks.forEach((f) => {
      if (!f) return;
      // the foot is the lower end of the fit
      const [foot, top] = f.from[1] <= f.to[1] ? [f.from, f.to] : [f.to, f.from];
      const A = at(...foot), B = at(...top);
      if (!A || !B) return;
      this.line(A, B, INK, 3);
      const [a0, a1] = arcAngles(A, B);
      const ctx = this.ctx;
      ctx.strokeStyle = INK;
      ctx.lineWidth = 2;
      ctx.beginPath();
      ctx.arc(A[0], A[1], 28, a0, a1);
      ctx.stroke();
      const out = top[0] >= foot[0] ? 1 : -1;
      this.label('angle', `${f.angle.toFixed(1)}°`, [A[0] + out * 34, A[1] - 10], INK, out > 0 ? 'left' : 'right');
      tops.push(B);
      feet.push(A);
      if (laws && d.repose_angle && repose) {
        const run = Math.abs(top[0] - foot[0]) || 0.05;
        const rise = run * Math.tan((d.repose_angle * Math.PI) / 180);
        const C = at(foot[0] + out * run, foot[1] + rise);
        this.line(A, C, LAW, 2, [6, 4]);
        const law = reposeLabel(d);
        // beside the line's middle, on the side away from the heap's axis (clear of its top)
        if (C && !named) this.label('law', law, [(A[0] + C[0]) / 2 - out * 14, (A[1] + C[1]) / 2 - 14], LAW, out > 0 ? 'right' : 'left');
        named ||= !!C;
      }
    });
    // (in 2D only: over a 3D heap's axis the note would cover what rests on it, the bunny of
    // the page's first view)
    if (laws && dim === 2 && d.repose_angle && !repose && tops.length) {
      const x = tops.reduce((s, p) => s + p[0], 0) / tops.length;
      const y = Math.min(...tops.map((p) => p[1]));
      // the whole note where it reaches at most 150 px past the heap's feet
      const span = Math.max(...feet.map((p) => p[0])) - Math.min(...feet.map((p) => p[0]));
      const notes = this.textWidth(COLLAPSE_NOTE[0]) <= span + 300 ? COLLAPSE_NOTE : COLLAPSE_NOTE.slice(1);
      this.label('note', notes, [x, y - 24], LAW, 'center');
    }
  }

  /// The run-out ruler: on the floor from the footprint's edge to the front, with the
  /// distance and its ratio to L0 (R0; in 3D the mean over the sectors, drawn along `right`).
  ruler(d, dim, P, right) {
    const r = d.runout;
    const ends = [];
    if (dim === 2) {
      const [xc, l0] = [r.centre[0], r.footprint];
      if (r.runout[0] > d.spacing) ends.push([xc - l0, r.front[0], r.runout[0]]);
      if (r.runout[1] > d.spacing) ends.push([xc + l0, r.front[1], r.runout[1]]);
      for (const [x0, x1, dist] of ends) {
        const A = P(x0, 0), B = P(x1, 0);
        this.line(A, B, INK, 3);
        for (const e of [A, B]) if (e) this.line([e[0], e[1] - 7], [e[0], e[1] + 7], INK, 2);
        // L0 as the experiments take it: a column against a wall is half of a symmetric one
        const L0 = d.column?.column.half_width ?? l0;
        if (A && B) this.label('runout', `run-out ${dist.toFixed(2)} m (${(dist / L0).toFixed(1)} L0)`, [(A[0] + B[0]) / 2, A[1] + 16], INK, 'center');
      }
    } else if (r.runout[0] > d.spacing) {
      const [xc, zc] = r.centre;
      const along = (x) => P(xc + x * right[0], 0, zc + x * right[1]);
      const A = along(r.footprint), B = along(r.front[0]);
      this.line(A, B, INK, 3);
      if (A && B) this.label('runout', `run-out ${r.runout[0].toFixed(2)} m (${(r.runout[0] / r.footprint).toFixed(1)} R0)`, [(A[0] + B[0]) / 2, A[1] + 16], INK, 'center');
    }
  }

  /// A column's markers: where the experiments put the front (a band where the law gives a
  /// range) and the final height, naming the source.
  column(d, dim, P) {
    const m = d.column;
    const col = m.column;
    const ctx = this.ctx;
    const post = (A) => A && this.line([A[0], A[1]], [A[0], A[1] - 18], LAW, 2);
    if (dim === 2) {
      for (const [near, far] of m.fronts) {
        const A = P(near, 0), B = P(far, 0);
        if (!A || !B) continue;
        ctx.fillStyle = 'rgba(43, 138, 62, 0.25)';
        ctx.fillRect(Math.min(A[0], B[0]) - 1, A[1] - 6, Math.abs(B[0] - A[0]) + 2, 12);
        post(A);
        post(B);
      }
      const x0 = col.wall === 0 ? col.centre[0] - col.half_width : col.wall < 0 ? 0 : col.centre[0] - col.half_width;
      const x1 = col.wall === 0 ? col.centre[0] + col.half_width : col.wall < 0 ? col.half_width : col.centre[0];
      this.line(P(x0, m.height), P(x1, m.height), LAW, 2, [8, 5]);
      const far = m.fronts[m.fronts.length - 1];
      const F = P((far[0] + far[1]) / 2, 0);
      const who = m.law.source.split(',')[0];
      this.label('law', `${who}: run-out${far[0] === far[1] ? '' : ' range'}, a = ${col.aspect_ratio.toFixed(1)}`, F && [F[0], F[1] - 40], LAW, 'center');
      const H = P(x1, m.height);
      this.label('law', `final height, ${who}`, H && [H[0] + 8, H[1] - 10], LAW);
    } else {
      const [xc, zc] = col.centre;
      const ring = (r, y) => {
        ctx.beginPath();
        for (let i = 0; i <= 64; i++) {
          const t = (i / 64) * 2 * Math.PI;
          const p = P(xc + r * Math.cos(t), y, zc + r * Math.sin(t));
          if (!p) continue;
          if (i) ctx.lineTo(p[0], p[1]); else ctx.moveTo(p[0], p[1]);
        }
        ctx.stroke();
      };
      ctx.strokeStyle = LAW;
      ctx.lineWidth = 2;
      ctx.setLineDash([8, 5]);
      ring(m.fronts[0][0], 0);
      if (m.fronts[0][1] !== m.fronts[0][0]) ring(m.fronts[0][1], 0);
      ring(0.3 * col.half_width, m.height);
      ctx.setLineDash([]);
      const F = P(xc, 0, zc + m.fronts[0][1]);
      this.label('law', `${m.law.source.split(',')[0]}: run-out, a = ${col.aspect_ratio.toFixed(1)}`, F && [F[0], F[1] + 16], LAW, 'center');
      const H = P(xc - 0.3 * col.half_width, m.height, zc);
      this.label('law', `final height, ${m.law.source.split(',')[0]}`, H && [H[0] - 8, H[1] - 8], LAW, 'right');
    }
  }

  /// The hand tool: the dragged line and what the core reads of it.
  hand({ a, b, reading }, dim, P) {
    const A = P(...a), B = P(...b);
    if (!A || !B) return;
    this.line(A, B, HAND, 3);
    for (const e of [A, B]) {
      this.ctx.fillStyle = HAND;
      this.ctx.beginPath();
      this.ctx.arc(e[0], e[1], 4, 0, 2 * Math.PI);
      this.ctx.fill();
    }
    if (reading) this.label('hand', `${reading.length.toFixed(3)} m, ${reading.inclination.toFixed(1)}° to the horizontal`, [B[0] + 10, B[1] - 12], HAND);
  }
}

/// Where the particles drawn lie on the view: a grid of 6-pixel cells, each marked where a
/// particle's disc (its projected radius) reaches it; `covers(box)` says whether a box meets
/// a marked cell.
export function occupancy(camera, dim, { positions, stride, count, radius = 0 }, w, h) {
  const cell = 6;
  const nx = Math.ceil(w / cell), ny = Math.ceil(h / cell);
  const grid = new Uint8Array(nx * ny);
  const z = (i) => (dim === 3 ? positions[i * stride + 2] : 0);
  for (let i = 0; i < count; i++) {
    const x = positions[i * stride], y = positions[i * stride + 1];
    const c = camera.project(x, y, z(i));
    if (!c) continue;
    // the disc's radius on the view, from a point one radius to its side
    const e = camera.project(x + radius, y, z(i));
    const r = e ? Math.hypot(e[0] - c[0], e[1] - c[1]) : 0;
    const [i0, i1] = [Math.floor((c[0] - r) / cell), Math.floor((c[0] + r) / cell)];
    const [j0, j1] = [Math.floor((c[1] - r) / cell), Math.floor((c[1] + r) / cell)];
    for (let j = Math.max(0, j0); j <= Math.min(ny - 1, j1); j++) {
      for (let k = Math.max(0, i0); k <= Math.min(nx - 1, i1); k++) grid[j * nx + k] = 1;
    }
  }
  return {
    covers(b) {
      const [i0, i1] = [Math.max(0, Math.floor(b.x / cell)), Math.min(nx - 1, Math.floor((b.x + b.w) / cell))];
      const [j0, j1] = [Math.max(0, Math.floor(b.y / cell)), Math.min(ny - 1, Math.floor((b.y + b.h) / cell))];
      for (let j = j0; j <= j1; j++) for (let k = i0; k <= i1; k++) if (grid[j * nx + k]) return true;
      return false;
    },
  };
}
