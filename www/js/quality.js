// Rendering quality adapts to the machine: without a GPU (Chromium's SwiftShader, a
// blocklisted driver) drawing tens of thousands of sprites is what limits the frame rate, so
// the contact shadows go first, then per-fragment sphere depth, then resolution, and they come
// back when frames are quick again. What is measured is the time a frame spends outside the
// simulation. Pure (tested under `node --test`): the renderer applies the level it reports.

export const LEVELS = [
  { shadows: true, sphereDepth: true, scale: 1, label: '' },
  { shadows: false, sphereDepth: true, scale: 1, label: 'no shadows' },
  { shadows: false, sphereDepth: false, scale: 1, label: 'flat depth' },
  { shadows: false, sphereDepth: false, scale: 0.75, label: '¾ resolution' },
  { shadows: false, sphereDepth: false, scale: 0.5, label: '½ resolution' },
];

export class QualityGovernor {
  /// `frameMs`: the frame time aimed at (1000 / target fps).
  constructor(frameMs, { samples = 20, holdMs = 1500, raiseAfterMs = 6000 } = {}) {
    Object.assign(this, { frameMs, size: samples, holdMs, raiseAfterMs });
    this.level = 0;
    this.fixed = false;
    this.samples = [];
    this.changed = -Infinity;
    this.otherMs = 0;
  }

  /// Records a frame that spent `otherMs` outside the simulation, at time `now` (ms); returns
  /// the new level when it changes, else null. Over half a frame's time outside the
  /// simulation (the median of the last samples) lowers the quality; under a fifth, for long
  /// enough, raises it.
  record(otherMs, now) {
    this.samples.push(otherMs);
    if (this.samples.length > this.size) this.samples.shift();
    const sorted = [...this.samples].sort((a, b) => a - b);
    this.otherMs = sorted[sorted.length >> 1];
    if (this.samples.length < this.size || now - this.changed < this.holdMs || this.fixed) return null;
    let level = this.level;
    if (this.otherMs > 0.6 * this.frameMs && level < LEVELS.length - 1) level++;
    else if (this.otherMs < 0.2 * this.frameMs && level > 0 && now - this.changed > this.raiseAfterMs) level--;
    if (level === this.level) return null;
    this.set(level, now);
    return level;
  }

  /// Sets the level (a benchmark may fix it); measuring starts again.
  set(level, now) {
    this.level = level;
    this.changed = now;
    this.samples.length = 0;
  }
}

/// Gives `renderer` the settings of quality `level`.
export function applyQuality(renderer, level) {
  const q = LEVELS[level];
  if ('shadows' in renderer) renderer.shadows = q.shadows;
  if ('scale' in renderer) renderer.scale = q.scale;
  if ('sphereDepth' in renderer) renderer.sphereDepth = q.sphereDepth;
  return q.label;
}
