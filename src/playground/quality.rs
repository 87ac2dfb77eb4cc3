//! Quality levels: the resolution a front end samples a scene at. A scene file is written at
//! the resolution of the work–precision study's defaults (about 10 cells across the thinnest
//! part of a solid, 20 across a sand column: `docs/work-precision.md`); a level coarsens its
//! cells, up to a factor, and raises the particles per cell (per axis, up to 4) where that keeps
//! the bodies recognisable for less: the cheapest sampling that keeps a minimum number of
//! particles. Coarser cells buy a longer stable time step as well as fewer particles: the cost
//! of a simulated second goes as N / h.
//!
//! What a level costs in accuracy is measured on the study's three validation cases at the
//! same cell factor and particles per cell (`cargo xtask quality`, `benches/quality.rs`;
//! figures in [`ACCURACY`]), and for sand on the shipped column collapses, 2D and 3D, sampled
//! at each level (`cargo xtask quality sand`; figures in each level's [`Quality::sand`]).

use crate::config::SceneConfig;
use crate::error::{Result, not_one_of};
use serde::Serialize;

/// A named quality level.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Quality {
    pub id: &'static str,
    pub label: &'static str,
    /// What the level is for, in a sentence.
    pub hint: &'static str,
    /// The largest cell size relative to the scene file's.
    pub cell_factor: f64,
    /// Particles the scene keeps at least, in 2D and in 3D (see [`resample`]).
    pub min_particles: [usize; 2],
    /// Particles each body keeps at least (or all it has as written), in 2D and in 3D: a small
    /// body in a large scene, or one dropped, gets more particles per cell to keep its shape
    /// (the bunny's ears).
    pub min_body_particles: [usize; 2],
    /// What the level's grid costs for sand: the shipped column collapses
    /// (`scenes/column_collapse_2d.json`, `_3d.json`) sampled at the level, in 2D and in 3D.
    pub sand: [SandCost; 2],
}

/// A shipped column collapse (a = 2, φ = 35°) sampled at a quality level and run to rest
/// (`cargo xtask quality sand`, `benches/quality.rs`), against Lube et al. (2005) in 2D
/// (the range 2.40–3.02 its two regimes span at a = 2; 0 inside it) and Lube et al. (2004) in
/// 3D. Errors are relative (−0.2 is 20 % short).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SandCost {
    /// The cell size (m) and particles per cell per axis the level samples the scene at.
    pub cell_size: f64,
    pub particles_per_cell: u32,
    /// Error of the run-out read where the deposit is one grain (2 mm) thick.
    pub runout: f64,
    /// Error of the run-out at the farthest particle.
    pub farthest: f64,
    /// The deposit's flank: the 20–80 % least-squares slope of its surface (degrees; 3D: of
    /// its radial profile).
    pub flank: f64,
}

const fn sand(
    cell_size: f64,
    particles_per_cell: u32,
    runout: f64,
    farthest: f64,
    flank: f64,
) -> SandCost {
    SandCost {
        cell_size,
        particles_per_cell,
        runout,
        farthest,
        flank,
    }
}

/// The most particles per cell per axis a level raises a body to.
pub const MAX_PPC: u32 = 4;

/// The particles per cell per axis a body of `count(ppc)` particles takes at level `q` in
/// dimension `dim`: from `ppc` up, until it keeps the level's least per body.
pub fn body_ppc(
    q: &Quality,
    dim: usize,
    ppc: u32,
    mut count: impl FnMut(u32) -> Result<usize>,
) -> Result<u32> {
    let least = q.min_body_particles[if dim == 2 { 0 } else { 1 }];
    let mut p = ppc;
    while p < MAX_PPC && count(p)? < least {
        p += 1;
    }
    Ok(p)
}

/// The levels a front end offers, coarsest first.
pub static QUALITIES: [Quality; 3] = [
    Quality {
        id: "live",
        label: "Live",
        hint: "the cheapest sampling with cells up to twice the scene's and at least 2 000 particles (2D) or 4 500 (3D): real time on one core",
        cell_factor: 2.0,
        min_particles: [2000, 4500],
        min_body_particles: [300, 1000],
        sand: [
            sand(0.02, 4, -0.1055, -0.1055, 27.3),
            sand(0.04, 3, -0.3637, -0.3841, 23.9),
        ],
    },
    Quality {
        id: "balanced",
        label: "Balanced",
        hint: "cells up to 1.5 times the scene's, at least 4 000 particles (2D) or 9 000 (3D)",
        cell_factor: 1.5,
        min_particles: [4000, 9000],
        min_body_particles: [600, 2000],
        sand: [
            sand(0.01, 2, 0.0, 0.0, 24.4),
            sand(0.2 / 7.0, 3, -0.2909, -0.3184, 23.1),
        ],
    },
    Quality {
        id: "fine",
        label: "Fine",
        hint: "the scene file as written: the resolution of the validation defaults",
        cell_factor: 1.0,
        min_particles: [0, 0],
        min_body_particles: [0, 0],
        sand: [
            sand(0.01, 2, 0.0, 0.0, 24.4),
            sand(0.02, 2, -0.1974, -0.2268, 19.5),
        ],
    },
];

/// The level a front end opens with.
pub const DEFAULT_QUALITY: &str = "live";

impl Quality {
    /// The level named `id`.
    pub fn find(id: &str) -> Result<&'static Quality> {
        QUALITIES
            .iter()
            .find(|q| q.id == id)
            .ok_or_else(|| not_one_of("quality", id, QUALITIES.iter().map(|q| q.id)))
    }

    /// The level of the scene file as written.
    pub fn fine() -> &'static Quality {
        &QUALITIES[QUALITIES.len() - 1]
    }
}

/// The errors of the work–precision study's validation cases (2D, GIMP, CFL 0.4) at a cell
/// factor and particles per cell: what a level costs in accuracy. Each error is relative (0.05
/// is 5 %).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Accuracy {
    pub cell_factor: f64,
    pub particles_per_cell: u32,
    /// Vibrating bar (E = 1 MPa, 1 m × 0.1 m, FLIP, h = 0.025 m × factor): period error.
    pub bar_period: f64,
    /// The same bar: relative L2 error of the modal displacement over three periods.
    pub bar_l2: f64,
    /// Column collapse (a = 2, φ = 32°, h = 0.01 m × factor): error of the normalised
    /// run-out (farthest particle) against Lube et al. (2005)'s experiments.
    pub column_runout: f64,
    /// The same column: final-height error against the same experiments.
    pub column_height: f64,
    /// Resting soft column (E = 100 kPa, PIC, 10 s, h = 0.02 m × factor): settlement error
    /// against the closed form.
    pub resting_settlement: f64,
}

/// The measured errors, one row per cell factor and particles per cell measured: factors at
/// which every case's domain is a whole number of cells; a level's sampling takes the nearest
/// row (`cargo xtask quality`; the figures and the commit they were measured at are in
/// docs/playground.md).
pub static ACCURACY: [Accuracy; 9] = [
    acc(1.0, 2, 0.00086, 0.0090, 0.0052, -0.0241, -0.0077),
    acc(1.25, 2, 0.00134, 0.0143, -0.0541, -0.0498, -0.0081),
    acc(1.25, 3, 0.00127, 0.0134, -0.1344, 0.0560, -0.0078),
    acc(5.0 / 3.0, 2, 0.00239, 0.0259, -0.1153, -0.0259, -0.0106),
    acc(5.0 / 3.0, 3, 0.00225, 0.0242, -0.0824, 0.0532, -0.0104),
    acc(2.0, 2, 0.00347, 0.0376, -0.1402, -0.0208, -0.0116),
    acc(2.0, 3, 0.00322, 0.0352, -0.1398, 0.0752, -0.0116),
    acc(2.0, 4, 0.00317, 0.0343, -0.1053, 0.0928, -0.0114),
    acc(1.0, 3, 0.00082, 0.0084, 0.0658, 0.0613, -0.0073),
];

const fn acc(
    cell_factor: f64,
    particles_per_cell: u32,
    bar_period: f64,
    bar_l2: f64,
    column_runout: f64,
    column_height: f64,
    resting_settlement: f64,
) -> Accuracy {
    Accuracy {
        cell_factor,
        particles_per_cell,
        bar_period,
        bar_l2,
        column_runout,
        column_height,
        resting_settlement,
    }
}

/// The measured row nearest a cell factor and particles per cell.
pub fn accuracy(cell_factor: f64, particles_per_cell: u32) -> Accuracy {
    let distance = |a: &Accuracy| {
        (a.cell_factor / cell_factor).ln().abs()
            + 0.1 * (a.particles_per_cell as f64 - particles_per_cell as f64).abs()
    };
    *ACCURACY
        .iter()
        .min_by(|a, b| distance(a).total_cmp(&distance(b)))
        .expect("a table")
}

/// The resolution a scene was sampled at, and what it costs in accuracy.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Resolution {
    /// The level's id.
    pub quality: &'static str,
    /// Cell size (m).
    pub cell_size: f64,
    /// The scene file's cell size (m).
    pub scene_cell_size: f64,
    /// Particles per cell per axis of the scene's bodies and of the bodies dropped.
    pub particles_per_cell: u32,
    /// The validation errors at this cell factor and particles per cell.
    pub accuracy: Accuracy,
    /// What the level's grid costs for sand in the scene's dimension: the level's
    /// [`Quality::sand`] entry for 2D or 3D (the 2D cases' figures do not carry over to 3D).
    pub sand: SandCost,
}

/// `scene` sampled at level `q`: the cheapest sampling that keeps at least
/// `q.min_particles` particles, with cells from the scene's size up to `q.cell_factor` times
/// it (sizes that divide the domain) and the particles per cell per axis from the scene's up to
/// [`MAX_PPC`]: for each number of particles per cell the largest cells that keep the floor,
/// and of those the one with the least N / h, what a simulated second costs (N particles, a
/// time step ∝ h). A large scene gets the largest cells at the scene's particles per cell, a
/// small one larger cells with more particles per cell, so that the bodies keep their particles. The cap
/// on the time step grows with the cells (it stays the same fraction of a cell).
/// A body that would keep fewer than `q.min_body_particles` (and fewer than it has as written)
/// gets more particles per cell. `count(body, cell_size, ppc)` samples a body (the particles it
/// would get); it is asked for the scene's own resolution only, other lattices scaling the
/// count by (p / p0 · h0 / h)^dim.
pub fn resample(
    scene: &SceneConfig,
    q: &Quality,
    mut count: impl FnMut(usize, f64, u32) -> Result<usize>,
) -> Result<(SceneConfig, Resolution)> {
    let mut out = scene.clone();
    let (h0, dim) = (scene.cell_size, scene.dim as i32);
    // The scene's own particles per cell (the fewest of its bodies'; 2 without bodies).
    let own = scene
        .bodies
        .iter()
        .map(|b| b.particles_per_cell)
        .min()
        .unwrap_or(2);
    let mut ppc = own;
    // The bodies there from the start set the resolution, a poured one by all it pours
    // (`count` says how many); those that enter later (`appear_at`) are sampled at it like
    // bodies dropped. An empty scene keeps its cells: there is nothing to make cheaper, and
    // what is dropped keeps its shape by the level's least per body.
    let present = |b: &crate::config::BodyConfig| b.appear_time() == 0.0;
    if q.cell_factor > 1.0 && scene.bodies.iter().any(present) {
        let floor = q.min_particles[if dim == 2 { 0 } else { 1 }] as f64;
        let least = q.min_body_particles[if dim == 2 { 0 } else { 1 }] as f64;
        let mut bodies = Vec::with_capacity(scene.bodies.len());
        for (i, b) in scene.bodies.iter().enumerate() {
            bodies.push((
                count(i, h0, b.particles_per_cell)? as f64,
                b.particles_per_cell,
            ));
        }
        // Body `b`'s particles per cell and particles at cell size h, the scene's at `p`: its
        // own or `p`, raised to keep the level's least per body (or all it has as written).
        let body = |b: usize, p: u32, h: f64| -> (u32, f64) {
            let (n, p0) = bodies[b];
            let at = |pb: u32| n * (pb as f64 / p0 as f64 * h0 / h).powi(dim);
            let mut pb = p.max(p0);
            while pb < MAX_PPC && at(pb) < least.min(n) {
                pb += 1;
            }
            (pb, at(pb))
        };
        // Particles of the bodies there from the start.
        let particles = |p: u32, h: f64| -> f64 {
            (0..bodies.len())
                .filter(|&b| present(&scene.bodies[b]))
                .map(|b| body(b, p, h).1)
                .sum()
        };
        // Candidate cells: the smallest side over a whole number of them, from the level's
        // largest to the file's (which divides the domain), those that divide every side.
        let side = scene
            .domain
            .size
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min);
        let whole = |x: f64| (x - x.round()).abs() <= 1e-6 * x.max(1.0);
        let n_file = (side / h0).round() as i64;
        let n_least = ((side / (h0 * q.cell_factor)) * (1.0 - 1e-9)).ceil() as i64;
        // A spout must stay resolved on the cells (its radius at least one, a cell from the
        // walls).
        let spouts_fit = |h: f64| {
            let mut at = scene.world();
            at.cell_size = h;
            (scene.bodies.iter().enumerate())
                .all(|(i, b)| at.check_pour(b, &format!("bodies[{i}]")).is_ok())
        };
        let cells: Vec<f64> = (n_least.max(1)..=n_file)
            .map(|n| side / n as f64)
            .filter(|&h| scene.domain.size.iter().all(|&l| whole(l / h)) && spouts_fit(h))
            .collect();
        // For each particles per cell, the largest cells that keep the floor (or the file's);
        // of those, the cheapest.
        let mut best = (f64::INFINITY, own, h0);
        for p in own..=MAX_PPC.max(own) {
            let h = cells
                .iter()
                .copied()
                .find(|&h| particles(p, h) >= floor)
                .unwrap_or(h0);
            let cost = particles(p, h) / h;
            if cost < best.0 * (1.0 - 1e-9) {
                best = (cost, p, h);
            }
        }
        (ppc, out.cell_size) = (best.1, best.2);
        out.max_dt = scene.max_dt * out.cell_size / h0;
        for (i, b) in out.bodies.iter_mut().enumerate() {
            b.particles_per_cell = body(i, ppc, out.cell_size).0;
        }
        out.validate()?;
    }
    let resolution = Resolution {
        quality: q.id,
        cell_size: out.cell_size,
        scene_cell_size: h0,
        particles_per_cell: ppc,
        accuracy: accuracy(out.cell_size / h0, ppc),
        sand: q.sand[if dim == 2 { 0 } else { 1 }],
    };
    Ok((out, resolution))
}

/// `scene` sampled at level `q` as a front end samples it: [`resample`], each body counted by
/// sampling it, a poured one by the particles it pours in all (its volume over a particle's).
/// What [`super::Playground::with_quality`] simulates, and `mpm run --quality`.
pub fn sample_at(scene: &SceneConfig, q: &Quality) -> Result<(SceneConfig, Resolution)> {
    resample(scene, q, |i, h, ppc| {
        let mut b = scene.bodies[i].clone();
        b.particles_per_cell = ppc;
        if let Some(p) = &b.pour {
            let spacing = h / ppc as f64;
            return Ok((p.rate * p.duration / spacing.powi(scene.dim as i32)).round() as usize);
        }
        Ok(b.sample(&format!("bodies[{i}]"), scene.dim, h)?.0.len())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::playground::Playground;

    /// Each level's sand figures were measured at the sampling the level gives the shipped
    /// collapses today: a change of the levels or of the scenes shows here, and the figures
    /// are to be measured again (`cargo xtask quality sand`). A scene's resolution carries its
    /// dimension's entry, the figures the page's quality line quotes.
    #[test]
    fn sand_figures_match_the_levels_sampling() {
        let scenes = [
            include_str!("../../scenes/column_collapse_2d.json"),
            include_str!("../../scenes/column_collapse_3d.json"),
        ];
        for q in &QUALITIES {
            for (k, text) in scenes.iter().enumerate() {
                let scene = SceneConfig::from_json(text).unwrap();
                let pg = Playground::with_quality(scene, q).unwrap();
                let (h, ppc) = (
                    pg.scene().cell_size,
                    pg.scene().bodies[0].particles_per_cell,
                );
                let s = q.sand[k];
                assert_eq!(pg.quality().sand, s, "{} {}D", q.id, k + 2);
                assert!(
                    (h / s.cell_size - 1.0).abs() < 1e-9 && ppc == s.particles_per_cell,
                    "{} {}D: sampled at h = {h}, ppc {ppc}; figures for h = {}, ppc {}",
                    q.id,
                    k + 2,
                    s.cell_size,
                    s.particles_per_cell
                );
            }
        }
    }
}
