//! Where the shear box's resistance comes from (docs/validation.md, "The soil lab"): the
//! shipped box (`scenes/lab/shear_box_mc_2d.json`) with each wall of each half its own
//! kinematic body, so that the force the sand exerts on each wall is read apart; beside them
//! the shear and normal force the sand carries across the shear plane itself (its particles'
//! stresses summed over a slab one cell thick), the mean stress state in the band's middle
//! half, and the lid's support, rise and tilt.
//!
//! `nice cargo run --release --example shear_box_forces -- [key=value ...]`
//!
//! keys (defaults in brackets): `sigma` the lid's load (Pa) [10000], `psi` ψ (°) [0], `phi`
//! φ (°) [30], `c` cohesion (Pa) [0], `h` cell size (m) [the scene's], `ppc` particles per
//! cell and axis [2], `gap` the opening between the halves (m; the upper half's walls raised
//! by it) [one cell, as in the scene], `height` the sample's height (m) [0.04], `speed` the
//! drive (m/s) [0.02], `span` (s) [0.2], `every` between readings (s) [0.005], `floor` the
//! floor's μ [0.5], `e` the sand's Young's modulus (Pa) [1e7], `cfl` [the scene's].
//!
//! Columns: δ (mm); τ = F/L from the upper half's force along the motion (kPa); that force
//! on its trailing (left) and leading (right) wall and on the lower half's two walls, over L
//! (kPa, along +x); the vertical force the sand exerts on each wall of the upper half and on
//! the lower half, over L (kPa, up positive); the plane's shear and normal force from the
//! sand's stresses, over L (kPa); the band's mean σ_xx, σ_yy, τ_xy in its middle half (kPa,
//! compression positive); the lid's support over L (kPa), rise and tilt (mm, right end less
//! left end); σ_n on the plane by the statics of what lies above it (the lid's and the sand's
//! weight plus the upper half's vertical force, over L: kPa), as `mpm::lab::ShearBox` reads
//! it, and atan(τ/σ_n) (°).

use mpm::math::SymTensor;
use mpm::{BodyConfig, D2, Material, SceneConfig, Shape, Simulation};
use std::collections::HashMap;

fn main() {
    let args: HashMap<String, f64> = std::env::args()
        .skip(1)
        .map(|a| {
            let (k, v) = a.split_once('=').expect("key=value");
            (k.to_string(), v.parse().expect("a number"))
        })
        .collect();
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/lab/shear_box_mc_2d.json"
    );
    let file = SceneConfig::load(std::path::Path::new(path)).expect("the shipped scene");
    let get = |k: &str, d: f64| args.get(k).copied().unwrap_or(d);
    let sigma = get("sigma", 1e4);
    let h = get("h", file.cell_size);
    let ppc = get("ppc", 2.0) as u32;
    let gap = get("gap", h);
    let height = get("height", 0.04);
    let speed = get("speed", 0.02);
    let span = get("span", 0.2);
    let every = get("every", 0.005);
    let (x0, length, wall) = (0.1, 0.1, 0.02);
    let plane = 0.5 * height;
    let top = height + 0.03;

    let mut scene = SceneConfig::new(2, &file.domain.size, h);
    scene.boundary.friction = get("floor", 0.5);
    scene.contact = file.contact;
    scene.cfl = get("cfl", file.cfl);
    let mut sand = file.bodies[0].clone();
    sand.shape = Shape::cuboid(&[x0, 0.0], &[x0 + length, height]);
    sand.particles_per_cell = ppc;
    let Material::MohrCoulomb(m) = &mut sand.material else {
        panic!("the shipped sample is Mohr–Coulomb")
    };
    m.friction_angle = get("phi", m.friction_angle);
    m.dilatancy_angle = get("psi", 0.0);
    m.cohesion = get("c", 0.0);
    m.youngs_modulus = get("e", m.youngs_modulus);
    let frame = file.bodies[1].material.clone();
    let wall_body = |name: &str, lo: [f64; 2], hi: [f64; 2], v: f64| {
        BodyConfig::new(name, Shape::cuboid(&lo, &hi), frame.clone())
            .kinematic()
            .with_velocity(&[v, 0.0])
            .with_particles_per_cell(ppc)
    };
    let mut lid = file.bodies[3].clone();
    lid.shape = Shape::cuboid(&[x0, height], &[x0 + length, height + 0.01]);
    lid.particles_per_cell = ppc;
    let Material::Elastic(l) = &mut lid.material else {
        panic!("the shipped lid is elastic")
    };
    l.density = sigma / (9.81 * 0.01);
    scene.bodies = vec![
        sand,
        wall_body("upper trailing", [x0 - wall, plane + gap], [x0, top], speed),
        wall_body(
            "upper leading",
            [x0 + length, plane + gap],
            [x0 + length + wall, top],
            speed,
        ),
        wall_body("lower left", [x0 - wall, 0.0], [x0, plane], 0.0),
        wall_body(
            "lower right",
            [x0 + length, 0.0],
            [x0 + length + wall, plane],
            0.0,
        ),
        lid,
    ];
    let mut sim = Simulation::<D2>::new(scene).expect("a valid scene");
    let g = 9.81;
    let lid_weight = sim.bodies()[5].stats().mass * g;
    let y_band = plane + 0.5 * gap;
    let above_plane = {
        let p = sim.particles();
        let sand: f64 = sim.bodies()[0]
            .range()
            .filter(|&i| p.x[i][1] as f64 > y_band)
            .map(|i| p.mass[i] as f64)
            .sum();
        sand * g + lid_weight
    };
    println!(
        "h {h} m, {} sand particles, the weight above the plane {:.2} kPa (the lid {:.2} kPa), gap {gap} m, plane at y = {:.4} m",
        sim.bodies()[0].range().len(),
        above_plane / length / 1e3,
        lid_weight / length / 1e3,
        plane + 0.5 * gap
    );
    println!(
        "{:>6} {:>7} | {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} | {:>7} {:>7} | {:>7} {:>7} {:>7} | {:>7} {:>6} {:>6} | {:>7} {:>6}",
        "δ mm",
        "τ=F/L",
        "UL Fx",
        "UR Fx",
        "LL Fx",
        "LR Fx",
        "UL Fy",
        "UR Fy",
        "L Fy",
        "τ plane",
        "σ plane",
        "σxx",
        "σyy",
        "τxy",
        "lid",
        "rise",
        "tilt",
        "σ_n",
        "φ_ds"
    );
    let lid0 = lid_shape(&sim);
    let mut impulse = [[0.0f64; 2]; 6];
    let mut elapsed = 0.0;
    let mut next = every;
    while sim.time() < span - 1e-12 {
        sim.step().expect("the run");
        let dt = sim.diagnostics().dt;
        for (b, j) in impulse.iter_mut().enumerate() {
            let f = sim.bodies()[b].stats().contact_force;
            j[0] += f[0] * dt;
            j[1] += f[1] * dt;
        }
        elapsed += dt;
        if sim.time() < next - 1e-12 {
            continue;
        }
        next += every;
        let f = |b: usize, a: usize| impulse[b][a] / elapsed / length / 1e3;
        let (plane_tau, plane_sigma, band) = plane_forces(&sim, y_band, h, x0, length);
        // the reading: σ_n on the plane by the statics of what lies above it
        let tau = -(f(1, 0) + f(2, 0));
        let sigma_n = above_plane / length / 1e3 + f(1, 1) + f(2, 1);
        let (rise, tilt) = {
            let (y, t) = lid_shape(&sim);
            (y - lid0.0, t - lid0.1)
        };
        println!(
            "{:6.2} {:7.2} | {:7.2} {:7.2} {:7.2} {:7.2} {:7.2} {:7.2} {:7.2} | {:7.2} {:7.2} | {:7.2} {:7.2} {:7.2} | {:7.2} {:6.3} {:6.3} | {:7.2} {:6.2}",
            sim.time() * speed * 1e3,
            tau,
            f(1, 0),
            f(2, 0),
            f(3, 0),
            f(4, 0),
            f(1, 1),
            f(2, 1),
            f(3, 1) + f(4, 1),
            plane_tau / length / 1e3,
            plane_sigma / length / 1e3,
            band[0] / 1e3,
            band[1] / 1e3,
            band[2] / 1e3,
            f(5, 1),
            rise * 1e3,
            tilt * 1e3,
            sigma_n,
            (tau / sigma_n).atan().to_degrees()
        );
        impulse = [[0.0; 2]; 6];
        elapsed = 0.0;
    }
}

/// The shear and normal force the sand carries across the plane y = `y` (N/m: its particles'
/// τ_xy and −σ_yy summed over the slab one cell thick about the plane, over the slab's
/// thickness), and the mean (−σ_xx, −σ_yy, τ_xy) of the slab's particles in the middle half
/// of the box (τ_xy > 0 where the sand below resists the upper part's motion along +x).
fn plane_forces(
    sim: &Simulation<D2>,
    y: f64,
    h: f64,
    x0: f64,
    length: f64,
) -> (f64, f64, [f64; 3]) {
    let p = sim.particles();
    let (mut tau, mut sigma) = (0.0, 0.0);
    let (mut mean, mut volume) = ([0.0; 3], 0.0);
    for i in sim.bodies()[0].range() {
        let [px, py] = [p.x[i][0] as f64, p.x[i][1] as f64];
        if (py - y).abs() > 0.5 * h {
            continue;
        }
        let s = p.stress[i].components();
        let v = p.volume[i] as f64;
        let (sxx, syy, sxy) = (s[0] as f64, s[1] as f64, s[3] as f64);
        tau += sxy * v / h;
        sigma -= syy * v / h;
        if px > x0 + 0.25 * length && px < x0 + 0.75 * length {
            mean[0] -= sxx * v;
            mean[1] -= syy * v;
            mean[2] += sxy * v;
            volume += v;
        }
    }
    (tau, sigma, mean.map(|m| m / volume.max(1e-300)))
}

/// The lid's mean height and its tilt (the least-squares slope of its particles' heights
/// against x, times its length): (m, m).
fn lid_shape(sim: &Simulation<D2>) -> (f64, f64) {
    let p = sim.particles();
    let r = sim.bodies()[5].range();
    let n = r.len() as f64;
    let (mut sx, mut sy) = (0.0, 0.0);
    for i in r.clone() {
        sx += p.x[i][0] as f64;
        sy += p.x[i][1] as f64;
    }
    let (mx, my) = (sx / n, sy / n);
    let (mut sxx, mut sxy) = (0.0, 0.0);
    for i in r {
        let dx = p.x[i][0] as f64 - mx;
        sxx += dx * dx;
        sxy += dx * (p.x[i][1] as f64 - my);
    }
    (my, sxy / sxx * 0.1)
}
