// The static folder of `cargo xtask dist` (MPM_DIST, default target/dist), served alone by a
// plain static file server (files by extension, no other header) under a sub-path, as a
// project page of a static host would be: the page loads in headless Chromium without a
// console error or a failed request, simulates, and reaches every lesson and scene with the
// files they reference.
//
//   cargo xtask dist && node --test www/tests/dist.test.mjs
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { createServer } from 'node:http';
import { existsSync, readFileSync, statSync } from 'node:fs';
import { extname, join, normalize, resolve, sep } from 'node:path';
import { launch } from './browser.mjs';

const DIST = resolve(process.env.MPM_DIST || 'target/dist');
const PREFIX = '/some/host/path/';
const TYPES = {
  '.html': 'text/html', '.js': 'text/javascript', '.css': 'text/css', '.json': 'application/json',
  '.wasm': 'application/wasm', '.obj': 'text/plain', '.txt': 'text/plain', '.md': 'text/plain',
};

let server, root, browser;
const served = [];

before(async () => {
  assert.ok(existsSync(join(DIST, 'index.html')), `${DIST} has no index.html: run cargo xtask dist`);
  server = createServer((req, res) => {
    const path = decodeURIComponent(new URL(req.url, 'http://x').pathname);
    let file = null;
    if (path.startsWith(PREFIX)) {
      const rel = normalize(path.slice(PREFIX.length) || 'index.html');
      const full = join(DIST, rel);
      if (full.startsWith(DIST + sep) && existsSync(full) && statSync(full).isFile()) file = full;
    }
    served.push([path, file ? 200 : 404]);
    if (!file) {
      res.writeHead(404, { 'Content-Type': 'text/plain' }).end('not found\n');
      return;
    }
    res.writeHead(200, { 'Content-Type': TYPES[extname(file)] || 'application/octet-stream' });
    res.end(readFileSync(file));
  });
  await new Promise((ok) => server.listen(0, '127.0.0.1', ok));
  root = `http://127.0.0.1:${server.address().port}${PREFIX}`;
  browser = await launch();
});
after(async () => {
  await browser?.close();
  server?.close();
});

test('the static folder alone, under a sub-path: the page loads and simulates, every lesson and scene is reachable', async () => {
  const page = await browser.context.newPage();
  const errors = [], failed = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('response', (r) => { if (r.status() >= 400) failed.push(`${r.status()} ${r.url()}`); });
  page.on('requestfailed', (r) => failed.push(`failed ${r.url()}`));
  await page.goto(root);
  await page.waitForFunction(() => window.mpm?.sim && window.mpm.stats.frames > 5, null, { timeout: 60_000 });
  const t0 = await page.evaluate(() => mpm.simTime);
  await page.waitForFunction((t0) => mpm.simTime > t0 + 0.01, t0, { timeout: 60_000 });
  const s = await page.evaluate(() => ({ particles: mpm.sim.particles, failure: mpm.sim.failure || null, thread: mpm.session.kind }));
  assert.ok(s.particles > 1000 && s.failure === null, JSON.stringify(s));
  assert.equal(s.thread, 'worker', 'the worker starts from the static folder too');

  // The lists the build wrote, and every file they name with the files those reference,
  // fetched by the page itself with relative URLs.
  const missing = await page.evaluate(async () => {
    const solver = await import('./www/pkg/mpm.js');
    await solver.default(); // a no-op where the page already started it
    const { assetPaths } = solver;
    const get = async (url) => {
      const r = await fetch(url);
      if (!r.ok) throw new Error(`${r.status} ${url}`);
      return r;
    };
    const out = [];
    const lessons = await (await get('www/pkg/lessons.json')).json();
    const scenes = await (await get('www/pkg/scenes.json')).json();
    if (lessons.length < 5) out.push(`only ${lessons.length} lessons listed`);
    const paths = [...scenes.map((s) => s.path), ...lessons.map((l) => l.path)];
    for (const path of paths) {
      try {
        const text = await (await get(path)).text();
        const json = JSON.parse(text);
        // A lesson's scene: a path beside it, or inline (its files relative to the lesson).
        let sceneText = text, base = new URL(path, location.href);
        if (json.caption !== undefined) {
          if (typeof json.scene === 'string') {
            base = new URL(json.scene, base);
            sceneText = await (await get(base.href)).text();
          } else {
            sceneText = JSON.stringify(json.scene);
          }
        }
        for (const f of assetPaths(sceneText)) await get(new URL(f, base).href);
      } catch (e) {
        out.push(`${path}: ${e.message}`);
      }
    }
    return out;
  });
  assert.deepEqual(missing, []);
  assert.deepEqual(errors, [], 'no console error');
  assert.deepEqual(failed, [], 'no failed request');
  assert.ok(served.every(([p]) => p.startsWith(PREFIX)), `a request left the folder's path: ${served.filter(([p]) => !p.startsWith(PREFIX)).map(([p]) => p)}`);
  await page.close();
});
