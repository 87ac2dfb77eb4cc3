//! How densely a resting deposit is filled: the share of its interior that holds no particle.
//! A deposit whose particles string out into strands or spread into beads has holes that its
//! particles' volumes do not show; this finds them from the positions alone.

use std::collections::{HashMap, HashSet};

/// The interior of a deposit cut into cubes (squares in 2D) of 1.5 particle spacings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gaps {
    /// Cubes whose centre is inside the interior.
    pub cubes: usize,
    /// Of those, the ones holding no particle.
    pub empty: usize,
}

impl Gaps {
    /// The share of the interior's cubes that are empty (0 without an interior).
    pub fn share(&self) -> f64 {
        self.empty as f64 / self.cubes.max(1) as f64
    }
}

/// The gaps inside the deposit of `points` (x, y up, z; z ignored in 2D), of particle spacing
/// `s`, its surface read over columns `h` wide. The interior lies two spacings or more under
/// the surface (the lowest top of a particle's own column and those around it), where the
/// deposit is at least four spacings thick, two spacings in from its lateral ends; it is cut
/// into cubes of 1.5 spacings from the deposit's lowest corner, each counted where its centre
/// is inside.
pub fn interior_gaps(points: &[[f64; 3]], dim: usize, s: f64, h: f64) -> Gaps {
    if points.is_empty() {
        return Gaps { cubes: 0, empty: 0 };
    }
    let column = |x: &[f64; 3]| ((x[0] / h).floor() as i64, (x[2] / h).floor() as i64);
    let mut top: HashMap<(i64, i64), f64> = HashMap::new();
    for x in points {
        let t = top.entry(column(x)).or_insert(x[1]);
        *t = x[1].max(*t);
    }
    let surface = |x: &[f64; 3]| {
        let (i, k) = column(x);
        let dk = if dim == 3 { -1..=1 } else { 0..=0 };
        dk.flat_map(|c| (-1..=1).map(move |r| (i + r, k + c)))
            .map(|c| top.get(&c).copied().unwrap_or(f64::NEG_INFINITY))
            .fold(f64::INFINITY, f64::min)
    };
    let lo = |a: usize| points.iter().map(|x| x[a]).fold(f64::INFINITY, f64::min);
    let hi = |a: usize| {
        points
            .iter()
            .map(|x| x[a])
            .fold(f64::NEG_INFINITY, f64::max)
    };
    // the lateral axes: x, and z in 3D
    let lateral = [0, 2];
    let (l0, l1) = ([lo(0), lo(2)], [hi(0), hi(2)]);
    let floor = lo(1);
    let inside = |x: &[f64; 3]| {
        let top = surface(x);
        x[1] < top - 2.0 * s
            && top - floor > 4.0 * s
            && (0..dim - 1).all(|k| {
                let a = lateral[k];
                x[a] > l0[k] + 2.0 * s && x[a] < l1[k] - 2.0 * s
            })
    };
    let c = 1.5 * s;
    let cube = |x: &[f64; 3]| -> [i64; 3] {
        [
            ((x[0] - l0[0]) / c).floor() as i64,
            ((x[1] - floor) / c).floor() as i64,
            if dim == 3 {
                ((x[2] - l0[1]) / c).floor() as i64
            } else {
                0
            },
        ]
    };
    let full: HashSet<[i64; 3]> = points.iter().map(cube).collect();
    let n = |k: usize| ((l1[k] - l0[k]) / c).ceil() as i64;
    let (nx, ny, nz) = (
        n(0),
        ((hi(1) - floor) / c).ceil() as i64,
        if dim == 3 { n(1) } else { 1 },
    );
    let mut gaps = Gaps { cubes: 0, empty: 0 };
    for i in 0..nx {
        for j in 0..ny {
            for k in 0..nz {
                let centre = [
                    l0[0] + (i as f64 + 0.5) * c,
                    floor + (j as f64 + 0.5) * c,
                    if dim == 3 {
                        l0[1] + (k as f64 + 0.5) * c
                    } else {
                        0.0
                    },
                ];
                if inside(&centre) {
                    gaps.cubes += 1;
                    gaps.empty += usize::from(!full.contains(&[i, j, k]));
                }
            }
        }
    }
    gaps
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A block of particles on a lattice of spacing `s`, `n` wide (and deep in 3D) and `m`
    /// tall.
    fn block(dim: usize, s: f64, n: usize, m: usize) -> Vec<[f64; 3]> {
        let nz = if dim == 3 { n } else { 1 };
        let mut p = vec![];
        for i in 0..n {
            for j in 0..m {
                for k in 0..nz {
                    let z = if dim == 3 { (k as f64 + 0.5) * s } else { 0.0 };
                    p.push([(i as f64 + 0.5) * s, (j as f64 + 0.5) * s, z]);
                }
            }
        }
        p
    }

    #[test]
    fn a_full_lattice_has_no_gaps_and_a_hole_is_found() {
        for dim in [2, 3] {
            let (s, h) = (0.01, 0.02);
            let p = block(dim, s, 20, 12);
            let g = interior_gaps(&p, dim, s, h);
            assert!(g.cubes > 10, "{dim}D {g:?}");
            assert_eq!(g.empty, 0, "{dim}D {g:?}");
            // take out the particles within 1.6 spacings of the block's middle: a hole wider
            // than a cube, so at least one cube is empty
            let mid = [0.1, 0.06, if dim == 3 { 0.1 } else { 0.0 }];
            let holed: Vec<_> = p
                .into_iter()
                .filter(|x| (0..3).map(|a| (x[a] - mid[a]).powi(2)).sum::<f64>().sqrt() > 1.6 * s)
                .collect();
            let g = interior_gaps(&holed, dim, s, h);
            assert!(g.empty >= 1 && g.share() > 0.0, "{dim}D {g:?}");
            // a layer three spacings thick has no interior
            let g = interior_gaps(&block(dim, s, 20, 3), dim, s, h);
            assert_eq!(g.cubes, 0, "{dim}D {g:?}");
        }
    }
}
