// Cameras and the little matrix algebra they need (column-major 4×4, as WebGL expects).
// 3D: an orbit camera (drag to turn, wheel to zoom) around the middle of the domain.
// 2D: an orthographic view that fits the domain.

export function multiply(a, b) {
  const o = new Float32Array(16);
  for (let c = 0; c < 4; c++)
    for (let r = 0; r < 4; r++) {
      let s = 0;
      for (let k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
      o[c * 4 + r] = s;
    }
  return o;
}

export function perspective(fovy, aspect, near, far) {
  const f = 1 / Math.tan(fovy / 2);
  const o = new Float32Array(16);
  o[0] = f / aspect;
  o[5] = f;
  o[10] = (far + near) / (near - far);
  o[11] = -1;
  o[14] = (2 * far * near) / (near - far);
  return o;
}

export function ortho(l, r, b, t, n, f) {
  const o = new Float32Array(16);
  o[0] = 2 / (r - l);
  o[5] = 2 / (t - b);
  o[10] = -2 / (f - n);
  o[12] = -(r + l) / (r - l);
  o[13] = -(t + b) / (t - b);
  o[14] = -(f + n) / (f - n);
  o[15] = 1;
  return o;
}

function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
function norm(a) { const l = Math.hypot(a[0], a[1], a[2]) || 1; return [a[0] / l, a[1] / l, a[2] / l]; }
function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

export function lookAt(eye, target, up) {
  const z = norm(sub(eye, target));
  const x = norm(cross(up, z));
  const y = cross(z, x);
  return new Float32Array([
    x[0], y[0], z[0], 0,
    x[1], y[1], z[1], 0,
    x[2], y[2], z[2], 0,
    -dot(x, eye), -dot(y, eye), -dot(z, eye), 1,
  ]);
}

/// Applies a column-major matrix to (x, y, z, 1); returns [x, y, z, w].
export function transform(m, x, y, z) {
  return [
    m[0] * x + m[4] * y + m[8] * z + m[12],
    m[1] * x + m[5] * y + m[9] * z + m[13],
    m[2] * x + m[6] * y + m[10] * z + m[14],
    m[3] * x + m[7] * y + m[11] * z + m[15],
  ];
}

/// A camera over a domain of `size` ([w, h] or [w, h, d], metres).
export class Camera {
  constructor(size) {
    this.setDomain(size);
  }

  setDomain(size) {
    this.size = size.slice();
    this.dim = size.length;
    const [w, h, d = 0] = size;
    this.target = [w / 2, h * 0.3, d / 2];
    this.zoom3d = 1;
    this.yaw = -0.55;
    this.pitch = 0.42;
    this.zoom2d = 1;
  }

  /// The view and projection matrices for a viewport of `width` × `height` pixels.
  matrices(width, height) {
    const aspect = width / Math.max(1, height);
    if (this.dim === 2) {
      const [w, h] = this.size;
      const margin = 0.06 * Math.max(w, h);
      let halfW = (w + 2 * margin) / 2, halfH = (h + 2 * margin) / 2;
      if (halfW / halfH > aspect) halfH = halfW / aspect; else halfW = halfH * aspect;
      halfW /= this.zoom2d; halfH /= this.zoom2d;
      const cx = w / 2, cy = h / 2;
      this.view = lookAt([cx, cy, 10], [cx, cy, 0], [0, 1, 0]);
      this.proj = ortho(-halfW, halfW, -halfH, halfH, 0.1, 20);
      this.eye = [cx, cy, 10];
      this.orthographic = true;
    } else {
      // The distance at which the domain's bounding sphere fits the narrower field of view.
      const fovy = (40 * Math.PI) / 180;
      const half = Math.min(Math.tan(fovy / 2), aspect * Math.tan(fovy / 2));
      const sphere = 0.5 * Math.hypot(...this.size);
      this.radius = ((0.92 * sphere) / Math.sin(Math.atan(half))) * this.zoom3d;
      const cp = Math.cos(this.pitch);
      const eye = [
        this.target[0] + this.radius * cp * Math.sin(this.yaw),
        this.target[1] + this.radius * Math.sin(this.pitch),
        this.target[2] + this.radius * cp * Math.cos(this.yaw),
      ];
      this.eye = eye;
      this.view = lookAt(eye, this.target, [0, 1, 0]);
      const far = this.radius * 4 + Math.hypot(...this.size) * 2;
      this.proj = perspective(fovy, aspect, this.radius * 0.02, far);
      this.orthographic = false;
    }
    this.viewProj = multiply(this.proj, this.view);
    this.width = width;
    this.height = height;
    return this;
  }

  orbit(dx, dy) {
    if (this.dim === 2) return;
    this.yaw -= dx * 0.006;
    this.pitch = Math.min(1.45, Math.max(-0.1, this.pitch + dy * 0.006));
  }

  zoomBy(factor) {
    if (this.dim === 2) this.zoom2d = Math.min(8, Math.max(0.5, this.zoom2d / factor));
    else this.zoom3d = Math.min(4, Math.max(0.2, this.zoom3d * factor));
  }

  /// Screen position (CSS pixels) and depth of a world point, or null if behind the camera.
  project(x, y, z) {
    const c = transform(this.viewProj, x, y, z);
    if (c[3] <= 1e-6) return null;
    return [((c[0] / c[3]) * 0.5 + 0.5) * this.width, (0.5 - (c[1] / c[3]) * 0.5) * this.height, c[2] / c[3]];
  }

  /// The world point under a screen position: on the floor y = 0 in 3D (null if the ray
  /// misses it), in the plane z = 0 in 2D.
  unproject(px, py) {
    const nx = (px / this.width) * 2 - 1;
    const ny = 1 - (py / this.height) * 2;
    const inv = invert(this.viewProj);
    const a = transform(inv, nx, ny, -1);
    const b = transform(inv, nx, ny, 1);
    const p0 = [a[0] / a[3], a[1] / a[3], a[2] / a[3]];
    const p1 = [b[0] / b[3], b[1] / b[3], b[2] / b[3]];
    if (this.dim === 2) return [p0[0], p0[1]];
    const dy = p1[1] - p0[1];
    if (Math.abs(dy) < 1e-12) return null;
    const t = -p0[1] / dy;
    if (t < 0) return null;
    return [p0[0] + t * (p1[0] - p0[0]), 0, p0[2] + t * (p1[2] - p0[2])];
  }

  /// Pixels per metre at a world point (for point sprite sizes).
  pixelsPerMetre() {
    return (this.proj[5] * this.height) / 2;
  }
}

export function invert(m) {
  const inv = new Float32Array(16);
  inv[0] = m[5] * m[10] * m[15] - m[5] * m[11] * m[14] - m[9] * m[6] * m[15] + m[9] * m[7] * m[14] + m[13] * m[6] * m[11] - m[13] * m[7] * m[10];
  inv[4] = -m[4] * m[10] * m[15] + m[4] * m[11] * m[14] + m[8] * m[6] * m[15] - m[8] * m[7] * m[14] - m[12] * m[6] * m[11] + m[12] * m[7] * m[10];
  inv[8] = m[4] * m[9] * m[15] - m[4] * m[11] * m[13] - m[8] * m[5] * m[15] + m[8] * m[7] * m[13] + m[12] * m[5] * m[11] - m[12] * m[7] * m[9];
  inv[12] = -m[4] * m[9] * m[14] + m[4] * m[10] * m[13] + m[8] * m[5] * m[14] - m[8] * m[6] * m[13] - m[12] * m[5] * m[10] + m[12] * m[6] * m[9];
  inv[1] = -m[1] * m[10] * m[15] + m[1] * m[11] * m[14] + m[9] * m[2] * m[15] - m[9] * m[3] * m[14] - m[13] * m[2] * m[11] + m[13] * m[3] * m[10];
  inv[5] = m[0] * m[10] * m[15] - m[0] * m[11] * m[14] - m[8] * m[2] * m[15] + m[8] * m[3] * m[14] + m[12] * m[2] * m[11] - m[12] * m[3] * m[10];
  inv[9] = -m[0] * m[9] * m[15] + m[0] * m[11] * m[13] + m[8] * m[1] * m[15] - m[8] * m[3] * m[13] - m[12] * m[1] * m[11] + m[12] * m[3] * m[9];
  inv[13] = m[0] * m[9] * m[14] - m[0] * m[10] * m[13] - m[8] * m[1] * m[14] + m[8] * m[2] * m[13] + m[12] * m[1] * m[10] - m[12] * m[2] * m[9];
  inv[2] = m[1] * m[6] * m[15] - m[1] * m[7] * m[14] - m[5] * m[2] * m[15] + m[5] * m[3] * m[14] + m[13] * m[2] * m[7] - m[13] * m[3] * m[6];
  inv[6] = -m[0] * m[6] * m[15] + m[0] * m[7] * m[14] + m[4] * m[2] * m[15] - m[4] * m[3] * m[14] - m[12] * m[2] * m[7] + m[12] * m[3] * m[6];
  inv[10] = m[0] * m[5] * m[15] - m[0] * m[7] * m[13] - m[4] * m[1] * m[15] + m[4] * m[3] * m[13] + m[12] * m[1] * m[7] - m[12] * m[3] * m[5];
  inv[14] = -m[0] * m[5] * m[14] + m[0] * m[6] * m[13] + m[4] * m[1] * m[14] - m[4] * m[2] * m[13] - m[12] * m[1] * m[6] + m[12] * m[2] * m[5];
  inv[3] = -m[1] * m[6] * m[11] + m[1] * m[7] * m[10] + m[5] * m[2] * m[11] - m[5] * m[3] * m[10] - m[9] * m[2] * m[7] + m[9] * m[3] * m[6];
  inv[7] = m[0] * m[6] * m[11] - m[0] * m[7] * m[10] - m[4] * m[2] * m[11] + m[4] * m[3] * m[10] + m[8] * m[2] * m[7] - m[8] * m[3] * m[6];
  inv[11] = -m[0] * m[5] * m[11] + m[0] * m[7] * m[9] + m[4] * m[1] * m[11] - m[4] * m[3] * m[9] - m[8] * m[1] * m[7] + m[8] * m[3] * m[5];
  inv[15] = m[0] * m[5] * m[10] - m[0] * m[6] * m[9] - m[4] * m[1] * m[10] + m[4] * m[2] * m[9] + m[8] * m[1] * m[6] - m[8] * m[2] * m[5];
  let det = m[0] * inv[0] + m[1] * inv[4] + m[2] * inv[8] + m[3] * inv[12];
  det = det === 0 ? 1 : 1 / det;
  for (let i = 0; i < 16; i++) inv[i] *= det;
  return inv;
}
