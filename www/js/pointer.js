// The pointer on the view: drag to orbit (3D), wheel to zoom, click to drop or inspect.

/// Wires `canvas`: drags turn `camera`, the wheel zooms, a click (a press that did not move)
/// calls `onClick(x, y)` with the position in CSS pixels from the canvas' top-left corner.
export function setupPointer(canvas, camera, onClick) {
  let down = null;
  canvas.addEventListener('pointerdown', (e) => {
    down = { x: e.clientX, y: e.clientY, lastX: e.clientX, lastY: e.clientY, moved: false };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener('pointermove', (e) => {
    if (!down) return;
    const dx = e.clientX - down.lastX, dy = e.clientY - down.lastY;
    if (Math.hypot(e.clientX - down.x, e.clientY - down.y) > 5) down.moved = true;
    if (down.moved) {
      canvas.classList.add('dragging');
      camera.orbit(dx, dy);
    }
    down.lastX = e.clientX;
    down.lastY = e.clientY;
  });
  canvas.addEventListener('pointerup', (e) => {
    canvas.classList.remove('dragging');
    if (down && !down.moved) {
      const r = canvas.getBoundingClientRect();
      onClick(e.clientX - r.left, e.clientY - r.top);
    }
    down = null;
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
