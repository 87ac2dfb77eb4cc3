// Canvas 2D fallback renderer for browsers without WebGL2: particles as flat discs, sorted back
// to front in 3D, with the domain outline.

import { colourOf, css } from './colours.js';

export class CanvasRenderer {
  constructor(canvas) {
    this.canvas = canvas;
    this.ctx = canvas.getContext('2d');
    if (!this.ctx) throw new Error('no 2D canvas');
    this.kind = 'Canvas 2D (no WebGL2)';
    this.scale = 1;
  }

  setDomain(size) {
    this.size = size.slice();
    this.dim = size.length;
  }

  draw({ camera, positions, stride, values, count, mode, range, radius, marker }) {
    const dpr = Math.min(2, window.devicePixelRatio || 1) * this.scale;
    const c = this.canvas;
    const w = Math.round(c.clientWidth * dpr), h = Math.round(c.clientHeight * dpr);
    if (c.width !== w || c.height !== h) { c.width = w; c.height = h; }
    const ctx = this.ctx;
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.fillStyle = '#edf1f8';
    ctx.fillRect(0, 0, c.clientWidth, c.clientHeight);
    const d = this.dim;
    const [W, H, D = 0] = this.size;
    const corners = d === 3
      ? [[0, 0, 0], [W, 0, 0], [W, 0, D], [0, 0, D], [0, H, 0], [W, H, 0], [W, H, D], [0, H, D]]
      : [[0, 0, 0], [W, 0, 0], [W, H, 0], [0, H, 0]];
    const pc = corners.map((p) => camera.project(...p));
    ctx.strokeStyle = '#7a8496';
    ctx.lineWidth = 1;
    const edges = d === 3
      ? [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4], [0, 4], [1, 5], [2, 6], [3, 7]]
      : [[0, 1], [1, 2], [2, 3], [3, 0]];
    if (d === 3 && pc.slice(0, 4).every(Boolean)) {
      ctx.fillStyle = '#ffffff';
      ctx.beginPath();
      pc.slice(0, 4).forEach((p, i) => (i ? ctx.lineTo(p[0], p[1]) : ctx.moveTo(p[0], p[1])));
      ctx.fill();
    }
    ctx.beginPath();
    for (const [a, b] of edges) {
      if (!pc[a] || !pc[b]) continue;
      ctx.moveTo(pc[a][0], pc[a][1]);
      ctx.lineTo(pc[b][0], pc[b][1]);
    }
    ctx.stroke();

    const proj = new Float32Array(count * 3);
    const order = new Uint32Array(count);
    for (let i = 0; i < count; i++) {
      const p = camera.project(positions[i * stride], positions[i * stride + 1], d === 3 ? positions[i * stride + 2] : 0);
      order[i] = i;
      if (!p) { proj[i * 3 + 2] = Infinity; continue; }
      proj.set(p, i * 3);
    }
    if (d === 3) order.sort((a, b) => proj[b * 3 + 2] - proj[a * 3 + 2]);
    const ppm = camera.pixelsPerMetre();
    for (const i of order) {
      const z = proj[i * 3 + 2];
      if (!Number.isFinite(z)) continue;
      let r = radius * ppm;
      if (d === 3) {
        const [x, y, zz] = [positions[i * stride], positions[i * stride + 1], positions[i * stride + 2]];
        const dist = Math.hypot(x - camera.eye[0], y - camera.eye[1], zz - camera.eye[2]);
        r = (radius * ppm) / Math.max(1e-3, dist);
      }
      ctx.fillStyle = css(colourOf(mode, values[i], range));
      const s = Math.max(1.5, 2 * r);
      ctx.fillRect(proj[i * 3] - s / 2, proj[i * 3 + 1] - s / 2, s, s);
    }
    if (marker) {
      const p = camera.project(marker[0], marker[1], marker[2] ?? 0);
      if (p) {
        ctx.strokeStyle = '#d81b8c';
        ctx.lineWidth = 3;
        ctx.beginPath();
        ctx.arc(p[0], p[1], 9, 0, 2 * Math.PI);
        ctx.stroke();
      }
    }
  }

  finish() {}
}
