// The page state in the URL hash, so that a link reproduces a demo exactly:
// #scene=column_collapse&dim=3&colour=speed&object=bunny&material=drucker_prager&time=1
//  &drucker_prager.friction_angle=25&gravity=9.81
// Parameters keep the order in which they were set (ψ ≤ φ checks depend on it).

const VIEW_KEYS = ['scene', 'dim', 'colour', 'object', 'material', 'time', 'size'];

export function readHash(hash = location.hash) {
  const q = new URLSearchParams(hash.replace(/^#/, ''));
  const view = {};
  const params = [];
  for (const [k, v] of q) {
    if (VIEW_KEYS.includes(k)) view[k] = v;
    else if (/^[a-z_]+(\.[a-z_]+)?$/.test(k)) params.push([k, Number(v)]);
  }
  return { view, params };
}

export function writeHash(view, params) {
  const q = new URLSearchParams();
  for (const k of VIEW_KEYS) if (view[k] !== undefined && view[k] !== null && view[k] !== '') q.set(k, view[k]);
  for (const [k, v] of params) q.append(k, String(+v.toPrecision(6)));
  const hash = `#${q.toString()}`;
  if (hash !== location.hash) history.replaceState(null, '', hash);
  return hash;
}
