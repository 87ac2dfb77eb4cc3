// The scenes the page offers: the files of scenes/ (listed by `cargo xtask build` into
// www/pkg/scenes.json, 2D and 3D versions paired) and the empty sandbox; fetching a scene with
// the files it references, and the shipped bunny.

export const SANDBOX = 'sandbox';

/// [{ base, name, paths: { 2: path, 3: path } }], the sandbox last.
export async function loadSceneList() {
  let files = [];
  try {
    const r = await fetch('www/pkg/scenes.json', { cache: 'no-cache' });
    if (r.ok) files = await r.json();
  } catch {
    files = [];
  }
  const byBase = new Map();
  for (const f of files) {
    const e = byBase.get(f.base) || { base: f.base, name: '', paths: {} };
    e.paths[f.dim] = f.path;
    e.name = (e.name || f.name || f.base).replace(/\s*\((2D|3D)\)\s*$/i, '');
    byBase.set(f.base, e);
  }
  return [...byBase.values(), { base: SANDBOX, name: 'Sandbox (empty box)', paths: { 2: SANDBOX, 3: SANDBOX } }];
}

/// The scene `key` (a base name of `list`, or the path of a scene file) in dimension `dim`:
/// its JSON and the texts of the files it references ({ text, assets: JSON or null }; the
/// sandbox is { sandbox: dim }). `session` names the files a scene references.
export async function sceneSource(key, dim, list, session) {
  if (key === SANDBOX) return { sandbox: dim };
  const path = key.endsWith('.json') ? key : list.find((s) => s.base === key)?.paths[dim];
  if (!path) throw new Error(`no ${dim}D version of scene “${key}”`);
  const text = await fetchText(path);
  const base = new URL(path, location.href);
  const files = await session.assetPaths(text);
  if (!files.length) return { text, assets: null };
  const texts = await Promise.all(files.map((f) => fetchText(new URL(f, base).href)));
  return { text, assets: JSON.stringify(Object.fromEntries(files.map((f, i) => [f, texts[i]]))) };
}

async function fetchText(url) {
  const r = await fetch(url, { cache: 'no-cache' });
  if (!r.ok) throw new Error(`${url}: ${r.status} ${r.statusText}`);
  return r.text();
}

/// The shipped bunny for the drop tool ({ obj, polygon }: mesh in 3D, silhouette in 2D);
/// without these files the solver builds a bunny out of balls.
export async function loadBunny() {
  const get = (f) => fetchText(`scenes/${f}`).catch(() => undefined);
  const [obj, polygon] = await Promise.all([get('bunny.obj'), get('bunny2d.txt')]);
  return { obj, polygon };
}
