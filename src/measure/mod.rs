//! Measures of a deposit: the slope of a heap's flanks, the run-out of a collapsed column from
//! its initial footprint, and the angle and length between points picked by hand.
//!
//! This is the one place these measures are written: the validation cases, the CLI's run
//! summary and the page's readouts (through the wasm layer) all call them, so an engineer and
//! a class get the same number for the same frame. Everything here works on plain f64
//! coordinates (a particle at `(x, y)` in 2D; in 3D a heap is measured on its radial profile
//! `(r, y)` about its axis), lengths in metres and angles in degrees.
//!
//! * **Flank angle** ([`heap`], [`flank_angles`]): the free surface is the highest particle
//!   (plus half a particle spacing) in each column of width `bin`; each flank's slope is the
//!   least-squares slope of the surface over the columns between 20 % and 80 % of the
//!   deposit's height, on either side of its peak.
//! * **Run-out** ([`plane_runout`], [`radial_runout`]): the initial footprint is the extent
//!   of the particles at the start (each reaching half a spacing beyond its centre); the
//!   deposit's front along a ray ends at the first gap wider than two spacings
//!   ([`deposit_front`]); the run-out is how far the front lies beyond the footprint.
//!   Read where the deposit is one grain thick ([`runout_at_thickness`], [`GRAIN`]), it is
//!   the run-out the experiments report and a grid's thin tail does not move it.
//! * **By hand** ([`length`], [`inclination`], [`angle_at`]): what a ruler and a protractor
//!   read between dragged points.

mod density;
pub use density::{Gaps, interior_gaps};

use crate::math::Dim;
use crate::sim::{AnySimulation, Simulation};

/// Least-squares slope of y(x) (NaN with fewer than two distinct x).
pub fn slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    sxy / sxx
}

/// The share of the deposit's height above which a column of the surface enters a flank's fit.
pub const FIT_FROM: f64 = 0.2;
/// The share of the deposit's height below which a column of the surface enters a flank's fit.
pub const FIT_TO: f64 = 0.8;

/// One flank of a heap: its angle to the horizontal and the fitted line, drawn between the
/// first and the last column of the fit (`from` nearer the peak's side with the smaller x).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Flank {
    /// Angle of the fitted slope to the horizontal (degrees, 0–90).
    pub angle: f64,
    /// The fitted line at the first and the last column of the fit: `[x, y]`.
    pub from: [f64; 2],
    pub to: [f64; 2],
}

/// A heap's free surface measured column by column: its height, where its peak stands and
/// its two flanks (left, right; `None` when fewer than two columns fall in the fit band).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Heap {
    /// Height of the highest column of the surface (m).
    pub height: f64,
    /// The centre of the highest column (m).
    pub peak: f64,
    pub flanks: [Option<Flank>; 2],
}

/// The surface and flanks of a heap of particles (spacing `s`) over the columns of width
/// `bin` that tile `[origin, origin + width]` (a particle outside goes to the nearest end
/// column). See the module's documentation for the fit.
pub fn heap(points: &[(f64, f64)], s: f64, bin: f64, origin: f64, width: f64) -> Heap {
    let nbins = ((width / bin).round() as usize).max(1);
    let mut top = vec![f64::NAN; nbins];
    for &(x, y) in points {
        let b = (((x - origin) / bin) as usize).min(nbins - 1);
        if top[b].is_nan() || y + 0.5 * s > top[b] {
            top[b] = y + 0.5 * s;
        }
    }
    let height = top
        .iter()
        .cloned()
        .filter(|v| !v.is_nan())
        .fold(0.0, f64::max);
    let peak = top.iter().position(|&v| v == height).unwrap_or(0);
    let centre = |b: usize| origin + (b as f64 + 0.5) * bin;
    let mut flanks = [None, None];
    for (k, range) in [(0..peak), (peak + 1..nbins)].into_iter().enumerate() {
        let (xs, ys): (Vec<f64>, Vec<f64>) = range
            .filter(|&b| !top[b].is_nan() && top[b] > FIT_FROM * height && top[b] < FIT_TO * height)
            .map(|b| (centre(b), top[b]))
            .unzip();
        if xs.len() >= 2 {
            let m = slope(&xs, &ys);
            let (mx, my) = (
                xs.iter().sum::<f64>() / xs.len() as f64,
                ys.iter().sum::<f64>() / ys.len() as f64,
            );
            let at = |x: f64| [x, my + m * (x - mx)];
            flanks[k] = Some(Flank {
                angle: m.abs().atan().to_degrees(),
                from: at(xs[0]),
                to: at(xs[xs.len() - 1]),
            });
        }
    }
    Heap {
        height,
        peak: centre(peak),
        flanks,
    }
}

/// The height of a heap of particles (spacing `s`) and the slope angles (degrees) of its two
/// flanks over columns of width `bin` tiling `[0, width]`: [`heap`], with NaN for a flank
/// that cannot be fitted.
pub fn flank_angles(points: &[(f64, f64)], s: f64, bin: f64, width: f64) -> (f64, [f64; 2]) {
    let h = heap(points, s, bin, 0.0, width);
    let angle = |f: Option<Flank>| f.map_or(f64::NAN, |f| f.angle);
    (h.height, [angle(h.flanks[0]), angle(h.flanks[1])])
}

/// The centroid `(x, z)` of points given as `[x, y, z]`: the axis of a 3D heap.
pub fn axis(points: &[[f64; 3]]) -> [f64; 2] {
    let n = points.len().max(1) as f64;
    [
        points.iter().map(|p| p[0]).sum::<f64>() / n,
        points.iter().map(|p| p[2]).sum::<f64>() / n,
    ]
}

/// The radial profile `(r, y)` of points `[x, y, z]` about the vertical axis through
/// `centre` (`[x, z]`).
pub fn radial_profile(points: &[[f64; 3]], centre: [f64; 2]) -> Vec<(f64, f64)> {
    points
        .iter()
        .map(|p| ((p[0] - centre[0]).hypot(p[2] - centre[1]), p[1]))
        .collect()
}

/// The flank of a 3D heap (spacing `s`) on its radial profile about `centre` (`[x, z]`),
/// with columns (rings) of width `bin` out to the farthest particle: the outer flank of the
/// profile's [`heap`]. The flank's `x` coordinates are radii.
pub fn radial_heap(points: &[[f64; 3]], s: f64, bin: f64, centre: [f64; 2]) -> Heap {
    let profile = radial_profile(points, centre);
    let reach = profile.iter().map(|p| p.0).fold(0.0, f64::max) + bin;
    let mut h = heap(&profile, s, bin, 0.0, reach);
    // a peak off the axis (a ring-shaped deposit) leaves an inner flank; a heap has one
    // flank, running outwards
    h.flanks[0] = None;
    h
}

/// The end of a deposit along a ray: `d` holds the distances of the particles from the
/// centre (any order); the deposit ends at the first gap wider than two particle spacings
/// `s` beyond `from` (gaps nearer the centre are ignored: an axisymmetric run's narrow
/// sectors hold few particles near the axis), and the last particle stands for half a
/// spacing of material beyond its centre.
pub fn deposit_front(mut d: Vec<f64>, s: f64, from: f64) -> f64 {
    d.sort_by(|a, b| a.total_cmp(b));
    let mut end = d.first().copied().unwrap_or(0.0);
    for w in d.windows(2) {
        if w[1] - w[0] > 2.0 * s && w[0] >= from {
            break;
        }
        end = w[1];
    }
    end + 0.5 * s
}

/// The thickness at which a deposit's run-out is read: one grain, 2 mm (the aluminium rods of
/// Bui et al. 2008, and the coarse sand of the laboratory collapses), used for every case.
pub const GRAIN: f64 = 0.002;

/// Where a deposit thins to `thickness` along a ray: `points` are the particles as
/// `(d, y)`, their distance from the column's axis (or back wall, or a 3D heap's axis) and
/// their height above the floor (spacing `s`). The surface is that of [`heap`] in columns
/// of width `bin` from d = 0 (the highest particle plus half a spacing; an empty column is
/// 0 thick); stepping out from the column holding `from` (the footprint's edge), the
/// run-out is where the surface first drops below `thickness`, interpolated linearly between
/// the centres of the last column at least that thick and the first thinner one, and never
/// beyond the last particle before a gap ([`deposit_front`]). A deposit thinner than
/// `thickness` at `from` ends there. On a grid whose particle rows are thicker than
/// `thickness`, this reads the last column holding a particle.
pub fn runout_at_thickness(
    points: &[(f64, f64)],
    s: f64,
    bin: f64,
    from: f64,
    thickness: f64,
) -> f64 {
    let front = deposit_front(
        points.iter().map(|p| p.0).filter(|&d| d >= 0.0).collect(),
        s,
        from,
    );
    let nbins = ((front / bin).ceil() as usize + 2).max(1);
    let mut top = vec![0.0f64; nbins];
    for &(d, y) in points {
        if d >= 0.0 && d < front {
            let b = ((d / bin) as usize).min(nbins - 1);
            top[b] = top[b].max(y + 0.5 * s);
        }
    }
    let centre = |b: usize| (b as f64 + 0.5) * bin;
    let first = ((from.max(0.0) / bin) as usize).min(nbins - 1);
    if top[first] < thickness {
        return from;
    }
    let end = (first + 1..nbins)
        .find(|&b| top[b] < thickness)
        .map_or(front, |b| {
            let (a, z) = (top[b - 1], top[b]);
            centre(b - 1) + (a - thickness) / (a - z) * bin
        });
    end.min(front)
}

/// The edge of a deposit along a ray: `d` holds the distances of the particles from the axis
/// (any order), each particle standing for the material `amount` gives at its distance (an
/// area s² in a plane deposit, a volume s³ in an axisymmetric one), `band(r0, r1)` is the
/// floor area between distances r0 and r1 (its length in a plane, an annulus's area about an
/// axis). The thickness at r is the material within half a window (`window`, at least two
/// spacings `s`) of r over the window's floor area; the edge is the first r, stepping out from
/// the axis by an eighth of a spacing, where it drops below `min_thickness`.
pub fn deposit_edge(
    mut d: Vec<f64>,
    s: f64,
    amount: f64,
    band: impl Fn(f64, f64) -> f64,
    window: f64,
    min_thickness: f64,
) -> f64 {
    d.sort_by(|a, b| a.total_cmp(b));
    let half = 0.5 * window.max(2.0 * s);
    let step = s / 8.0;
    let (mut lo, mut hi) = (0, 0); // the particles in [r − half, r + half)
    let mut r = 0.0;
    loop {
        while hi < d.len() && d[hi] < r + half {
            hi += 1;
        }
        while lo < hi && d[lo] < r - half {
            lo += 1;
        }
        let thickness = (hi - lo) as f64 * amount / band((r - half).max(0.0), r + half);
        if thickness < min_thickness || lo == d.len() {
            return r;
        }
        r += step;
    }
}

/// A plane column's centre x_c and half-width L0 from the x coordinates of its particles
/// (spacing `s`: each particle's material reaches half a spacing beyond its centre).
pub fn column_extent(xs: impl Iterator<Item = f64> + Clone, s: f64) -> (f64, f64) {
    let lo = xs.clone().fold(f64::INFINITY, f64::min) - 0.5 * s;
    let hi = xs.fold(f64::NEG_INFINITY, f64::max) + 0.5 * s;
    (0.5 * (lo + hi), 0.5 * (hi - lo))
}

/// The run-out of a deposit from its initial footprint.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Runout {
    /// The footprint's centre: `x` in 2D, `[x, z]` in 3D (then `centre[1]` is z).
    pub centre: [f64; 2],
    /// The footprint's half-width L0 (2D) or mean reach R0 over the sectors (3D) (m).
    pub footprint: f64,
    /// The deposit's front: in 2D the left and right ends (x, m); in 3D the mean front radius
    /// over the azimuthal sectors (twice).
    pub front: [f64; 2],
    /// How far the front lies beyond the footprint (m): left and right in 2D; the mean over
    /// the sectors and the largest in 3D.
    pub runout: [f64; 2],
}

/// The run-out of a plane deposit: `initial` and `current` are the x coordinates of the same
/// body's particles at the start and now (spacing `s`). The footprint is [`column_extent`]
/// of the start; each side's front is the [`deposit_front`] of the particles on that side of
/// the footprint's centre.
pub fn plane_runout(initial: &[f64], current: &[f64], s: f64) -> Runout {
    let (xc, l0) = column_extent(initial.iter().copied(), s);
    let front = |sign: f64| {
        deposit_front(
            current
                .iter()
                .map(|&x| sign * (x - xc))
                .filter(|&d| d > 0.0)
                .collect(),
            s,
            0.0,
        )
    };
    let (left, right) = (front(-1.0), front(1.0));
    Runout {
        centre: [xc, 0.0],
        footprint: l0,
        front: [xc - left, xc + right],
        runout: [left - l0, right - l0],
    }
}

/// The run-out of a 3D deposit about the vertical axis through the centroid of its initial
/// footprint: `initial` and `current` are the same body's particles `[x, y, z]` at the start
/// and now (spacing `s`), split into `sectors` azimuthal sectors. In each sector the
/// footprint reaches the farthest initial particle plus half a spacing (R0 of that
/// direction), the front is the [`deposit_front`] of the current particles beyond it, and the
/// run-out is the front less R0; the result holds the means over the sectors and the largest
/// run-out (a square footprint has a longer reach along its diagonals than a round one, and
/// each direction is measured from its own).
pub fn radial_runout(initial: &[[f64; 3]], current: &[[f64; 3]], s: f64, sectors: usize) -> Runout {
    let centre = axis(initial);
    let sectors = sectors.max(1);
    let split = |points: &[[f64; 3]]| {
        let mut rays = vec![Vec::new(); sectors];
        for p in points {
            let (dx, dz) = (p[0] - centre[0], p[2] - centre[1]);
            let k = ((dz.atan2(dx) / std::f64::consts::TAU + 0.5) * sectors as f64) as usize;
            rays[k.min(sectors - 1)].push(dx.hypot(dz));
        }
        rays
    };
    let (start, now) = (split(initial), split(current));
    let (mut r0, mut front, mut far, mut n) = (0.0, 0.0, f64::NEG_INFINITY, 0.0);
    for (a, b) in start.into_iter().zip(now) {
        if a.is_empty() || b.is_empty() {
            continue;
        }
        let reach = a.iter().copied().fold(0.0, f64::max) + 0.5 * s;
        let end = deposit_front(b, s, reach);
        r0 += reach;
        front += end;
        far = far.max(end - reach);
        n += 1.0;
    }
    let n = f64::max(n, 1.0);
    let (r0, front) = (r0 / n, front / n);
    Runout {
        centre,
        footprint: r0,
        front: [front, front],
        runout: [front - r0, far.max(front - r0)],
    }
}

/// The principal stresses of a stress given by its components (2D plane strain: xx, yy, zz,
/// xy; 3D: xx, yy, zz, xy, xz, yz; tension positive), as compression-positive values sorted
/// from the largest: the centres and radii of the Mohr circles follow. In 2D the first two are
/// the in-plane principal stresses (major, minor) and the third is −σ_zz, the out-of-plane
/// one.
pub fn principal_stresses(c: &[f64]) -> Vec<f64> {
    if c.len() == 4 {
        let (m, r) = (0.5 * (c[0] + c[1]), (0.5 * (c[0] - c[1])).hypot(c[3]));
        return vec![-(m - r), -(m + r), -c[2]];
    }
    // 3D: the eigenvalues of a symmetric 3×3 matrix by the trigonometric closed form
    let (xx, yy, zz, xy, xz, yz) = (c[0], c[1], c[2], c[3], c[4], c[5]);
    let q = (xx + yy + zz) / 3.0;
    let off = xy * xy + xz * xz + yz * yz;
    let mut e = if off == 0.0 {
        vec![xx, yy, zz]
    } else {
        let p2 = (xx - q).powi(2) + (yy - q).powi(2) + (zz - q).powi(2) + 2.0 * off;
        let p = (p2 / 6.0).sqrt();
        let (a, b, d) = ((xx - q) / p, (yy - q) / p, (zz - q) / p);
        let (e_, f, g) = (xy / p, xz / p, yz / p);
        let det = a * (b * d - g * g) - e_ * (e_ * d - g * f) + f * (e_ * g - b * f);
        let phi = (det / 2.0).clamp(-1.0, 1.0).acos() / 3.0;
        let third = 2.0 * std::f64::consts::PI / 3.0;
        vec![
            q + 2.0 * p * phi.cos(),
            q + 2.0 * p * (phi + third).cos(),
            q + 2.0 * p * (phi + 2.0 * third).cos(),
        ]
    };
    for x in &mut e {
        *x = -*x;
    }
    e.sort_by(|a, b| b.total_cmp(a));
    e
}

/// The length between two points (m): what a ruler reads.
pub fn length(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (q - p).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// The angle (degrees, 0–90) of the line from `a` to `b` to the horizontal (the plane
/// normal to y, the second coordinate): what a protractor laid on a slope reads.
pub fn inclination(a: &[f64], b: &[f64]) -> f64 {
    let rise = (b[1] - a[1]).abs();
    let run = a
        .iter()
        .zip(b)
        .enumerate()
        .filter(|(k, _)| *k != 1)
        .map(|(_, (p, q))| (q - p).powi(2))
        .sum::<f64>()
        .sqrt();
    rise.atan2(run).to_degrees()
}

/// The angle (degrees, 0–180) at `vertex` between the rays to `a` and to `b`; NaN when either
/// ray has no length.
pub fn angle_at(vertex: &[f64], a: &[f64], b: &[f64]) -> f64 {
    let u: Vec<f64> = a.iter().zip(vertex).map(|(p, v)| p - v).collect();
    let w: Vec<f64> = b.iter().zip(vertex).map(|(p, v)| p - v).collect();
    let norm = |v: &[f64]| v.iter().map(|c| c * c).sum::<f64>().sqrt();
    let (lu, lw) = (norm(&u), norm(&w));
    if lu == 0.0 || lw == 0.0 {
        return f64::NAN;
    }
    let c = u.iter().zip(&w).map(|(p, q)| p * q).sum::<f64>() / (lu * lw);
    c.clamp(-1.0, 1.0).acos().to_degrees()
}

/// The positions particles had when they first entered the simulation, by particle id: the
/// initial footprints run-outs are measured from. [`Footprints::update`] records the
/// particles that entered since its last call (a dropped body's footprint is where it was
/// dropped); a front end clears it when it clears or rebuilds the simulation.
#[derive(Clone, Debug, Default)]
pub struct Footprints {
    /// By id; NaN for an id not seen yet.
    start: Vec<[f64; 3]>,
    /// The simulation's issued ids at the last update: no particle entered while it holds,
    /// so a frame without a drop costs no pass over the particles.
    issued: u32,
}

impl Footprints {
    /// Records the particles of `sim` not seen before at their current positions.
    pub fn update<D: Dim>(&mut self, sim: &Simulation<D>) {
        if sim.ids_issued() == self.issued {
            return;
        }
        self.issued = sim.ids_issued();
        let p = sim.particles();
        for i in 0..p.len() {
            let id = p.id[i] as usize;
            if id >= self.start.len() {
                self.start.resize(id + 1, [f64::NAN; 3]);
            }
            if self.start[id][0].is_nan() {
                self.start[id] = point::<D>(&p.x[i]);
            }
        }
    }
    /// [`Footprints::update`] for a simulation of either dimension.
    pub fn update_any(&mut self, sim: &AnySimulation) {
        match sim {
            AnySimulation::D2(s) => self.update(s),
            AnySimulation::D3(s) => self.update(s),
        }
    }
    /// Forgets every position (the simulation was cleared or rebuilt).
    pub fn clear(&mut self) {
        self.start.clear();
        self.issued = 0;
    }
    /// The recorded start of particle `id`, if any.
    pub fn start(&self, id: u32) -> Option<[f64; 3]> {
        self.start
            .get(id as usize)
            .filter(|x| !x[0].is_nan())
            .copied()
    }
}

fn point<D: Dim>(x: &D::Vector) -> [f64; 3] {
    let mut r = [0.0; 3];
    for (a, c) in r.iter_mut().enumerate().take(D::DIM) {
        *c = x[a] as f64;
    }
    r
}

/// How many azimuthal sectors a 3D deposit's front is measured over.
pub const SECTORS: usize = 16;

/// The measures of one sand body as it stands: its heap's flanks (in 3D on the radial profile
/// about the body's centroid, the flank's x coordinates then radii) and its run-out from its
/// initial footprint.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Deposit {
    /// The body's index in the simulation.
    pub body: usize,
    pub name: String,
    /// The particle spacing the measures use (m).
    pub spacing: f64,
    /// In 3D the axis `[x, z]` the heap's radial profile is taken about (the body's
    /// centroid); `[0, 0]` in 2D.
    pub axis: [f64; 2],
    pub heap: Heap,
    /// `None` for a body whose start was not recorded, and for a poured body.
    pub runout: Option<Runout>,
    /// Whether the body was poured from a spout (`bodies[].pour`): built grain by grain with
    /// little momentum, its heap stands at the sand's angle of repose.
    #[serde(default)]
    pub poured: bool,
    /// Whether the body started as a column held by other bodies against its free sides
    /// ([`held`]): released as they move away (walls lifted from around it), not all at once,
    /// so no column collapse.
    #[serde(default)]
    pub held: bool,
    /// Whether the body started as a heap at rest (`shape.cone`) no steeper than its angle of
    /// repose: it stands as built. A heap built steeper fails as a whole, a collapse.
    #[serde(default)]
    pub heaped: bool,
    /// The material model's scene-file name.
    pub model: String,
    /// The sand's friction angle φ (degrees).
    pub friction_angle: f64,
    /// The angle of repose (degrees) a heap of it is judged against, in 2D and 3D alike
    /// ([`crate::material::Friction::repose`]): φ_ps of the start–stop Drucker–Prager cone,
    /// Davis's angle of Mohr–Coulomb.
    pub repose_angle: f64,
    /// When the body started as a column standing on the floor ([`column()`]): the column and
    /// where the experiments put its run-out and final height.
    pub column: Option<ColumnMarkers>,
}

/// A sand body that started as a column standing on the floor: in 2D a full rectangle
/// (free, or against one side wall: then half of a symmetric collapse), in 3D a cylinder
/// clear of the walls; with no other body against its free sides ([`held`]).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Column {
    /// Its axis: `[x, 0]` in 2D (the wall's x against a wall), `[x, z]` in 3D.
    pub centre: [f64; 2],
    /// L0, the half-width of a free column or the width of one against a wall (2D), or the
    /// radius R0 (3D) (m).
    pub half_width: f64,
    /// H0 (m).
    pub height: f64,
    /// −1 against the left wall, +1 against the right one, 0 free.
    pub wall: i32,
    /// a = H0/L0 (or H0/R0).
    pub aspect_ratio: f64,
}

/// Where the experiments put a column's deposit: the run-out (floor positions: in 2D the x
/// range `[near, far]` of each free side's front, in 3D the radius range about the axis) and
/// the final height, with the law's source and regime.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ColumnMarkers {
    pub column: Column,
    /// The aspect ratio's law ([`crate::laws::collapse_law`]).
    pub law: crate::laws::CollapseLaw,
    /// 2D: `[x_near, x_far]` for each free side (left first); 3D: one `[r_near, r_far]`.
    pub fronts: Vec<[f64; 2]>,
    /// H∞ by the law (m).
    pub height: f64,
}

/// The column `start` (the body's particles `[x, y, z]` at the start, spacing `s`) was, if it
/// was one: it stands on the floor (its lowest particle within a spacing of it) and fills its
/// bounding rectangle (2D) or cylinder (3D, clear of the walls) to 80 % (a jittered sampling
/// reaches up to half a spacing further). `domain` is the domain's size.
pub fn column(start: &[[f64; 3]], s: f64, domain: &[f64]) -> Option<Column> {
    if start.is_empty() {
        return None;
    }
    let n = start.len() as f64;
    let lo_y = start.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min) - 0.5 * s;
    let h0 = start.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max) + 0.5 * s;
    if lo_y > s || h0 <= 0.0 {
        return None;
    }
    if domain.len() == 2 {
        let lo = start.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min) - 0.5 * s;
        let hi = start.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max) + 0.5 * s;
        if n * s * s < 0.8 * (hi - lo) * h0 {
            return None;
        }
        let (left, right) = (lo < s, hi > domain[0] - s);
        let (centre, half_width, wall) = match (left, right) {
            (true, true) => return None,
            (true, false) => (0.0, hi, -1),
            (false, true) => (domain[0], domain[0] - lo, 1),
            (false, false) => (0.5 * (lo + hi), 0.5 * (hi - lo), 0),
        };
        Some(Column {
            centre: [centre, 0.0],
            half_width,
            height: h0,
            wall,
            aspect_ratio: h0 / half_width,
        })
    } else {
        let centre = axis(start);
        let reach = radial_profile(start, centre)
            .iter()
            .map(|p| p.0)
            .fold(0.0, f64::max)
            + 0.5 * s;
        let clear = centre[0] - reach > s
            && centre[0] + reach < domain[0] - s
            && centre[1] - reach > s
            && centre[1] + reach < domain[2] - s;
        let volume = n * s.powi(3);
        if !clear || volume < 0.8 * std::f64::consts::PI * reach * reach * h0 {
            return None;
        }
        // the radius of the cylinder of height H0 that holds the sampled volume (as the
        // validation's axisymmetric collapses take it): jittered particles reach further
        let r0 = (volume / (std::f64::consts::PI * h0)).sqrt();
        Some(Column {
            centre,
            half_width: r0,
            height: h0,
            wall: 0,
            aspect_ratio: h0 / r0,
        })
    }
}

/// Whether another body stood against column `c`'s free sides at the start (`others`: those
/// bodies' particles where they started; `h` the cell size, `s` the column's particle
/// spacing): a particle within a cell outside a side, below the column's top. A column held
/// between walls that are then lifted, say, is no collapse, and the laws of a released column
/// do not apply to it.
pub fn held(
    c: &Column,
    others: impl IntoIterator<Item = [f64; 3]>,
    dim: usize,
    h: f64,
    s: f64,
) -> bool {
    others.into_iter().any(|x| {
        if x[1] > c.height + h {
            return false;
        }
        let from_axis = if dim == 2 {
            (x[0] - c.centre[0]).abs()
        } else {
            (x[0] - c.centre[0]).hypot(x[2] - c.centre[1])
        };
        let gap = from_axis - c.half_width;
        gap > -0.5 * s && gap <= h
    })
}

/// The experiments' markers for column `c` in dimension `dim`.
pub fn column_markers(c: Column, dim: usize) -> ColumnMarkers {
    let law = crate::laws::collapse_law(dim, c.aspect_ratio);
    let [near, far] = law.runout.map(|r| c.half_width * (1.0 + r));
    let x = c.centre[0];
    let fronts = match (dim, c.wall) {
        (3, _) => vec![[near, far]],
        (_, -1) => vec![[x + near, x + far]],
        (_, 1) => vec![[x - near, x - far]],
        _ => vec![[x - near, x - far], [x + near, x + far]],
    };
    ColumnMarkers {
        height: c.height * law.height,
        column: c,
        law,
        fronts,
    }
}

/// The measures of every granular body present in `sim` (a material with a friction angle,
/// [`crate::material::Behaviour::Granular`]) that holds particles (a poured body has no
/// run-out: it enters as a stream, with no footprint; while its stream falls, the stream is
/// the surface's highest column): the surface columns
/// (rings in 3D) are a cell wide and tile the domain's width (out to the farthest particle
/// in 3D); a body's particle spacing is the cell size over its particles per cell.
pub fn deposits<D: Dim>(sim: &Simulation<D>, footprints: &Footprints) -> Vec<Deposit> {
    let p = sim.particles();
    let scene = sim.scene();
    let h = sim.cell_size();
    let mut out = Vec::new();
    for (b, body) in sim.bodies().iter().enumerate() {
        let config = &scene.bodies[b];
        let Some(friction) = config.material.behaviour().friction() else {
            continue;
        };
        let range = body.range();
        if range.is_empty() {
            continue;
        }
        let s = h / config.particles_per_cell.max(1) as f64;
        let now: Vec<[f64; 3]> = range.clone().map(|i| point::<D>(&p.x[i])).collect();
        let start: Option<Vec<[f64; 3]>> = range.map(|i| footprints.start(p.id[i])).collect();
        // a poured body enters as a stream, layer by layer: it has no footprint to run out of
        let poured = config.pour.is_some();
        let start = start.filter(|v| !v.is_empty() && !poured);
        let mut centre = [0.0; 2];
        let (heap, runout) = if D::DIM == 2 {
            let profile: Vec<(f64, f64)> = now.iter().map(|x| (x[0], x[1])).collect();
            let heap = heap(&profile, s, h, 0.0, scene.domain.size[0]);
            let runout = start.as_ref().map(|start| {
                let xs: Vec<f64> = start.iter().map(|x| x[0]).collect();
                let current: Vec<f64> = now.iter().map(|x| x[0]).collect();
                plane_runout(&xs, &current, s)
            });
            (heap, runout)
        } else {
            centre = axis(&now);
            let heap = radial_heap(&now, s, h, centre);
            let runout = start
                .as_ref()
                .map(|start| radial_runout(start, &now, s, SECTORS));
            (heap, runout)
        };
        let others = sim
            .bodies()
            .iter()
            .enumerate()
            .filter(|&(o, _)| o != b)
            .flat_map(|(_, o)| o.range())
            .filter_map(|i| footprints.start(p.id[i]));
        let standing = start
            .as_deref()
            .and_then(|start| column(start, s, &scene.domain.size));
        let contained = standing
            .as_ref()
            .is_some_and(|c| held(c, others, D::DIM, h, s));
        let column = standing
            .filter(|_| !contained)
            .map(|c| column_markers(c, D::DIM));
        out.push(Deposit {
            body: b,
            name: config.name.clone(),
            spacing: s,
            axis: centre,
            heap,
            runout,
            poured,
            held: contained,
            heaped: match config.shape {
                crate::geometry::Shape::Cone { radius, height, .. } => {
                    height.atan2(radius).to_degrees() <= friction.repose
                }
                _ => false,
            },
            model: config.material.kind().to_string(),
            friction_angle: friction.friction_angle,
            repose_angle: friction.repose,
            column,
        });
    }
    out
}

/// [`deposits`] for a simulation of either dimension.
pub fn deposits_any(sim: &AnySimulation, footprints: &Footprints) -> Vec<Deposit> {
    match sim {
        AnySimulation::D2(s) => deposits(s, footprints),
        AnySimulation::D3(s) => deposits(s, footprints),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Material;

    /// Particles on a square lattice of spacing `s` filling the region below `top(x)` over
    /// `[x0, x1]`.
    fn fill(s: f64, x0: f64, x1: f64, top: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
        let mut p = Vec::new();
        let mut x = x0 + 0.5 * s;
        while x < x1 {
            let mut y = 0.5 * s;
            while y < top(x) {
                p.push((x, y));
                y += s;
            }
            x += s;
        }
        p
    }

    /// A plane wedge H (1 − x/L) thins to a grain's thickness t at L (1 − t/H): read within
    /// the surface's resolution (half a spacing of height is s L / (2H) along the floor).
    #[test]
    fn runout_at_a_thickness_on_a_wedge() {
        let (big_h, big_l) = (0.1, 0.3);
        for (s, bin) in [(0.00125, 0.0025), (0.0025, 0.005)] {
            let wedge = fill(s, 0.0, big_l, |x| big_h * (1.0 - x / big_l));
            for t in [GRAIN, 0.01, 0.03] {
                let x = runout_at_thickness(&wedge, s, bin, 0.05, t);
                let exact = big_l * (1.0 - t / big_h);
                assert!(
                    (x - exact).abs() <= s * big_l / big_h,
                    "s = {s}, t = {t}: {x:.4} m against {exact:.4} m"
                );
            }
        }
    }

    /// A blunt deposit ends at its last particle, not where the surface line would reach the
    /// floor; a thin tail of particle rows thicker than the thickness reads to its last
    /// column; grains beyond a gap are not the deposit; a deposit already thinner than the
    /// thickness at `from` ends there.
    #[test]
    fn runout_at_a_thickness_ends_at_the_deposit() {
        let s = 0.005;
        let block = fill(s, 0.0, 0.2, |_| 0.02);
        let x = runout_at_thickness(&block, s, 0.01, 0.1, GRAIN);
        assert!((x - 0.2).abs() < 1e-9, "block: {x}");
        // one row of 5 mm particles out to 0.3 m, then a lone grain at 0.4 m
        let mut tail = fill(s, 0.0, 0.2, |_| 0.05);
        tail.extend(fill(s, 0.2, 0.3, |_| s));
        tail.push((0.4, 0.5 * s));
        let x = runout_at_thickness(&tail, s, 0.01, 0.1, GRAIN);
        assert!((x - 0.3).abs() < 1e-9, "tail: {x}");
        let thin = fill(s, 0.0, 0.2, |_| s);
        assert_eq!(runout_at_thickness(&thin, s, 0.01, 0.1, 0.01), 0.1);
    }

    #[test]
    fn slope_of_a_line() {
        let x = [0.0, 1.0, 2.0, 3.0];
        let y: Vec<f64> = x.iter().map(|x| 0.5 - 2.0 * x).collect();
        assert!((slope(&x, &y) + 2.0).abs() < 1e-12);
    }

    #[test]
    fn a_wedge_of_known_angle_in_2d() {
        // a symmetric heap with flanks at 30° and a one-sided wedge at 25°
        let s = 0.0025;
        for (theta, two) in [(30.0f64, true), (25.0, false), (40.0, true)] {
            let t = theta.to_radians().tan();
            let (peak, h) = (0.5, 0.15);
            let p = fill(s, 0.0, 1.0, |x| {
                if two || x > peak {
                    h - t * (x - peak).abs()
                } else {
                    h
                }
            });
            let m = heap(&p, s, 0.01, 0.0, 1.0);
            assert!(
                (m.height - h).abs() < 2.0 * s,
                "{theta}°: height {}",
                m.height
            );
            let right = m.flanks[1].expect("right flank");
            assert!(
                (right.angle - theta).abs() < 1.0,
                "{theta}°: right flank {:.2}°",
                right.angle
            );
            // the drawn line runs down the flank, from 80 % to 20 % of the height
            assert!(right.from[1] > right.to[1] && right.from[1] < 0.85 * h);
            if two {
                let left = m.flanks[0].expect("left flank");
                assert!((left.angle - theta).abs() < 1.0, "left {:.2}°", left.angle);
            } else {
                // a flat top: no column of the left side lies in the band
                assert!(m.flanks[0].is_none());
            }
            // the validation's form gives the same numbers
            let (height, f) = flank_angles(&p, s, 0.01, 1.0);
            assert_eq!(height, m.height);
            assert_eq!(f[1], right.angle);
        }
    }

    #[test]
    fn a_cone_of_known_angle_in_3d() {
        let s = 0.01;
        let (theta, h, c) = (32.0f64, 0.3, [0.7, 0.6]);
        let t = theta.to_radians().tan();
        let mut p = Vec::new();
        for i in 0..140 {
            for k in 0..120 {
                let (x, z) = ((i as f64 + 0.5) * s, (k as f64 + 0.5) * s);
                let top = h - t * (x - c[0]).hypot(z - c[1]);
                let mut y = 0.5 * s;
                while y < top {
                    p.push([x, y, z]);
                    y += s;
                }
            }
        }
        let centre = axis(&p);
        assert!((centre[0] - c[0]).abs() < s && (centre[1] - c[1]).abs() < s);
        let m = radial_heap(&p, s, 0.02, centre);
        let f = m.flanks[1].expect("the cone's flank");
        assert!((f.angle - theta).abs() < 1.5, "cone flank {:.2}°", f.angle);
        assert!(m.flanks[0].is_none());
        assert!(m.peak < 0.05, "peak at r = {}", m.peak);
    }

    #[test]
    fn a_box_of_known_runout_in_2d() {
        // a column over [0.4, 0.6] spreads to a layer over [0.25, 0.9]; a stray particle far
        // beyond a gap does not count
        let s = 0.005;
        let column: Vec<f64> = fill(s, 0.4, 0.6, |_| 0.3).iter().map(|p| p.0).collect();
        let mut layer: Vec<f64> = fill(s, 0.25, 0.9, |_| 0.05).iter().map(|p| p.0).collect();
        layer.push(1.2);
        let r = plane_runout(&column, &layer, s);
        assert!((r.centre[0] - 0.5).abs() < 1e-9);
        assert!((r.footprint - 0.1).abs() < 1e-9);
        assert!(
            (r.front[0] - 0.25).abs() < 1e-9,
            "left front {}",
            r.front[0]
        );
        assert!(
            (r.front[1] - 0.9).abs() < 1e-9,
            "right front {}",
            r.front[1]
        );
        assert!((r.runout[0] - 0.15).abs() < 1e-9 && (r.runout[1] - 0.3).abs() < 1e-9);
        // nothing moved: no run-out
        let still = plane_runout(&column, &column, s);
        assert!(still.runout.iter().all(|d| d.abs() < 1e-9));
    }

    #[test]
    fn a_box_of_known_runout_in_3d() {
        // a cylinder of radius 0.1 spread to a disc of radius 0.35
        let s = 0.005;
        let disc = |radius: f64, height: f64| {
            let mut p = Vec::new();
            let n = (0.8 / s) as i32;
            for i in 0..n {
                for k in 0..n {
                    let (x, z) = ((i as f64 + 0.5) * s, (k as f64 + 0.5) * s);
                    if (x - 0.4).hypot(z - 0.4) < radius {
                        let mut y = 0.5 * s;
                        while y < height {
                            p.push([x, y, z]);
                            y += s;
                        }
                    }
                }
            }
            p
        };
        let (column, layer) = (disc(0.1, 0.2), disc(0.35, 0.01));
        let r = radial_runout(&column, &layer, s, 16);
        assert!((r.footprint - 0.1).abs() < s, "R0 = {}", r.footprint);
        assert!((r.runout[0] - 0.25).abs() < 1.5 * s, "mean {}", r.runout[0]);
        assert!(r.runout[1] >= r.runout[0] && r.runout[1] - 0.25 < 1.5 * s);
    }

    #[test]
    fn deposit_edge_of_a_uniform_layer() {
        // a layer 0.02 thick out to 0.3 (plane: one particle per s² of section)
        let s = 0.005;
        let d: Vec<f64> = fill(s, 0.0, 0.3, |_| 0.02).iter().map(|p| p.0).collect();
        let edge = deposit_edge(d, s, s * s, |a, b| b - a, 0.01, 0.005);
        assert!((edge - 0.3).abs() < 0.01, "edge {edge}");
    }

    #[test]
    fn principal_stresses_in_closed_form() {
        // 2D: uniaxial compression along x rotated by 30°, and σ_zz
        let (s1, t) = (-100.0f64, 30f64.to_radians());
        let c = [
            s1 * t.cos().powi(2),
            s1 * t.sin().powi(2),
            -20.0,
            s1 * t.sin() * t.cos(),
        ];
        let p = principal_stresses(&c);
        assert!((p[0] - 100.0).abs() < 1e-9 && p[1].abs() < 1e-9 && (p[2] - 20.0).abs() < 1e-9);
        // 3D: a diagonal stress, and the same rotated about z
        let p = principal_stresses(&[-3.0, -1.0, -2.0, 0.0, 0.0, 0.0]);
        assert_eq!(p, vec![3.0, 2.0, 1.0]);
        let (a, b) = (-5.0, -1.0);
        let (c2, s2) = (t.cos(), t.sin());
        let rotated = [
            a * c2 * c2 + b * s2 * s2,
            a * s2 * s2 + b * c2 * c2,
            -2.0,
            (a - b) * s2 * c2,
            0.0,
            0.0,
        ];
        let p = principal_stresses(&rotated);
        for (x, e) in p.iter().zip([5.0, 2.0, 1.0]) {
            assert!((x - e).abs() < 1e-9, "{p:?}");
        }
        // a general one: the invariants agree
        let g = [-4.0, -1.0, -2.5, 0.7, -0.3, 1.1];
        let p = principal_stresses(&g);
        assert!((p.iter().sum::<f64>() + g[0] + g[1] + g[2]).abs() < 1e-9);
        assert!(p[0] >= p[1] && p[1] >= p[2]);
    }

    #[test]
    fn columns_are_recognised_with_their_law() {
        let s = 0.01;
        let block = |x0: f64, x1: f64, y0: f64, y1: f64| -> Vec<[f64; 3]> {
            fill(s, x0, x1, |_| y1 - y0)
                .into_iter()
                .map(|(x, y)| [x, y + y0, 0.0])
                .collect()
        };
        // a free column 0.2 wide and 0.2 high: a = 2, in the transition
        let c = column(&block(0.4, 0.6, 0.0, 0.2), s, &[1.0, 0.5]).unwrap();
        assert!((c.aspect_ratio - 2.0).abs() < 1e-9 && c.wall == 0);
        let m = column_markers(c, 2);
        assert_eq!(m.fronts.len(), 2);
        let [lo, hi] = crate::laws::lube_runout_range(2.0);
        assert!((m.fronts[1][0] - (0.5 + 0.1 * (1.0 + lo))).abs() < 1e-9);
        assert!((m.fronts[1][1] - (0.5 + 0.1 * (1.0 + hi))).abs() < 1e-9);
        assert!((m.fronts[0][1] - (0.5 - 0.1 * (1.0 + hi))).abs() < 1e-9);
        assert!((m.height - 0.2 * crate::laws::lube_height(2.0)).abs() < 1e-9);
        // against the left wall: L0 is its width, one front
        let c = column(&block(0.0, 0.2, 0.0, 0.4), s, &[2.4, 0.6]).unwrap();
        assert!(c.wall == -1 && (c.half_width - 0.2).abs() < 1e-9);
        let m = column_markers(c, 2);
        assert_eq!(m.fronts.len(), 1);
        assert!(m.fronts[0][0] > 0.2);
        // in the air, or a thin L, is no column
        assert!(column(&block(0.4, 0.6, 0.2, 0.4), s, &[1.0, 0.5]).is_none());
        let mut l = block(0.4, 0.6, 0.0, 0.05);
        l.extend(block(0.4, 0.45, 0.05, 0.4));
        assert!(column(&l, s, &[1.0, 0.5]).is_none());
        // held: a wall against a free side (within a cell, below the top); not one a cell
        // and more away, nor one above the column
        let c = column(&block(0.4, 0.6, 0.0, 0.2), s, &[1.0, 0.5]).unwrap();
        let h = 0.02;
        let wall = |x0: f64, x1: f64, y0: f64| block(x0, x1, y0, y0 + 0.24);
        assert!(held(&c, wall(0.36, 0.4, 0.0), 2, h, s));
        assert!(held(&c, wall(0.6, 0.64, 0.0), 2, h, s));
        assert!(!held(&c, wall(0.63, 0.67, 0.0), 2, h, s));
        assert!(!held(&c, wall(0.36, 0.4, 0.25), 2, h, s));
        assert!(!held(&c, std::iter::empty(), 2, h, s));
    }

    #[test]
    fn by_hand() {
        assert!((length(&[0.0, 0.0], &[3.0, 4.0]) - 5.0).abs() < 1e-12);
        assert!((inclination(&[0.0, 0.0], &[1.0, 1.0]) - 45.0).abs() < 1e-9);
        assert!((inclination(&[1.0, 1.0], &[0.0, 0.0]) - 45.0).abs() < 1e-9);
        // in 3D the run is measured in the floor's plane
        let a = inclination(&[0.0, 0.0, 0.0], &[3.0, 5.0, 4.0]);
        assert!((a - 45.0).abs() < 1e-9, "{a}");
        assert!((angle_at(&[0.0, 0.0], &[1.0, 0.0], &[0.0, 2.0]) - 90.0).abs() < 1e-9);
        let sixty = angle_at(&[0.0, 0.0], &[1.0, 0.0], &[0.5, 3f64.sqrt() / 2.0]);
        assert!((sixty - 60.0).abs() < 1e-9);
        assert!(angle_at(&[0.0, 0.0], &[0.0, 0.0], &[1.0, 0.0]).is_nan());
    }

    /// Every granular model's heap is measured, whatever the model (the registration's
    /// presets, asked only their behaviour): a 2D wedge with flanks at 30° reads 30° on both
    /// sides, has run out nowhere, and carries the angle of repose of its own yield surface
    /// (the cone's φ_ps, Mohr–Coulomb's Davis angle); a solid body beside it is not measured.
    #[test]
    fn every_granular_model_gets_its_heap_measured() {
        use crate::{BodyConfig, D2, Shape};
        let t = 30f64.to_radians().tan();
        let granular: Vec<Material> = crate::material::KINDS
            .iter()
            .map(|k| (k.preset)())
            .filter(|m| m.behaviour().friction().is_some())
            .collect();
        let kinds: Vec<&str> = granular.iter().map(|m| m.kind()).collect();
        assert_eq!(kinds, ["drucker_prager", "mohr_coulomb"]);
        for material in granular {
            let friction = material.behaviour().friction().unwrap();
            let sim = Simulation::<D2>::builder(&[1.0, 0.5], 0.01)
                .body(BodyConfig::new(
                    "block",
                    Shape::cuboid(&[0.05, 0.0], &[0.15, 0.1]),
                    Material::elastic(1e5, 0.3, 1000.0),
                ))
                .body(BodyConfig::new(
                    "heap",
                    Shape::polygon(&[[0.2, 0.0], [0.8, 0.0], [0.5, 0.3 * t]]),
                    material.clone(),
                ))
                .build()
                .unwrap();
            let mut f = Footprints::default();
            f.update(&sim);
            let d = deposits(&sim, &f);
            assert_eq!(d.len(), 1, "{}: only the sand is measured", material.kind());
            assert_eq!((d[0].body, d[0].model.as_str()), (1, material.kind()));
            for flank in &d[0].heap.flanks {
                let a = flank.as_ref().expect("two flanks").angle;
                assert!((a - 30.0).abs() < 1.5, "{}: {a}°", material.kind());
            }
            let r = d[0].runout.as_ref().unwrap();
            assert!(r.runout.iter().all(|x| x.abs() < 1e-6), "{:?}", r.runout);
            assert_eq!(d[0].friction_angle, friction.friction_angle);
            assert_eq!(d[0].repose_angle, friction.repose);
            // both stop below φ: the cone at φ_ps, Mohr–Coulomb (ψ = 0) at atan(sin φ)
            let phi = friction.friction_angle.to_radians();
            let expect = if material.kind() == "mohr_coulomb" {
                phi.sin().atan().to_degrees()
            } else {
                crate::material::plane_strain_angle(friction.friction_angle)
            };
            assert!(
                (d[0].repose_angle - expect).abs() < 1e-9,
                "{}",
                d[0].repose_angle
            );
            assert!(d[0].repose_angle < friction.friction_angle);
        }
    }

    #[test]
    fn a_sand_body_at_rest_has_no_runout_and_its_box_height() {
        use crate::{BodyConfig, D2, D3, Shape};
        let sand = Material::drucker_prager(3.5e5, 0.3, 2200.0, 35.0, 0.0, 0.0);
        let elastic = Material::elastic(1e5, 0.3, 1000.0);
        let sim = Simulation::<D2>::builder(&[1.0, 0.5], 0.02)
            .body(BodyConfig::new(
                "block",
                Shape::cuboid(&[0.05, 0.0], &[0.2, 0.1]),
                elastic,
            ))
            .body(BodyConfig::new(
                "sand",
                Shape::cuboid(&[0.4, 0.0], &[0.6, 0.3]),
                sand.clone(),
            ))
            .build()
            .unwrap();
        let mut f = Footprints::default();
        f.update(&sim);
        let d = deposits(&sim, &f);
        assert_eq!(d.len(), 1, "only the sand is measured");
        assert_eq!((d[0].body, d[0].name.as_str()), (1, "sand"));
        assert!(
            (d[0].heap.height - 0.3).abs() < 1e-6,
            "{}",
            d[0].heap.height
        );
        let r = d[0].runout.as_ref().unwrap();
        assert!((r.footprint - 0.1).abs() < 1e-6 && (r.centre[0] - 0.5).abs() < 1e-6);
        assert!(r.runout.iter().all(|x| x.abs() < 1e-6), "{:?}", r.runout);
        // a flat top has no flank in the 20–80 % band
        assert_eq!(d[0].heap.flanks, [None, None]);
        // a body never recorded has no run-out
        assert!(deposits(&sim, &Footprints::default())[0].runout.is_none());

        let sim = Simulation::<D3>::builder(&[1.0, 0.6, 1.0], 0.04)
            .body(BodyConfig::new(
                "sand",
                Shape::cuboid(&[0.4, 0.0, 0.4], &[0.6, 0.3, 0.6]),
                sand,
            ))
            .build()
            .unwrap();
        f.clear();
        f.update(&sim);
        let d = deposits(&sim, &f);
        let r = d[0].runout.as_ref().unwrap();
        assert!(r.runout[0].abs() < 1e-6, "{:?}", r.runout);
    }
}
