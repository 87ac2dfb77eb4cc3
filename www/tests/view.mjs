// Helpers shared by the browser tests (Playwright and Puppeteer pages alike).

/// An init script for a page that must run without WebGL2 (the Canvas 2D fallback): a
/// canvas then refuses 'webgl2' and gives every other context as before.
export function hideWebgl2() {
  const get = HTMLCanvasElement.prototype.getContext;
  HTMLCanvasElement.prototype.getContext = function (kind, ...rest) {
    return kind === 'webgl2' ? null : get.call(this, kind, ...rest);
  };
}

/// Screen position (page pixels) of a world point of the playground's view.
export async function screenOf(page, x, y, z) {
  return page.evaluate(([x, y, z]) => {
    const c = document.getElementById('view');
    const r = c.getBoundingClientRect();
    mpm.camera.matrices(c.clientWidth, c.clientHeight);
    const p = mpm.camera.project(x, y, z);
    return [r.left + p[0], r.top + p[1]];
  }, [x, y, z]);
}

/// Where up to `n` particles of body `body` are drawn in the frame shown: positions in CSS
/// pixels from the view's top-left corner, evenly sampled over the body. The view must colour
/// by body. With `unhidden` (a radius in CSS pixels), a particle is left out when a particle
/// of another body is drawn nearer the eye within that radius of it: what can be seen of the
/// body, when a bunny sits on the sand.
export async function bodyPoints(page, body, n = 200, unhidden = 0) {
  return page.evaluate(([body, n, unhidden]) => {
    if (mpm.view.colour !== 'body') throw new Error(`the view colours by ${mpm.view.colour}, not by body`);
    const f = mpm.frame, c = document.getElementById('view');
    mpm.camera.matrices(c.clientWidth, c.clientHeight);
    const stride = f.stride, dim = mpm.domain.length;
    const pos = f.positions, which = f.values;
    const at = (i) => mpm.camera.project(pos[i * stride], pos[i * stride + 1], dim === 3 ? pos[i * stride + 2] : 0);
    const mine = [];
    const others = [];
    for (let i = 0; i < f.count; i++) {
      if (which[i] === body) mine.push(i);
      else if (unhidden > 0) {
        const p = at(i);
        if (p) others.push(p);
      }
    }
    const hidden = ([x, y, depth]) =>
      others.some(([u, v, d]) => d < depth && (u - x) ** 2 + (v - y) ** 2 < unhidden * unhidden);
    const step = Math.max(1, Math.floor(mine.length / n));
    const out = [];
    for (let k = 0; k < mine.length; k += step) {
      const p = at(mine[k]);
      if (p && !hidden(p)) out.push([p[0], p[1]]);
    }
    return out;
  }, [body, n, unhidden]);
}

/// The fraction of `points` (CSS pixels in the view, see `bodyPoints`) whose pixel in the
/// decoded view screenshot `png` (of a view `cssWidth` pixels wide) satisfies `test([r, g, b])`.
export function fractionAt(png, points, cssWidth, test) {
  const scale = png.width / cssWidth;
  let hits = 0;
  for (const [x, y] of points) {
    const px = Math.round(x * scale), py = Math.round(y * scale);
    if (px < 0 || py < 0 || px >= png.width || py >= png.height) continue;
    const i = (py * png.width + px) * png.channels;
    if (test([png.data[i], png.data[i + 1], png.data[i + 2]])) hits++;
  }
  return points.length ? hits / points.length : 0;
}
