//! Mohr–Coulomb beside the paper's plane-strain-matched Drucker–Prager cone (Eq. 13,
//! `friction_match: "plane_strain"`), the same φ = 32°, ψ = 0, c = 0, E, ν and density, on
//! the GIMP grid of the fast validation tests (h = 0.01 m, two particles per cell):
//!
//! - **heap**: a plane heap 0.1 m tall with flanks at 25°–40° on a floor as rough as the sand
//!   (μ = tan φ), after 1.5 s: the flank angle fitted between 20 % and 80 % of the height, how
//!   far the base spread and the fastest particle's speed;
//! - **column**: the plane collapses of aspect ratio 0.5 and 2 of `scenes/validation/`, run to
//!   rest: run-out (L∞ − L0)/L0 and height H∞/H0 as the validation tests measure them.
//!
//! Prints one markdown table per family (docs/method.md, "Mohr–Coulomb and the plane-strain
//! cone"). `cargo run --release --example mohr_coulomb_vs_cone` (about a minute).

#[path = "../tests/support/validation.rs"]
mod validation;
use mpm::material::FrictionMatch;
use mpm::{D2, KernelKind, Material, SceneConfig, Simulation};
use validation::*;

/// The scene's first body made of Mohr–Coulomb with the Drucker–Prager body's parameters.
fn to_mohr_coulomb(scene: &mut SceneConfig) {
    let Material::DruckerPrager(m) = scene.bodies[0].material else {
        panic!("the body under test is Drucker–Prager sand");
    };
    scene.bodies[0].material = Material::mohr_coulomb(
        m.youngs_modulus,
        m.poisson_ratio,
        m.density,
        m.friction_angle,
        m.dilatancy_angle,
        m.cohesion,
    );
}

fn models() -> [(&'static str, bool); 2] {
    [
        ("Drucker–Prager, plane strain (Eq. 13)", false),
        ("Mohr–Coulomb", true),
    ]
}

/// Flank angle (degrees), base spread (m) and end speed (m/s) of a heap after `seconds`.
fn heap(slope: f64, mohr_coulomb: bool, n: &Numerics, seconds: f64) -> (f64, f64, f64) {
    let mut scene = heap_slope_scene(32.0, slope, 3.5e5, n);
    if mohr_coulomb {
        to_mohr_coulomb(&mut scene);
    }
    let s = spacing(&scene);
    let mut sim = Simulation::<D2>::new(scene).expect("heap scene");
    let width = |sim: &Simulation<D2>| {
        let b = sim.bodies()[0].stats();
        b.bbox_max[0] - b.bbox_min[0]
    };
    let w0 = width(&sim);
    sim.advance(seconds).expect("heap step");
    let p = sim.particles();
    let pts: Vec<(f64, f64)> = (0..p.len())
        .map(|i| (p.x[i][0] as f64, p.x[i][1] as f64))
        .collect();
    let (_, f) = flank_angles(&pts, s, sim.cell_size(), 1.2);
    (
        0.5 * (f[0] + f[1]),
        width(&sim) - w0,
        sim.diagnostics().max_speed,
    )
}

/// Run-out and height of a plane column collapse run to rest (at most `t_max` s).
fn column(file: &str, mohr_coulomb: bool, n: &Numerics, t_max: f64) -> (f64, f64) {
    let mut scene = load(file, n);
    if mohr_coulomb {
        to_mohr_coulomb(&mut scene);
    }
    let s = spacing(&scene);
    let g = scene.gravity_vector()[1].abs();
    let mut sim = Simulation::<D2>::new(scene).expect("column scene");
    let (xc, l0) = column_extent(&sim, s);
    let p = sim.particles();
    let h0 = (0..p.len()).map(|i| p.x[i][1] as f64).fold(0.0, f64::max) + 0.5 * s;
    let t_min = 4.0 * (h0 / g).sqrt();
    loop {
        sim.advance(0.02).expect("column step");
        let t = sim.time();
        if (t > t_min && sim.diagnostics().max_speed < REST_SPEED * (g * h0).sqrt()) || t >= t_max {
            break;
        }
    }
    let p = sim.particles();
    let front = |sign: f64| {
        deposit_front(
            (0..p.len())
                .map(|i| sign * (p.x[i][0] as f64 - xc))
                .filter(|&d| d > 0.0)
                .collect(),
            s,
            0.0,
        )
    };
    let l_inf = 0.5 * (front(1.0) + front(-1.0));
    let h_inf = (0..p.len())
        .filter(|&i| (p.x[i][0] as f64 - xc).abs() < l0)
        .map(|i| p.x[i][1] as f64)
        .fold(0.0, f64::max)
        + 0.5 * s;
    ((l_inf - l0) / l0, h_inf / h0)
}

fn main() {
    let n = Numerics::new(0.01, KernelKind::Gimp).plane_strain();
    assert_eq!(n.friction_match, Some(FrictionMatch::PlaneStrain));
    println!(
        "φ = 32°, ψ = 0, c = 0; plane-strain angle of the cone φ_ps = {:.1}°; {}\n",
        plane_strain_angle(32.0),
        n.label()
    );
    println!("| heap flanks | model | flank angle after 1.5 s | base spread | end speed |");
    println!("| --- | --- | --- | --- | --- |");
    for slope in [25.0, 30.0, 35.0, 40.0] {
        for (name, mc) in models() {
            let (angle, spread, speed) = heap(slope, mc, &n, 1.5);
            println!(
                "| {slope}° | {name} | {angle:.1}° | {:.1} mm | {:.1} mm/s |",
                1e3 * spread,
                1e3 * speed
            );
        }
    }
    println!("\n| column | model | run-out (L∞ − L0)/L0 | height H∞/H0 |");
    println!("| --- | --- | --- | --- |");
    for (file, a) in [
        ("column_collapse_a0.5_2d.json", 0.5),
        ("column_collapse_a2_2d.json", 2.0),
    ] {
        for (name, mc) in models() {
            let (runout, height) = column(file, mc, &n, 4.0);
            println!("| a = {a} | {name} | {runout:.2} | {height:.2} |");
        }
    }
}
