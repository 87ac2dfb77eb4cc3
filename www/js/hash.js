// The page state in the URL hash, so that a link reproduces a demo exactly:
// #scene=column_collapse&dim=3&colour=speed&object=bunny&material=drucker_prager&time=1&sleep=0
//  &quality=live&drucker_prager.friction_angle=25&gravity=9.81&drop=0.0412:ball:elastic:0.25:0.8,0.55,0.5
//  &pour=1.25:drucker_prager:0.00236:2.0004:1,0.4,0.5
// (or #lesson=friction_angle&… for a lesson of lessons/, whose scene it is).
// The view settings (`sleep=0` when material at rest is stepped, not put to sleep; on when
// absent, the page's default), then the session the solver records (`Playground::session`): the quality
// level the scene is sampled at, parameters in the order they were set (ψ ≤ φ checks depend on it), `cleared=1` when the scene's own
// bodies were removed with Clear, each body dropped by a click as a `drop` entry, in the
// order they were dropped:
//   drop=TIME:OBJECT:MATERIAL:SIZE:X,Y[,Z][:VX,VY[,VZ]]
// and each pour (the Pour tool, held on the floor) as a `pour` entry, in the order they began:
//   pour=TIME:MATERIAL:RATE:DURATION:X,Y[,Z]
// TIME is the simulated time (s) of the drop or the pour's start, counted from the start of
// the scene or from the Clear; OBJECT one of bunny, ball, box; MATERIAL the preset (elastic,
// von_mises, drucker_prager, mohr_coulomb; a pour's is sand); SIZE (m) and the centre (m) as
// given to addObject; the velocity (m/s) is left out when zero. RATE is the volume poured per
// second (m³/s, in 2D m²/s), DURATION how long it poured (s; while it pours, so far) and X,Y[,Z]
// the centre of the spout's exit (m), as `Playground::session` records them. The entries are
// written unescaped (`:` and `,` are allowed in a fragment) to keep links short. Pure (tested
// under `node --test`) but for `writeHash`.

const VIEW_KEYS = ['lesson', 'scene', 'dim', 'colour', 'object', 'material', 'time', 'size', 'sleep'];
/// The values a view entry may take (the page's menus); `object`, `material` and `quality`
/// come from the solver (`readHash`'s `choices`). A link with another value has it named.
export const VIEW_CHOICES = {
  dim: ['2', '3'],
  colour: ['body', 'speed', 'pressure', 'plastic_strain', 'yield', 'sleeping'],
  time: ['1', '0.5', '0.25', '0.1'],
};
const NUMBER = /^-?\d+(\.\d+)?(e[-+]?\d+)?$/;
/// A material parameter of one body: `bodies[i].<model>.<field>` (captures `<model>.<field>`).
const BODY_PARAM = /^bodies\[\d+\]\.(.+)$/;

/// The state of `hash`: { view, session: { quality, params, cleared, drops, pours }, errors } (no
/// `quality` when the hash names none). `names` are the
/// parameter names (the solver's table); without them every `name` or `model.field` key counts
/// as a parameter. `choices` adds the values allowed for `object`, `material` and `quality`
/// (to VIEW_CHOICES'). A malformed or unknown entry, or a value not allowed, is left out, with
/// a message naming it and what is allowed in `errors` (never an exception).
export function readHash(hash, names, choices = {}) {
  const allowed = { ...VIEW_CHOICES, ...choices };
  const q = new URLSearchParams(hash.replace(/^#/, ''));
  const view = {};
  const params = [];
  const drops = [];
  const pours = [];
  const errors = [];
  let cleared = false, quality;
  const isParam = names
    ? (k) => names.includes(k) || ((m) => !!m && m[1].includes('.') && names.includes(m[1]))(k.match(BODY_PARAM))
    : (k) => /^(bodies\[\d+\]\.)?[a-z_]+(\.[a-z_]+)?$/.test(k);
  for (const [k, v] of q) {
    if (k === 'sleep' && v !== '0' && v !== '1') errors.push(`sleep=${v}: 0 (material at rest is stepped) or 1 (it sleeps)`);
    else if (allowed[k] && !allowed[k].includes(v)) errors.push(`${k}=${v}: not one of ${allowed[k].join(', ')}`);
    else if (k === 'size' && !(NUMBER.test(v) && Number(v) > 0 && Number.isFinite(Number(v)))) errors.push(`size=${v}: not a size in metres`);
    else if ((k === 'scene' || k === 'lesson') && !v) errors.push(`${k}=: names none`);
    else if (VIEW_KEYS.includes(k)) view[k] = v;
    else if (k === 'drop') {
      try {
        drops.push(parseDrop(v));
      } catch (e) {
        errors.push(`drop=${v}: ${e.message}`);
      }
    } else if (k === 'pour') {
      try {
        pours.push(parsePour(v));
      } catch (e) {
        errors.push(`pour=${v}: ${e.message}`);
      }
    } else if (k === 'cleared') cleared = v === '1';
    else if (k === 'quality') quality = v;
    else if (isParam(k)) {
      if (NUMBER.test(v) && Number.isFinite(Number(v))) params.push([k, Number(v)]);
      else errors.push(`${k}=${v}: not a number`);
    } else errors.push(`${k}=${v}: not a setting of the page`);
  }
  const session = { params, cleared, drops, pours };
  if (quality !== undefined) session.quality = quality;
  return { view, session, errors };
}

/// A `drop` entry: { t, object, material, size, centre, velocity }; throws on a malformed one.
export function parseDrop(text) {
  const expected = 'expected TIME:OBJECT:MATERIAL:SIZE:X,Y[,Z][:VX,VY[,VZ]]';
  const parts = text.split(':');
  if (parts.length < 5 || parts.length > 6) throw new Error(`${parts.length} fields, ${expected}`);
  const [time, object, material, size, centre, velocity] = parts;
  const number = (what, s) => {
    if (!NUMBER.test(s) || !Number.isFinite(Number(s))) throw new Error(`${what} “${s}” is not a number; ${expected}`);
    return Number(s);
  };
  const vector = (what, s) => {
    const v = s.split(',').map((x) => number(what, x));
    if (v.length < 2 || v.length > 3) throw new Error(`the ${what} needs 2 or 3 components, not ${v.length}; ${expected}`);
    return v;
  };
  for (const [what, s] of [['object', object], ['material', material]])
    if (!/^[a-z_]+$/.test(s)) throw new Error(`${what} “${s}” is not a name; ${expected}`);
  const drop = {
    t: number('time', time),
    object,
    material,
    size: number('size', size),
    centre: vector('centre', centre),
  };
  if (drop.t < 0) throw new Error(`time ${time} is negative`);
  drop.velocity = velocity === undefined ? drop.centre.map(() => 0) : vector('velocity', velocity);
  if (drop.velocity.length !== drop.centre.length)
    throw new Error(`the centre has ${drop.centre.length} components, the velocity ${drop.velocity.length}`);
  return drop;
}

/// A `pour` entry: { t, material, rate, duration, spout }; throws on a malformed one.
export function parsePour(text) {
  const expected = 'expected TIME:MATERIAL:RATE:DURATION:X,Y[,Z]';
  const parts = text.split(':');
  if (parts.length !== 5) throw new Error(`${parts.length} fields, ${expected}`);
  const [time, material, rate, duration, spout] = parts;
  const number = (what, s) => {
    if (!NUMBER.test(s) || !Number.isFinite(Number(s))) throw new Error(`${what} “${s}” is not a number; ${expected}`);
    return Number(s);
  };
  if (!/^[a-z_]+$/.test(material)) throw new Error(`material “${material}” is not a name; ${expected}`);
  const pour = {
    t: number('time', time),
    material,
    rate: number('rate', rate),
    duration: number('duration', duration),
    spout: spout.split(',').map((x) => number('spout', x)),
  };
  if (pour.spout.length < 2 || pour.spout.length > 3)
    throw new Error(`the spout needs 2 or 3 components, not ${pour.spout.length}; ${expected}`);
  if (pour.t < 0) throw new Error(`time ${time} is negative`);
  if (!(pour.duration > 0)) throw new Error(`duration ${duration} is not positive`);
  return pour;
}

/// The `pour` entry of a pour (see the top of the file).
export function formatPour(p) {
  const n = (x) => String(+x);
  return [n(p.t), p.material, n(p.rate), n(p.duration), p.spout.map(n).join(',')].join(':');
}

/// The `drop` entry of a drop (see the top of the file).
export function formatDrop(d) {
  const n = (x) => String(+x);
  const fields = [n(d.t), d.object, d.material, n(d.size), d.centre.map(n).join(',')];
  if (d.velocity.some((v) => v !== 0)) fields.push(d.velocity.map(n).join(','));
  return fields.join(':');
}

/// The hash of view settings `view` and session `{ quality, params, cleared, drops, pours }`.
export function formatHash(view, { quality, params = [], cleared = false, drops = [], pours = [] } = {}) {
  const q = new URLSearchParams();
  for (const k of VIEW_KEYS) if (view[k] !== undefined && view[k] !== null && view[k] !== '') q.set(k, view[k]);
  if (quality) q.set('quality', quality);
  for (const [k, v] of params) q.append(k, String(+v.toPrecision(6)));
  if (cleared) q.set('cleared', '1');
  const entries = [q.toString(), ...drops.map((d) => `drop=${formatDrop(d)}`), ...pours.map((p) => `pour=${formatPour(p)}`)].filter((s) => s);
  return `#${entries.join('&')}`;
}

/// Puts the state in the address bar (without a history entry); returns the hash.
export function writeHash(view, session) {
  const hash = formatHash(view, session);
  if (hash !== location.hash) history.replaceState(null, '', hash);
  return hash;
}
