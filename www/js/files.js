// Scene files in and out of the page. *Save scene* downloads the session as a scene file the
// CLI runs unchanged (`Playground.saveScene`: every parameter as set, each dropped body entering
// at its drop time). *Open scene* takes a scene file from a file picker or dropped on the view,
// with the meshes and outlines it references dropped alongside (matched by file name against
// the paths written in the scene; the shipped bunny's files otherwise); a bad file gets the
// solver's message naming the field, on the page. The naming and matching are pure (tested
// under `node --test`).

import { banner, toast } from './hud.js';
import { fetchText } from './scenes.js';

/// Files of the repository a scene may name without their being dropped alongside: the
/// shipped bunny (what a dropped bunny is, in a saved scene).
export const SHIPPED = ['bunny.obj', 'bunny2d.txt'];

/// A file name (without extension) for scene `name` at simulated time `t` (s), or over the
/// times `t` to `t1`: `bunny-on-a-sand-ball-3d-t1.25s`, `…-t0.50-2.30s`.
export function fileStem(name, t, t1) {
  const slug = String(name || 'scene').toLowerCase().normalize('NFKD').replace(/[\u0300-\u036f]/g, '')
    .replace(/[^a-z0-9]+/g, '-').replace(/^-+|-+$/g, '').slice(0, 48).replace(/-+$/, '') || 'scene';
  const time = (x) => (Number.isFinite(x) && x > 0 ? x : 0).toFixed(2);
  return `${slug}-t${time(t)}${t1 === undefined ? '' : `-${time(t1)}`}s`;
}

/// The last part of a path (either slash).
export function baseName(path) {
  return String(path).split(/[\\/]/).pop();
}

/// The scene (or lesson) file among `files` ([{name}]): the one ending in .json. Throws a
/// message when there is none or more than one.
export function sceneFileOf(files) {
  const json = files.filter((f) => /\.json$/i.test(f.name));
  if (json.length === 1) return json[0];
  if (!json.length) throw new Error(`no scene file (.json) among ${files.map((f) => f.name).join(', ') || 'the files'}`);
  throw new Error(`one scene file at a time, not ${json.map((f) => f.name).join(' and ')}`);
}

/// Which of `files` ([{name}]) the scene's asset `paths` (as written in it) take, by file name:
/// `{found: [[path, file]], missing: [path]}`.
export function matchAssets(paths, files) {
  const byName = new Map(files.map((f) => [f.name, f]));
  const found = [], missing = [];
  for (const p of paths) {
    const f = byName.get(baseName(p));
    if (f) found.push([p, f]);
    else missing.push(p);
  }
  return { found, missing };
}

/// Downloads `blob` as a file called `name`.
export function download(blob, name) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob);
  a.download = name;
  a.style.display = 'none';
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 30_000);
}

/// Downloads the session as a scene file named after the scene and the simulated time.
export async function saveScene(app) {
  let text;
  try {
    text = await app.session.saveScene();
  } catch (e) {
    toast(`Cannot save the scene: ${e.message}`);
    return;
  }
  const name = `${fileStem(app.session.scene.name, app.simTime)}.json`;
  download(new Blob([text], { type: 'application/json' }), name);
  const files = await app.session.assetPaths(text);
  toast(`Saved ${name}: \`mpm run\` runs it${files.length ? `, with ${files.join(', ')} beside it (in scenes/)` : ''}.`);
}

/// Opens a scene file with the files dropped alongside (`files`: File objects); shows what
/// went wrong on the page. Resolves to whether the scene opened.
export async function openFiles(app, files) {
  let name = files[0]?.name ?? 'the file';
  const fail = (msg) => {
    banner('open', 'bad', `Cannot open ${name}: ${msg}`, { label: 'Close', run: () => banner('open') });
    return false;
  };
  try {
    const file = sceneFileOf(files);
    name = file.name;
    const text = await file.text();
    let paths = [];
    try {
      paths = await app.session.assetPaths(text);
    } catch (e) {
      return fail(e.message); // not a scene: the solver names the field
    }
    const { found, missing } = matchAssets(paths, files);
    const assets = await Promise.all(found.map(async ([p, f]) => [p, await f.text()]));
    const absent = [];
    for (const p of missing) {
      if (SHIPPED.includes(baseName(p))) assets.push([p, await fetchText(`scenes/${baseName(p)}`)]);
      else absent.push(p);
    }
    if (absent.length)
      return fail(`it references ${absent.join(', ')}: open ${absent.length > 1 ? 'them' : 'it'} together with the scene file (or drop them on the view with it)`);
    const error = await app.openScene(name, { text, assets: assets.length ? JSON.stringify(Object.fromEntries(assets)) : null });
    return error ? fail(error) : true;
  } catch (e) {
    return fail(e.message);
  }
}

/// Wires Save scene, Open scene (a file picker) and dropping files on the view.
export function setupFiles(app, stage) {
  const input = document.getElementById('open-file');
  document.getElementById('save').addEventListener('click', () => saveScene(app));
  document.getElementById('open').addEventListener('click', () => input.click());
  input.addEventListener('change', async () => {
    const files = [...input.files];
    input.value = '';
    if (files.length) await openFiles(app, files);
  });
  const over = (on) => stage.classList.toggle('drop-target', on);
  const hasFiles = (e) => [...(e.dataTransfer?.types ?? [])].includes('Files');
  // Files dropped beside the view do nothing (rather than the browser leaving the page for them).
  for (const type of ['dragover', 'drop'])
    window.addEventListener(type, (e) => {
      if (!hasFiles(e) || stage.contains(e.target)) return;
      e.preventDefault();
      e.dataTransfer.dropEffect = 'none';
    });
  stage.addEventListener('dragover', (e) => {
    if (!hasFiles(e)) return;
    e.preventDefault();
    e.dataTransfer.dropEffect = 'copy';
    over(true);
  });
  stage.addEventListener('dragleave', (e) => { if (e.target === stage || !stage.contains(e.relatedTarget)) over(false); });
  stage.addEventListener('drop', (e) => {
    e.preventDefault();
    over(false);
    const files = [...(e.dataTransfer?.files ?? [])];
    if (files.length) openFiles(app, files);
  });
}
