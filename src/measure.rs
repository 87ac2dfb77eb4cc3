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
//! * **By hand** ([`length`], [`inclination`], [`angle_at`]): what a ruler and a protractor
//!   read between dragged points.

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
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Flank {
    /// Angle of the fitted slope to the horizontal (degrees, 0–90).
    pub angle: f64,
    /// The fitted line at the first and the last column of the fit: `[x, y]`.
    pub from: [f64; 2],
    pub to: [f64; 2],
}

/// A heap's free surface measured column by column: its height, where its peak stands and
/// its two flanks (left, right; `None` when fewer than two columns fall in the fit band).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
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
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Runout {
    /// The footprint's centre: `x` in 2D, `[x, z]` in 3D (then `centre[1]` is z).
    pub centre: [f64; 2],
    /// The footprint's half-width L0 (2D) or radius R0 (3D) (m).
    pub footprint: f64,
    /// The deposit's front: in 2D the left and right ends (x, m); in 3D the mean front radius
    /// over the azimuthal sectors and the farthest sector's.
    pub front: [f64; 2],
    /// How far the front lies beyond the footprint (m): left and right in 2D; mean and
    /// largest over the sectors in 3D.
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
/// and now (spacing `s`). The footprint's radius R0 is the farthest initial particle's
/// distance from the axis plus half a spacing; the front in each of `sectors` azimuthal
/// sectors is the [`deposit_front`] of its particles beyond R0.
pub fn radial_runout(initial: &[[f64; 3]], current: &[[f64; 3]], s: f64, sectors: usize) -> Runout {
    let centre = axis(initial);
    let r0 = radial_profile(initial, centre)
        .iter()
        .map(|p| p.0)
        .fold(0.0, f64::max)
        + 0.5 * s;
    let sectors = sectors.max(1);
    let mut rays = vec![Vec::new(); sectors];
    for p in current {
        let (dx, dz) = (p[0] - centre[0], p[2] - centre[1]);
        let k = ((dz.atan2(dx) / std::f64::consts::TAU + 0.5) * sectors as f64) as usize;
        rays[k.min(sectors - 1)].push(dx.hypot(dz));
    }
    let fronts: Vec<f64> = rays
        .into_iter()
        .filter(|d| !d.is_empty())
        .map(|d| deposit_front(d, s, r0))
        .collect();
    let mean = fronts.iter().sum::<f64>() / fronts.len().max(1) as f64;
    let far = fronts.iter().copied().fold(0.0, f64::max);
    Runout {
        centre,
        footprint: r0,
        front: [mean, far],
        runout: [mean - r0, far - r0],
    }
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
