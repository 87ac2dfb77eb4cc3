// The pointer on the view: drag (one finger) to orbit (3D), wheel or pinch (two fingers) to
// zoom, click or tap to drop or inspect, press and hold to pour. The gestures are recognised in
// touch.js.

import { Gestures, Hold } from './touch.js';

/// Wires `canvas`: drags turn `camera`, the wheel and a pinch zoom, a click or tap (a press
/// that did not move) calls `onClick(x, y)` with the position in CSS pixels from the canvas'
/// top-left corner.
///
/// With `measure` {active(), drag(from, to, done)}: while `active()`, a one-finger drag
/// measures instead of turning the view: `drag` gets its start and end (CSS pixels on the
/// canvas) as it moves, and `done` when it ends.
///
/// With `hold` {active(), start(x, y), stop()}: while `active()`, a press calls `start` with
/// where it went down (CSS pixels on the canvas) and `stop` when it is released, cancelled or
/// leaves the view (or the window loses the focus); it never turns the view.
export function setupPointer(canvas, camera, onClick, measure = null, hold = null) {
  const g = new Gestures();
  const held = new Hold();
  let start = null; // the hand tool's drag
  const local = (e) => {
    const r = canvas.getBoundingClientRect();
    return [e.clientX - r.left, e.clientY - r.top];
  };
  const inside = (e) => {
    const r = canvas.getBoundingClientRect();
    return e.clientX >= r.left && e.clientX <= r.right && e.clientY >= r.top && e.clientY <= r.bottom;
  };
  const release = (a) => {
    if (a?.stop) hold.stop();
  };
  canvas.addEventListener('pointerdown', (e) => {
    canvas.setPointerCapture(e.pointerId);
    if (held.held || hold?.active()) {
      // the main button of a mouse or pen, or the first finger: not a right or middle click
      const a = held.down(e.pointerId, ...local(e), e.isPrimary && e.button === 0);
      if (a?.start) hold.start(...a.start);
      return;
    }
    if (measure?.active() && e.isPrimary) {
      start = local(e);
      return;
    }
    g.down(e.pointerId, e.clientX, e.clientY);
  });
  canvas.addEventListener('pointermove', (e) => {
    if (held.held) {
      release(held.move(e.pointerId, inside(e)));
      return;
    }
    if (start) {
      measure.drag(start, local(e), false);
      return;
    }
    const a = g.move(e.pointerId, e.clientX, e.clientY);
    if (a?.orbit) camera.orbit(a.orbit[0], a.orbit[1]);
    if (a?.zoom) camera.zoomBy(a.zoom);
    canvas.classList.toggle('dragging', g.dragging);
  });
  canvas.addEventListener('pointerup', (e) => {
    if (held.held) {
      release(held.up(e.pointerId));
      return;
    }
    if (start) {
      measure.drag(start, local(e), true);
      start = null;
      return;
    }
    const a = g.up(e.pointerId, e.clientX, e.clientY);
    canvas.classList.toggle('dragging', g.dragging);
    if (a?.tap) {
      const r = canvas.getBoundingClientRect();
      onClick(a.tap[0] - r.left, a.tap[1] - r.top);
    }
  });
  for (const type of ['pointercancel', 'lostpointercapture', 'pointerleave']) {
    canvas.addEventListener(type, (e) => release(held.cancel(e.pointerId)));
  }
  // A finger held still opens the context menu on some touch screens: not while it pours.
  canvas.addEventListener('contextmenu', (e) => {
    if (held.held || hold?.active()) e.preventDefault();
  });
  window.addEventListener('blur', () => {
    if (held.held) release(held.cancel(held.id));
  });
  canvas.addEventListener('pointercancel', (e) => {
    start = null;
    g.cancel(e.pointerId);
    canvas.classList.toggle('dragging', g.dragging);
  });
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    camera.zoomBy(Math.exp(e.deltaY * 0.001));
  }, { passive: false });
}

/// The particle drawn nearest screen point (px, py), within `reach` pixels, and among close
/// ones the nearest the eye: its index, or -1. `project(x, y, z)` gives [sx, sy, depth] or
/// null; positions are `stride` floats per particle, `dim` of them used. Pure.
export function nearestParticle({ positions, stride, count }, dim, project, px, py, reach = 14) {
  let best = -1, bestScore = Infinity;
  for (let i = 0; i < count; i++) {
    const s = project(positions[i * stride], positions[i * stride + 1], dim === 3 ? positions[i * stride + 2] : 0);
    if (!s) continue;
    const d = Math.hypot(s[0] - px, s[1] - py);
    if (d > reach) continue;
    const score = s[2] + d * 1e-4;
    if (score < bestScore) { bestScore = score; best = i; }
  }
  return best;
}

/// Whether world point `p` (from `camera.unproject`) lies where an object can be dropped in a
/// box of size `domain`: inside it, over the floor in 3D.
export function insideBox(p, domain) {
  if (!p) return false;
  const [W, H, D] = domain;
  return p[0] >= 0 && p[0] <= W && (domain.length === 2 ? p[1] >= 0 && p[1] <= H : p[2] >= 0 && p[2] <= D);
}
