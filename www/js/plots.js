// Teaching plots on 2D canvases: the energy budget over time, and a particle's stress path in
// p–q space against its material's yield surface.

import { format } from './params.js';
import { energyWindow, pqWindow, surfaceLine, ticks } from './plot-scale.js';
import { mohr, mohrWindow } from './measure-view.js';

export function setup(canvas) {
  const dpr = Math.min(2, window.devicePixelRatio || 1);
  const w = canvas.clientWidth, h = canvas.clientHeight;
  if (canvas.width !== Math.round(w * dpr) || canvas.height !== Math.round(h * dpr)) {
    canvas.width = Math.round(w * dpr);
    canvas.height = Math.round(h * dpr);
  }
  const ctx = canvas.getContext('2d');
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  ctx.clearRect(0, 0, w, h);
  return { ctx, w, h };
}

export function axes(ctx, box, xr, yr, xlabel, ylabel, fmtX, fmtY) {
  const { x0, y0, x1, y1 } = box;
  ctx.strokeStyle = '#d5dbe5';
  ctx.fillStyle = '#5b6577';
  ctx.font = '11px system-ui, sans-serif';
  ctx.lineWidth = 1;
  ctx.textAlign = 'right';
  ctx.textBaseline = 'middle';
  for (const t of ticks(yr[0], yr[1])) {
    const y = y1 - ((t - yr[0]) / (yr[1] - yr[0])) * (y1 - y0);
    ctx.beginPath(); ctx.moveTo(x0, y); ctx.lineTo(x1, y); ctx.stroke();
    ctx.fillText(fmtY(t), x0 - 4, y);
  }
  ctx.textAlign = 'center';
  ctx.textBaseline = 'top';
  for (const t of ticks(xr[0], xr[1])) {
    const x = x0 + ((t - xr[0]) / (xr[1] - xr[0])) * (x1 - x0);
    ctx.beginPath(); ctx.moveTo(x, y0); ctx.lineTo(x, y1); ctx.stroke();
    ctx.fillText(fmtX(t), x, y1 + 3);
  }
  ctx.fillStyle = '#2a3345';
  ctx.font = '12px system-ui, sans-serif';
  ctx.fillText(xlabel, (x0 + x1) / 2, y1 + 17);
  ctx.save();
  ctx.translate(10, (y0 + y1) / 2);
  ctx.rotate(-Math.PI / 2);
  ctx.textBaseline = 'middle';
  ctx.fillText(ylabel, 0, 0);
  ctx.restore();
}

export const ENERGY_SERIES = [
  { key: 'kinetic', label: 'kinetic', colour: '#d9480f' },
  { key: 'potential', label: 'gravitational', colour: '#1c7ed6' },
  { key: 'elastic', label: 'elastic', colour: '#2b8a3e' },
  { key: 'dissipated', label: 'dissipated', colour: '#862e9c' },
  { key: 'total', label: 'sum', colour: '#212529', dash: [4, 3] },
];

/// Energies over time, relative to the state when the plot was (re)started: gravitational
/// energy is measured from its value then, dissipation counts from then, and the sum
/// (kinetic + gravitational + elastic + dissipated) shows how well energy is accounted for:
/// dissipated holds plasticity, viscosity, walls, contact, sleeping, the transfers'
/// numerical damping and the stress update's integration error, so the sum stays flat while
/// the account closes.
export class EnergyPlot {
  constructor(canvas, capacity = 900) {
    this.canvas = canvas;
    this.capacity = capacity;
    this.restart();
  }

  restart() {
    this.samples = [];
    this.ref = null;
  }

  push(d) {
    const dissipated =
      d.dissipated_plastic +
      d.dissipated_viscous +
      d.dissipated_boundary +
      d.dissipated_contact +
      (d.dissipated_sleep || 0) +
      (d.dissipated_numerical || 0) +
      (d.dissipated_integration || 0);
    if (!this.ref) this.ref = { gravitational: d.gravitational, dissipated, time: d.time };
    const s = {
      time: d.time - this.ref.time,
      kinetic: d.kinetic,
      potential: d.gravitational - this.ref.gravitational,
      elastic: d.elastic,
      dissipated: dissipated - this.ref.dissipated,
    };
    s.total = s.kinetic + s.potential + s.elastic + s.dissipated;
    const last = this.samples[this.samples.length - 1];
    if (last && s.time <= last.time) return;
    this.samples.push(s);
    if (this.samples.length > this.capacity) this.samples.splice(0, this.samples.length - this.capacity);
  }

  draw(unit) {
    const { ctx, w, h } = setup(this.canvas);
    const box = { x0: 60, y0: 8, x1: w - 10, y1: h - 34 };
    const S = this.samples;
    if (S.length < 2) {
      ctx.fillStyle = '#5b6577';
      ctx.font = '13px system-ui, sans-serif';
      ctx.textAlign = 'center';
      ctx.fillText('energies appear here while the simulation runs', w / 2, h / 2);
      return;
    }
    const { xr, yr } = energyWindow(S, ENERGY_SERIES.map((k) => k.key));
    axes(ctx, box, xr, yr, 'time (s)', unit, (t) => `${+t.toPrecision(3)}`, (v) => format(v));
    const X = (t) => box.x0 + ((t - xr[0]) / (xr[1] - xr[0] || 1)) * (box.x1 - box.x0);
    const Y = (v) => box.y1 - ((v - yr[0]) / (yr[1] - yr[0])) * (box.y1 - box.y0);
    for (const k of ENERGY_SERIES) {
      ctx.strokeStyle = k.colour;
      ctx.lineWidth = 2;
      ctx.setLineDash(k.dash || []);
      ctx.beginPath();
      S.forEach((s, i) => (i ? ctx.lineTo(X(s.time), Y(s[k.key])) : ctx.moveTo(X(s.time), Y(s[k.key]))));
      ctx.stroke();
    }
    ctx.setLineDash([]);
  }
}

/// A particle's stress path in p–q space (p = −tr σ/3, q = √(3 J2), kPa) with the current
/// yield surface of its material, as the solver reports it (the Drucker–Prager cone from its
/// apex, the von Mises cylinder q = σ_y, or none).
export class StressPlot {
  constructor(canvas, capacity = 1500) {
    this.canvas = canvas;
    this.capacity = capacity;
    this.clear();
  }

  clear() {
    this.path = [];
    this.point = null;
  }

  push(sp) {
    this.point = sp;
    this.path.push([sp.p, sp.q]);
    if (this.path.length > this.capacity) this.path.shift();
  }

  draw() {
    const { ctx, w, h } = setup(this.canvas);
    const sp = this.point;
    if (!sp) {
      ctx.fillStyle = '#5b6577';
      ctx.font = '13px system-ui, sans-serif';
      ctx.textAlign = 'center';
      ctx.fillText('choose “Inspect” and click a particle', w / 2, h / 2 - 8);
      ctx.fillText('to follow its stress path', w / 2, h / 2 + 10);
      return;
    }
    const surface = sp.surface;
    const win = pqWindow(this.path, surface);
    const { k, unit, pMin, pMax, qMax } = win;
    const box = { x0: 60, y0: 8, x1: w - 10, y1: h - 34 };
    const tick = (v) => `${+v.toPrecision(3)}`;
    axes(ctx, box, [pMin, pMax], [0, qMax], `pressure p (${unit})`, `q = √(3 J₂) (${unit})`, tick, tick);
    const X = (p) => box.x0 + ((p - pMin) / (pMax - pMin)) * (box.x1 - box.x0);
    const Y = (q) => box.y1 - (q / qMax) * (box.y1 - box.y0);
    // The yield surface, with the inadmissible side shaded.
    const line = surfaceLine(surface, win);
    ctx.font = '12px system-ui, sans-serif';
    ctx.textAlign = 'left';
    if (line) {
      const [[p0, q0], [p1, q1]] = line;
      ctx.fillStyle = 'rgba(224, 49, 49, 0.08)';
      ctx.beginPath();
      ctx.moveTo(X(p0), Y(q0));
      ctx.lineTo(X(p1), Y(q1));
      ctx.lineTo(X(p1), box.y0);
      ctx.lineTo(X(p0), box.y0);
      ctx.closePath();
      ctx.fill();
      ctx.strokeStyle = '#e03131';
      ctx.lineWidth = 2.5;
      ctx.beginPath();
      ctx.moveTo(X(p0), Y(q0));
      ctx.lineTo(X(p1), Y(q1));
      ctx.stroke();
      const lower = surfaceLine(surface, win, true); // a pyramid's inner meridian, dashed
      if (lower) {
        ctx.setLineDash([6, 4]);
        ctx.lineWidth = 1.5;
        ctx.beginPath();
        ctx.moveTo(X(lower[0][0]), Y(lower[0][1]));
        ctx.lineTo(X(lower[1][0]), Y(lower[1][1]));
        ctx.stroke();
        ctx.setLineDash([]);
      }
      ctx.fillStyle = '#c92a2a';
    } else ctx.fillStyle = '#5b6577';
    ctx.fillText(surface.label, box.x0 + 6, box.y0 + 12);
    ctx.strokeStyle = '#1c7ed6';
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    this.path.forEach(([p, q], i) => (i ? ctx.lineTo(X(p * k), Y(q * k)) : ctx.moveTo(X(p * k), Y(q * k))));
    ctx.stroke();
    ctx.fillStyle = '#d81b8c';
    ctx.beginPath();
    ctx.arc(X(sp.p * k), Y(sp.q * k), 5, 0, 2 * Math.PI);
    ctx.fill();
  }
}

/// The Mohr circles of the inspected particle (normal stress σ against shear stress τ, kPa,
/// compression positive): in 2D plane strain the in-plane circle (the out-of-plane stress a
/// point on the σ axis), in 3D the three principal circles; for sand the Mohr–Coulomb envelope
/// τ = c + σ tan φ at the current φ and c (a Mohr–Coulomb material's yield surface), and for
/// Drucker–Prager the trace of its cone (plane strain: the line at φ_ps; 3D: the circle it
/// allows in triaxial compression at the particle's pressure).
export class MohrPlot {
  constructor(canvas) {
    this.canvas = canvas;
    this.clear();
  }

  clear() {
    this.point = null;
    this.drawn = null; // what the last draw showed, for tests
  }

  set(sp, dim) {
    this.point = sp;
    this.dim = dim;
  }

  draw() {
    const { ctx, w, h } = setup(this.canvas);
    const sp = this.point;
    if (!sp || !sp.principal) {
      this.drawn = null;
      ctx.fillStyle = '#5b6577';
      ctx.font = '13px system-ui, sans-serif';
      ctx.textAlign = 'center';
      ctx.fillText('Mohr circles of the inspected particle', w / 2, h / 2);
      return;
    }
    if (w < 80 || h < 60) {
      this.drawn = null; // hidden (the plots are off)
      return;
    }
    const m = mohr(sp, this.dim);
    const big = Math.max(...sp.principal.map(Math.abs)) >= 1e3;
    const k = big ? 1e-3 : 1;
    const unit = big ? 'kPa' : 'Pa';
    const win = mohrWindow(m);
    const box = { x0: 60, y0: 8, x1: w - 10, y1: h - 34 };
    // equal scales on σ and τ where the box allows (circles stay round)
    const sx = (box.x1 - box.x0) / (win.sMax - win.sMin);
    const tMax = Math.max(win.tMax, (box.y1 - box.y0) / sx);
    const sy = (box.y1 - box.y0) / tMax;
    const s = Math.min(sx, sy);
    const X = (v) => box.x0 + (v - win.sMin) * s;
    const Y = (t) => box.y1 - t * s;
    const tick = (v) => `${+(v * k).toPrecision(3)}`;
    axes(ctx, box, [win.sMin, win.sMin + (box.x1 - box.x0) / s], [0, (box.y1 - box.y0) / s],
      `normal stress σ (${unit})`, `τ (${unit})`, tick, tick);
    ctx.save();
    ctx.beginPath();
    ctx.rect(box.x0, box.y0, box.x1 - box.x0, box.y1 - box.y0);
    ctx.clip();
    const sMax = win.sMin + (box.x1 - box.x0) / s;
    const envelopeLine = (angle, cohesion, colour, dash) => {
      const t = Math.tan((angle * Math.PI) / 180);
      const s0 = t > 0 ? Math.max(win.sMin, -cohesion / t) : win.sMin;
      ctx.strokeStyle = colour;
      ctx.lineWidth = 2;
      ctx.setLineDash(dash);
      ctx.beginPath();
      ctx.moveTo(X(s0), Y(cohesion + t * s0));
      ctx.lineTo(X(sMax), Y(cohesion + t * sMax));
      ctx.stroke();
      ctx.setLineDash([]);
    };
    if (m.envelope) envelopeLine(m.envelope.angle, m.envelope.cohesion, '#e03131', []);
    if (m.cone?.kind === 'line') envelopeLine(m.cone.angle, m.cone.cohesion, '#862e9c', [6, 4]);
    if (m.cone?.kind === 'circle') {
      ctx.strokeStyle = '#862e9c';
      ctx.setLineDash([6, 4]);
      ctx.lineWidth = 2;
      ctx.beginPath();
      ctx.arc(X(m.cone.centre), Y(0), Math.max(0.5, m.cone.radius * s), Math.PI, 2 * Math.PI);
      ctx.stroke();
      ctx.setLineDash([]);
    }
    ctx.strokeStyle = '#1c7ed6';
    ctx.lineWidth = 2;
    for (const c of m.circles) {
      ctx.beginPath();
      ctx.arc(X(c.centre), Y(0), Math.max(0.5, c.radius * s), Math.PI, 2 * Math.PI);
      ctx.stroke();
    }
    ctx.fillStyle = '#d81b8c';
    for (const p of m.points) {
      ctx.beginPath();
      ctx.arc(X(p), Y(0), 4, 0, 2 * Math.PI);
      ctx.fill();
    }
    ctx.restore();
    ctx.font = '12px system-ui, sans-serif';
    ctx.textAlign = 'left';
    let y = box.y0 + 12;
    // each legend line wrapped at a word to the plot's width (a narrow column cut it off)
    const room = box.x1 - box.x0 - 12;
    let widest = 0;
    const note = (text, colour) => {
      ctx.fillStyle = colour;
      let line = '';
      const write = () => {
        ctx.fillText(line, box.x0 + 6, y);
        widest = Math.max(widest, ctx.measureText(line).width);
        y += 15;
      };
      for (const word of text.split(' ')) {
        const next = line ? `${line} ${word}` : word;
        if (line && ctx.measureText(next).width > room) {
          write();
          line = word;
        } else line = next;
      }
      write();
    };
    note(this.dim === 2 ? 'in-plane circle (plane strain); dot: σ_zz' : 'the three principal circles', '#1c7ed6');
    if (m.envelope) note(`Mohr–Coulomb${m.envelope.own ? ' yield surface' : ''}: φ ${m.envelope.angle}°, c ${+(m.envelope.cohesion * k).toPrecision(3)} ${unit}`, '#c92a2a');
    if (m.cone) note(m.cone.kind === 'line' ? `Drucker–Prager cone, plane strain: φ_ps ${m.cone.angle.toFixed(1)}°`
      : 'Drucker–Prager cone at this p (triaxial compression)', '#862e9c');
    this.drawn = { circles: m.circles.length, envelope: !!m.envelope, angle: m.envelope?.angle ?? null, cone: m.cone?.kind ?? null,
      legendFits: widest <= room };
  }
}
