// Gestures on the view from pointer events, for a mouse, a pen and fingers alike: one pointer
// dragged turns the 3D view, two pinch to zoom, a press that did not move (a tap or a click)
// drops or inspects; with the Pour tool, a press held (`Hold`) pours from where it went down
// until it is released, cancelled or leaves the view. Pure: pointer.js feeds it the events and
// applies what it returns; tested under `node --test`.

/// How far (CSS pixels) a pointer may move and still count as a tap.
export const TAP_SLOP = 6;

export class Gestures {
  constructor(slop = TAP_SLOP) {
    this.slop = slop;
    this.pointers = new Map(); // id → {x, y, x0, y0}
    this.moved = false; // the gesture became a drag or a pinch: no tap when it ends
    this.spread = 0; // the distance between two pointers at the last move
  }

  /// A pointer went down at (x, y).
  down(id, x, y) {
    if (this.pointers.size === 0) this.moved = false;
    this.pointers.set(id, { x, y, x0: x, y0: y });
    if (this.pointers.size >= 2) {
      // A second finger: a pinch, never a tap.
      this.moved = true;
      this.spread = this.distance();
    }
  }

  /// A pointer moved to (x, y): `{orbit: [dx, dy]}` (one pointer dragged), `{zoom: factor}`
  /// (two pinched: below 1 when they spread, as the camera's `zoomBy` takes it) or null.
  move(id, x, y) {
    const p = this.pointers.get(id);
    if (!p) return null;
    const dx = x - p.x, dy = y - p.y;
    p.x = x;
    p.y = y;
    if (this.pointers.size >= 2) {
      const d = this.distance();
      const before = this.spread;
      this.spread = d;
      return before > 0 && d > 0 && d !== before ? { zoom: before / d } : null;
    }
    if (!this.moved && Math.hypot(x - p.x0, y - p.y0) > this.slop) this.moved = true;
    return this.moved && (dx || dy) ? { orbit: [dx, dy] } : null;
  }

  /// A pointer went up at (x, y): `{tap: [x, y]}` when it was the only one and did not move
  /// beyond the slop, else null.
  up(id, x, y) {
    const had = this.pointers.delete(id);
    if (this.pointers.size === 1) this.spread = 0;
    if (!had || this.pointers.size > 0 || this.moved) return null;
    return { tap: [x, y] };
  }

  /// A pointer was cancelled (the browser took the gesture): no tap.
  cancel(id) {
    this.pointers.delete(id);
    this.moved = true;
  }

  /// Whether a drag or pinch is under way.
  get dragging() {
    return this.moved && this.pointers.size > 0;
  }

  distance() {
    const [a, b] = [...this.pointers.values()];
    return Math.hypot(a.x - b.x, a.y - b.y);
  }
}

/// A press held on the view (the Pour tool): it starts where the first primary pointer goes
/// down and ends when that pointer goes up, is cancelled, or leaves the view. It never turns
/// nor zooms the view, however the pointer moves, and other pointers are ignored while it lasts
/// (a second finger does not start another).
export class Hold {
  constructor() {
    this.id = null; // the pointer held
  }

  /// A pointer went down at (x, y): `{start: [x, y]}` when it is primary and none is held,
  /// else null.
  down(id, x, y, primary = true) {
    if (this.id !== null || !primary) return null;
    this.id = id;
    return { start: [x, y] };
  }

  /// A pointer moved, `inside` the view or not: `{stop: true}` when the one held left the view.
  move(id, inside) {
    return id === this.id && !inside ? this.end() : null;
  }

  /// A pointer went up: `{stop: true}` when it was the one held.
  up(id) {
    return this.held && id === this.id ? this.end() : null;
  }

  /// A pointer was cancelled (the browser took it, or the page lost it): as `up`.
  cancel(id) {
    return this.up(id);
  }

  /// Whether a press is held.
  get held() {
    return this.id !== null;
  }

  end() {
    this.id = null;
    return { stop: true };
  }
}
