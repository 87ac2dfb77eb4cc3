//! The paper's scenes behave as in its figures, checked on the shipped scene files at a
//! coarse resolution (only the cell size is overridden), in 3D and in 2D:
//! - the elastic bunny (Fig. 1 middle) bounces and recovers its shape (up to its sag);
//! - the plastic bunny (Fig. 1 right) flattens for good and does not bounce;
//! - the notched sand block (Fig. 2) collapses into a pile flatter than the friction angle that
//!   runs out beyond the block's footprint;
//! - the elastic bunny dropped on a sand ball (Fig. 3) sinks below the ball's top;
//! - a granular column on a frictional floor spreads into a lower, wider pile.
#![cfg(not(target_arch = "wasm32"))]
// Real is f32 by default, f64 with the `f64` feature: the casts to f64 are no-ops there.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

use mpm::io::Snapshot;
use mpm::{AnySimulation, BodyStats, Dim, Material, SceneConfig, Shape, Simulation};
use std::path::Path;

/// The shipped scene `name` with a coarser cell.
fn coarse(name: &str, cell_size: f64) -> SceneConfig {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(format!("{name}.json"));
    let mut scene = SceneConfig::load(&path).unwrap();
    scene.cell_size = cell_size;
    scene.validate().unwrap();
    scene
}

/// Runs to `time`, sampling every body's statistics every `every` seconds.
fn history(scene: SceneConfig, time: f64, every: f64) -> (AnySimulation, Vec<Vec<BodyStats>>) {
    let mut sim = AnySimulation::new(scene).unwrap();
    let mut out = vec![sim.body_stats()];
    while sim.time() < time - 1e-9 {
        sim.advance(every).unwrap();
        out.push(sim.body_stats());
    }
    assert_eq!(Snapshot::of(&sim).nonfinite(), 0);
    assert_eq!(Snapshot::of(&sim).escaped(), 0);
    (sim, out)
}

fn extent(b: &BodyStats, dim: usize) -> Vec<f64> {
    (0..dim).map(|a| b.bbox_max[a] - b.bbox_min[a]).collect()
}

/// The first local minimum of the centre of mass height (the first impact), and the largest
/// rise of the centre of mass above it afterwards.
fn rebound(h: &[Vec<BodyStats>], body: usize) -> (usize, f64) {
    let y: Vec<f64> = h.iter().map(|s| s[body].center_of_mass[1]).collect();
    let impact = (1..y.len() - 1)
        .find(|&i| y[i] < y[i - 1] && y[i] <= y[i + 1])
        .expect("the body lands");
    let rise = y[impact..]
        .iter()
        .cloned()
        .fold(f64::NEG_INFINITY, f64::max)
        - y[impact];
    (impact, rise)
}

/// The bunny scene `name` at cell size `cell`, run for 1.5 s: its statistics every 5 ms, the
/// dimension, the drop height, and how far it ended from its initial shape (`shape_change`).
fn bunny(name: &str, cell: f64) -> (Vec<Vec<BodyStats>>, usize, f64, f64) {
    let scene = coarse(name, cell);
    let dim = scene.dim;
    let before = positions_by_id(&AnySimulation::new(scene.clone()).unwrap());
    let (sim, h) = history(scene, 1.5, 0.005);
    // the drop: from the initial lowest point to the floor
    let drop = h[0][0].bbox_min[1];
    let change = shape_change(&before, &positions_by_id(&sim), dim);
    (h, dim, drop, change)
}

/// Each particle's position, indexed by its stable id (the third component zero in 2D).
fn positions_by_id(sim: &AnySimulation) -> Vec<[f64; 3]> {
    fn of<D: Dim>(s: &Simulation<D>) -> Vec<[f64; 3]> {
        let p = s.particles();
        let mut x = vec![[0.0; 3]; p.len()];
        for i in 0..p.len() {
            for a in 0..D::DIM {
                x[p.id[i] as usize][a] = p.x[i][a] as f64;
            }
        }
        x
    }
    match sim {
        AnySimulation::D2(s) => of(s),
        AnySimulation::D3(s) => of(s),
    }
}

/// How far a body has moved from its shape `before` to `after` (positions by particle): the
/// RMS distance of the particles from where the best-fitting rigid motion puts them (the
/// centre of mass's translation and the rotation R, the polar factor of
/// Σ (x − c)(X − C)ᵀ), relative to the initial radius of gyration. Zero for any rigid motion,
/// whatever pose a body comes to rest in.
fn shape_change(before: &[[f64; 3]], after: &[[f64; 3]], dim: usize) -> f64 {
    use glam::{DMat3, DVec3};
    let n = before.len() as f64;
    let centre = |x: &[[f64; 3]]| x.iter().map(|&p| DVec3::from(p)).sum::<DVec3>() / n;
    let (c0, c1) = (centre(before), centre(after));
    let pairs = || {
        before
            .iter()
            .zip(after)
            .map(|(&p, &q)| (DVec3::from(p) - c0, DVec3::from(q) - c1))
    };
    let mut a = pairs().fold(DMat3::ZERO, |a, (u, v)| {
        a + DMat3::from_cols(v * u.x, v * u.y, v * u.z)
    });
    if dim == 2 {
        a.z_axis = DVec3::Z;
    }
    // The polar factor by Newton's iteration R ← (R + R⁻ᵀ)/2.
    let mut r = a;
    for _ in 0..60 {
        r = (r + r.inverse().transpose()) * 0.5;
    }
    let (d2, g2) = pairs().fold((0.0, 0.0), |(d, g), (u, v)| {
        (d + (v - r * u).length_squared(), g + u.length_squared())
    });
    (d2 / g2).sqrt()
}

fn elastic_bunny(name: &str, cell: f64) {
    let (h, dim, drop, change) = bunny(name, cell);
    let (impact, rise) = rebound(&h, 0);
    assert!(
        rise > 0.1 * drop,
        "{name}: the centre of mass rose {rise:.4} m after the impact at step {impact}, \
         less than a tenth of the {drop:.3} m drop"
    );
    // The static sag under gravity stays (E = 100 kPa: a few per cent); the plastic bunny
    // ends 18-21 % from its shape.
    assert!(
        change < 0.10,
        "{name}: the shape changed by {:.1} % of the radius of gyration",
        100.0 * change
    );
    let (e0, e1) = (extent(&h[0][0], dim), extent(&h[h.len() - 1][0], dim));
    eprintln!(
        "{name}: rebound {rise:.4} m of a {drop:.3} m drop; shape change {:.1} %; extents \
         {e0:.4?} → {e1:.4?}",
        100.0 * change
    );
}

fn plastic_bunny(name: &str, cell: f64) {
    let (h, dim, drop, change) = bunny(name, cell);
    let (impact, rise) = rebound(&h, 0);
    assert!(
        rise < 0.02 * drop,
        "{name}: the centre of mass rose {rise:.4} m after the impact at step {impact} (a \
         bounce; allowed: 2 % of the {drop:.3} m drop)"
    );
    let (e0, e1) = (extent(&h[0][0], dim), extent(&h[h.len() - 1][0], dim));
    let flattening = 1.0 - e1[1] / e0[1];
    assert!(
        flattening >= 0.2,
        "{name}: the height went from {:.4} to {:.4} m, {:.1} % lower (at least 20 % wanted)",
        e0[1],
        e1[1],
        100.0 * flattening
    );
    let plastic = h[h.len() - 1][0].max_plastic_strain;
    assert!(plastic > 0.05, "{name}: max plastic strain {plastic}");
    eprintln!(
        "{name}: rise after impact {rise:.5} m; height {:.4} → {:.4} m ({:.1} % lower); shape \
         change {:.1} %",
        e0[1],
        e1[1],
        100.0 * flattening,
        100.0 * change
    );
}

#[test]
fn elastic_bunny_bounces_and_recovers_its_shape_3d() {
    elastic_bunny("elastic_bunny_3d", 0.04);
}

#[test]
fn elastic_bunny_bounces_and_recovers_its_shape_2d() {
    elastic_bunny("elastic_bunny_2d", 0.02);
}

#[test]
fn plastic_bunny_flattens_and_does_not_bounce_3d() {
    plastic_bunny("plastic_bunny_3d", 0.04);
}

#[test]
fn plastic_bunny_flattens_and_does_not_bounce_2d() {
    plastic_bunny("plastic_bunny_2d", 0.02);
}

/// The slope of a pile's free surface: the height profile (the highest particle in columns
/// of width `bin` along x) is fitted by a straight line on each flank, over the middle 80 % of
/// the flank's span from the crest to the toe (leaving out the rounded crest and the toe).
/// Returns the steeper flank's angle in degrees, the height and the x extent of the pile.
fn pile(s: &Snapshot, bin: f64) -> (f64, f64, f64, f64) {
    let xs: Vec<f64> = s.position.iter().map(|p| p[0] as f64).collect();
    let (x0, x1) = (
        xs.iter().cloned().fold(f64::INFINITY, f64::min),
        xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
    );
    let n = ((x1 - x0) / bin).floor() as usize + 1;
    let mut top = vec![0.0f64; n];
    for p in &s.position {
        let i = (((p[0] as f64 - x0) / bin) as usize).min(n - 1);
        top[i] = top[i].max(p[1] as f64);
    }
    if std::env::var("PROFILE").is_ok() {
        eprintln!("profile from x = {x0:.3} by {bin}: {top:.3?}");
    }
    let peak = (0..n).max_by(|&a, &b| top[a].total_cmp(&top[b])).unwrap();
    let fit = |from: usize, to: usize| -> f64 {
        // columns strictly inside the middle 80 % of [from, to]
        let (lo, hi) = (from.min(to) as f64, from.max(to) as f64);
        let pts: Vec<(f64, f64)> = (0..n)
            .filter(|&i| {
                let f = i as f64;
                f >= lo + 0.1 * (hi - lo) && f <= hi - 0.1 * (hi - lo)
            })
            .map(|i| ((i as f64 + 0.5) * bin, top[i]))
            .collect();
        if pts.len() < 3 {
            return 0.0; // too short to be a flank (e.g. against a wall)
        }
        let m = pts.len() as f64;
        let (sx, sy) = pts.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
        let (mx, my) = (sx / m, sy / m);
        let (sxy, sxx) = pts.iter().fold((0.0, 0.0), |a, p| {
            (a.0 + (p.0 - mx) * (p.1 - my), a.1 + (p.0 - mx).powi(2))
        });
        (sxy / sxx).abs().atan().to_degrees()
    };
    let slope = fit(0, peak).max(fit(peak, n - 1));
    (slope, top[peak], x0, x1)
}

fn friction_angle(scene: &SceneConfig, body: usize) -> f64 {
    match &scene.bodies[body].material {
        Material::DruckerPrager(m) => m.friction_angle,
        m => panic!("body {body} is {}, not sand", m.kind()),
    }
}

fn sand_pile(name: &str, cell: f64, time: f64) {
    let scene = coarse(name, cell);
    let phi = friction_angle(&scene, 0);
    let (sim, h) = history(scene, time, 0.1);
    let (b0, b1) = (&h[0][0], &h[h.len() - 1][0]);
    let s = Snapshot::of(&sim);
    let (slope, height, x0, x1) = pile(&s, cell);
    assert!(
        slope < phi,
        "{name}: the pile's slope is {slope:.1}°, not below the friction angle {phi}°"
    );
    assert!(
        x1 - x0 > b0.bbox_max[0] - b0.bbox_min[0] && x1 > b0.bbox_max[0],
        "{name}: the pile spans x ∈ [{x0:.3}, {x1:.3}], not beyond the initial footprint \
         [{:.3}, {:.3}]",
        b0.bbox_min[0],
        b0.bbox_max[0]
    );
    assert!(
        height < b0.bbox_max[1],
        "{name}: the pile is {height:.3} m high, the block was {:.3}",
        b0.bbox_max[1]
    );
    assert!(b1.kinetic < 0.01 * b0.mass * 9.81 * b0.bbox_max[1]);
    eprintln!(
        "{name}: slope {slope:.1}° (φ = {phi}°), run-out x ∈ [{x0:.3}, {x1:.3}] from [{:.3}, {:.3}], \
         height {height:.3} from {:.3} m",
        b0.bbox_min[0], b0.bbox_max[0], b0.bbox_max[1]
    );
}

#[test]
fn notched_sand_block_collapses_into_a_pile_3d() {
    sand_pile("notched_sand_block_3d", 0.05, 2.0);
}

#[test]
fn notched_sand_block_collapses_into_a_pile_2d() {
    sand_pile("notched_sand_block_2d", 0.02, 2.0);
}

#[test]
fn column_collapses_into_a_lower_wider_pile_3d() {
    sand_pile("column_collapse_3d", 0.025, 1.5);
}

#[test]
fn column_collapses_into_a_lower_wider_pile_2d() {
    sand_pile("column_collapse_2d", 0.02, 1.5);
}

fn bunny_on_sand_ball(name: &str, cell: f64) {
    let scene = coarse(name, cell);
    let ball = scene
        .bodies
        .iter()
        .position(|b| matches!(b.shape, Shape::Ball { .. }))
        .expect("a sand ball");
    let bunny = 1 - ball;
    let top = match &scene.bodies[ball].shape {
        Shape::Ball { center, radius } => center[1] + radius,
        _ => unreachable!(),
    };
    friction_angle(&scene, ball);
    let (_, h) = history(scene, 1.5, 0.05);
    let end = &h[h.len() - 1][bunny];
    assert!(
        end.center_of_mass[1] < top
            && end.bbox_min[1] < top - 0.25 * (top - h[0][ball].bbox_min[1]),
        "{name}: the bunny ends with its centre at {:.3} m and its lowest point at {:.3} m; \
         the ball's top was at {top:.3} m",
        end.center_of_mass[1],
        end.bbox_min[1]
    );
    eprintln!(
        "{name}: bunny centre {:.3} m, lowest point {:.3} m; ball top was {top:.3} m",
        end.center_of_mass[1], end.bbox_min[1]
    );
}

#[test]
fn bunny_sinks_into_the_sand_ball_3d() {
    bunny_on_sand_ball("bunny_on_sand_ball_3d", 0.05);
}

#[test]
fn bunny_sinks_into_the_sand_ball_2d() {
    bunny_on_sand_ball("bunny_on_sand_ball_2d", 0.02);
}
