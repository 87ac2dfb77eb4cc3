// Helpers shared by the browser tests (Playwright and Puppeteer pages alike).

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
