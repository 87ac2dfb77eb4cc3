//! Contact between bodies on the grid (Sec. 4.3): momentum, no interpenetration, separation;
//! and no contact work for bodies that are apart.

mod common;

use common::*;
use mpm::{BodyConfig, D2, D3, Dim, Shape, Simulation};

fn ball<D: Dim>(name: &str, c: [f64; 3], r: f64, v: f64) -> BodyConfig {
    BodyConfig::new(
        name,
        Shape::ball(&c[..D::DIM], r),
        elastic(1e5, 0.3, 1000.0),
    )
    .with_velocity(&cut::<D>([v, 0.0, 0.0]))
}

fn collide<D: Dim>(friction: Option<f64>) {
    let h = if D::DIM == 2 { 0.01 } else { 0.02 };
    let mut b = Simulation::<D>::builder(&cut::<D>([1.0, 1.0, 1.0]), h)
        .gravity(&vec![0.0; D::DIM])
        .body(ball::<D>("left", [0.35, 0.5, 0.5], 0.1, 0.5))
        .body(ball::<D>("right", [0.65, 0.52, 0.5], 0.1, -0.5));
    if let Some(mu) = friction {
        b = b.contact_friction(mu);
    }
    let mut sim = b.build().unwrap();
    let p0 = sim.diagnostics().momentum;
    let scale = sim.bodies()[0].stats().mass * 0.5;
    let mut touched = false;
    while sim.time() < 0.4 {
        sim.step().unwrap();
        let (a, b) = (sim.bodies()[0].stats(), sim.bodies()[1].stats());
        assert!(
            a.bbox_max[0] < b.bbox_min[0],
            "{}D: bodies interpenetrate at t = {}",
            D::DIM,
            sim.time()
        );
        let p = sim.diagnostics().momentum;
        for k in 0..D::DIM {
            assert!(
                (p[k] - p0[k]).abs() < 1e-5 * scale,
                "{}D: momentum {p0:?} -> {p:?}",
                D::DIM
            );
        }
        touched |= sim.diagnostics().dissipated_contact > 0.0;
    }
    assert!(touched, "{}D: the bodies never met", D::DIM);
    let (va, vb) = (
        sim.bodies()[0].stats().momentum[0],
        sim.bodies()[1].stats().momentum[0],
    );
    assert!(
        va < 0.0 && vb > 0.0,
        "{}D: bodies did not separate (momenta {va}, {vb})",
        D::DIM
    );
    // contact never adds energy
    let d = sim.diagnostics();
    assert!(d.dissipated_contact >= 0.0);
    assert!(d.total_energy() < 2.0 * 0.5 * scale * 0.5 * 1.0001);
}

#[test]
fn two_elastic_balls_collide_conserve_momentum_and_separate() {
    collide::<D2>(None);
    collide::<D3>(None);
}

#[test]
fn frictional_contact_conserves_momentum_too() {
    collide::<D2>(Some(0.3));
    collide::<D3>(Some(0.3));
}

fn apart<D: Dim>() {
    let mut sim = Simulation::<D>::builder(&cut::<D>([1.0, 1.0, 1.0]), 0.02)
        .gravity(&vec![0.0; D::DIM])
        .body(ball::<D>("a", [0.2, 0.5, 0.5], 0.1, 0.0))
        .body(ball::<D>("b", [0.8, 0.5, 0.5], 0.1, 0.0))
        .build()
        .unwrap();
    for _ in 0..10 {
        sim.step().unwrap();
    }
    assert_eq!(sim.diagnostics().dissipated_contact, 0.0);
    // bodies apart allocate no mass-gradient storage: the contact pass has nothing to do
    assert!(sim.bodies().iter().all(|b| b.grid().mass_grad.is_empty()));
}

#[test]
fn bodies_apart_do_no_contact_work() {
    apart::<D2>();
    apart::<D3>();
}

/// A kinematic plate keeps its velocity, pushes the block it meets, and the force it feels is
/// the momentum it gives away (Newton's third law through the grid contact).
#[test]
fn a_kinematic_plate_keeps_its_velocity_and_pushes() {
    let plate = BodyConfig::new(
        "plate",
        Shape::cuboid(&[0.1, 0.3], &[0.15, 0.7]),
        elastic(1e5, 0.3, 1000.0),
    )
    .with_velocity(&[0.5, 0.0])
    .kinematic();
    let block = BodyConfig::new(
        "block",
        Shape::cuboid(&[0.3, 0.4], &[0.5, 0.6]),
        elastic(1e5, 0.3, 1000.0),
    );
    let mut sim = Simulation::<D2>::builder(&[1.0, 1.0], 0.01)
        .gravity(&[0.0, 0.0])
        .body(plate)
        .body(block)
        .build()
        .unwrap();
    let p_plate = sim.bodies()[0].stats().momentum;
    let mut impulse_on_plate = 0.0;
    while sim.time() < 0.5 {
        let dt = sim.step().unwrap().dt;
        impulse_on_plate += sim.bodies()[0].stats().contact_force[0] * dt;
        assert!(sim.bodies()[0].stats().bbox_max[0] < sim.bodies()[1].stats().bbox_min[0]);
    }
    assert_eq!(
        sim.bodies()[0].stats().momentum,
        p_plate,
        "the plate's momentum never changes"
    );
    let p_block = sim.bodies()[1].stats().momentum[0];
    assert!(
        p_block > 0.5 * sim.bodies()[1].stats().mass * 0.5,
        "the block was pushed: {p_block}"
    );
    assert!(
        (impulse_on_plate + p_block).abs() < 1e-3 * p_block,
        "impulse on the plate {impulse_on_plate} vs momentum of the block {p_block}"
    );
}

/// A von Mises block squeezed by a kinematic plate on a frictionless floor in plane strain
/// flows at σ_yy = 2σ_y/√3: the plate feels that stress times the block's width.
#[test]
fn a_von_mises_block_under_a_plate_yields_at_the_plane_strain_limit() {
    let (width, sy) = (0.2, 1.0e4);
    let block = BodyConfig::new(
        "metal",
        Shape::cuboid(&[0.4, 0.0], &[0.4 + width, 0.1]),
        mpm::Material::von_mises(5e5, 0.3, 1000.0, sy),
    );
    let plate = BodyConfig::new(
        "plate",
        Shape::cuboid(&[0.3, 0.11], &[0.7, 0.16]),
        elastic(1e5, 0.3, 1000.0),
    )
    .with_velocity(&[0.0, -0.02])
    .kinematic();
    let h = 0.01;
    let mut sim = Simulation::<D2>::builder(&[1.0, 0.4], h)
        .gravity(&[0.0, 0.0])
        .body(block)
        .body(plate)
        .build()
        .unwrap();
    let (mut impulse, mut time) = (0.0, 0.0);
    while sim.time() < 0.8 {
        let dt = sim.step().unwrap().dt;
        if sim.time() > 0.6 {
            impulse += sim.bodies()[1].stats().contact_force[1] * dt;
            time += dt;
        }
    }
    // the block has widened as it flowed: use its current width
    let s = sim.bodies()[0].stats();
    let current_width = s.bbox_max[0] - s.bbox_min[0] + h / 2.0;
    let expected = 2.0 / 3f64.sqrt() * sy * current_width;
    let force = impulse / time;
    assert!(
        sim.bodies()[0].stats().max_plastic_strain > 0.05,
        "the block did not yield"
    );
    eprintln!("plate force {force:.1} N/m vs {expected:.1}");
    assert!(
        (force - expected).abs() < 0.1 * expected,
        "plate force {force:.1} N/m vs {expected:.1}"
    );
}

/// Bodies held together by sticking or frictional contact at the paper's CFL number of 0.4,
/// from random scenes whose energy rose while the solids updated their stress last
/// (docs/stability.md, "Energy rises between bodies in contact"): a stiff box driving a 1 kPa
/// jelly into another box (GIMP, the paper's rule; the energy rose by 0.21 of its initial
/// value), four default elastic bodies overlapping at the start (B-spline, PIC; by 1.87),
/// and a box thrown into two overlapping ones under Coulomb μ = 0.86 (B-spline; by 0.47).
/// With the step's CFL number held at `STICKING_CFL` while such solids stick, none gains.
#[test]
fn bodies_stuck_together_gain_no_energy() {
    let scenes = [
        r#"{"dim": 2, "domain": {"size": [1.0, 1.0]}, "cell_size": 0.05, "gravity": [0.0, 0.0], "cfl": 0.4, "max_dt": 0.001, "kernel": "gimp", "boundary": {"friction": 0.0}, "bodies": [{"name": "body 0", "shape": {"box": {"min": [0.2106, 0.5349], "max": [0.4043, 0.6349]}}, "material": {"elastic": {"youngs_modulus": 95770000.0, "poisson_ratio": 0.0, "density": 1967.0}}, "velocity": [5.098, 0.0], "particles_per_cell": 2, "flip": 0.0}, {"name": "body 1", "shape": {"box": {"min": [0.4645, 0.4607], "max": [0.5645, 0.5607]}}, "material": {"elastic": {"youngs_modulus": 1000.0, "poisson_ratio": 0.0, "density": 300.0}}, "velocity": [0.0, 0.0], "particles_per_cell": 1, "flip": 0.0, "apic": true}, {"name": "body 2", "shape": {"box": {"min": [0.5811, 0.4477], "max": [0.6811, 0.7438]}}, "material": {"elastic": {"youngs_modulus": 9897000.0, "poisson_ratio": 0.3811, "density": 300.0}}, "velocity": [0.0, 0.0], "particles_per_cell": 2, "flip": 0.0}]}"#,
        r#"{"dim": 2, "domain": {"size": [1.0, 1.0]}, "cell_size": 0.05, "gravity": [0.0, 0.0], "cfl": 0.4, "max_dt": 0.001, "kernel": "quadratic_bspline", "boundary": {"friction": 0.0}, "bodies": [{"name": "body 0", "shape": {"box": {"min": [0.349, 0.4982], "max": [0.449, 0.7857]}}, "material": {"elastic": {"youngs_modulus": 1175000.0, "poisson_ratio": 0.484, "density": 1679.0}}, "velocity": [-3.956, 0.0], "particles_per_cell": 1, "flip": 0.0}, {"name": "body 1", "shape": {"ball": {"center": [0.4414, 0.5834], "radius": 0.1238}}, "material": {"elastic": {"youngs_modulus": 1000.0, "poisson_ratio": 0.0, "density": 2281.0}}, "velocity": [0.0, 0.0], "particles_per_cell": 1, "flip": 0.0}, {"name": "body 2", "shape": {"box": {"min": [0.4021, 0.3527], "max": [0.5021, 0.5631]}}, "material": {"elastic": {"youngs_modulus": 1000.0, "poisson_ratio": 0.0, "density": 1664.0}}, "velocity": [-3.097, 4.054], "particles_per_cell": 1, "flip": 0.0}, {"name": "body 3", "shape": {"box": {"min": [0.2979, 0.483], "max": [0.5959, 0.6623]}}, "material": {"elastic": {"youngs_modulus": 5417000.0, "poisson_ratio": 0.3778, "density": 300.0}}, "velocity": [0.0, 0.0], "particles_per_cell": 1, "flip": 0.0}]}"#,
        r#"{"dim": 2, "domain": {"size": [1.0, 1.0]}, "cell_size": 0.05, "gravity": [0.0, 0.0], "cfl": 0.4, "max_dt": 0.001, "kernel": "quadratic_bspline", "boundary": {"friction": 0.0}, "bodies": [{"name": "body 0", "shape": {"box": {"min": [0.4373, 0.4746], "max": [0.7348, 0.7172]}}, "material": {"elastic": {"youngs_modulus": 85080000.0, "poisson_ratio": 0.0, "density": 300.0}}, "velocity": [0.0, 0.0], "particles_per_cell": 1, "flip": 0.0}, {"name": "body 1", "shape": {"box": {"min": [0.5509, 0.6207], "max": [0.8324, 0.7207]}}, "material": {"elastic": {"youngs_modulus": 1000.0, "poisson_ratio": 0.0, "density": 300.0}}, "velocity": [0.0, 0.0], "particles_per_cell": 3, "flip": 0.0, "apic": true}, {"name": "body 2", "shape": {"box": {"min": [0.5695, 0.5987], "max": [0.7238, 0.6987]}}, "material": {"elastic": {"youngs_modulus": 40580000.0, "poisson_ratio": 0.4755, "density": 1943.0}}, "velocity": [2.375, 0.0], "particles_per_cell": 2, "flip": 0.0}], "contact": {"friction": 0.8639}}"#,
    ];
    for (i, json) in scenes.iter().enumerate() {
        let mut sim = Simulation::<D2>::new(mpm::SceneConfig::from_json(json).unwrap()).unwrap();
        let d0 = sim.diagnostics().clone();
        let scale = d0.kinetic + d0.elastic;
        let mut worst = f64::NEG_INFINITY;
        for _ in 0..300 {
            sim.step().unwrap();
            worst = worst.max((sim.diagnostics().total_energy() - d0.total_energy()) / scale);
        }
        assert!(
            worst < 1e-3,
            "scene {i}: energy rose by {worst:.3} of the initial energy"
        );
    }
}

/// The sticking contact's step bound (`STICKING_CFL`) acts on the bodies it holds together,
/// not on the scene: two soft elastic balls (c ≈ 12 m/s) collide under the paper's sticking
/// rule beside a ball at rest that is 100 times stiffer (c ≈ 120 m/s). While the soft pair is
/// stuck the step stays the stiff ball's, CFL 0.4 · h / (c + |v|): the pair's bound at 0.2 of
/// its own signal speed is five times longer. With the third ball as soft as the pair, the
/// step is the sticking bound's, half the scene's.
#[test]
fn the_sticking_bound_holds_only_the_bodies_in_contact() {
    for stiff in [1e7, 1e5] {
        let h = 0.01;
        let mut sim = Simulation::<D2>::builder(&[1.0, 1.0], h)
            .gravity(&[0.0, 0.0])
            .body(ball::<D2>("left", [0.3, 0.3, 0.0], 0.08, 0.5))
            .body(ball::<D2>("right", [0.5, 0.31, 0.0], 0.08, -0.5))
            .body(BodyConfig::new(
                "apart",
                Shape::ball(&[0.5, 0.75], 0.1),
                elastic(stiff, 0.3, 1000.0),
            ))
            .build()
            .unwrap();
        let cfl = sim.scene().cfl;
        let e0 = sim.diagnostics().total_energy();
        let (mut stuck_steps, mut worst) = (0, 0.0f64);
        for _ in 0..3000 {
            if sim.step_cfl() < cfl {
                stuck_steps += 1;
                let v = sim.diagnostics().max_speed;
                let unbound = mpm::sim::cfl_time_step(cfl, h, sim.max_wave_speed() + v, 0.0, 1.0);
                let ratio = sim.stable_dt() / unbound;
                if stiff > 1e5 {
                    assert!(
                        (ratio - 1.0).abs() < 1e-6,
                        "the stiff ball's step was cut to {ratio}"
                    );
                } else {
                    assert!(
                        (ratio - 0.5).abs() < 1e-6,
                        "the stuck step is {ratio} of the scene's"
                    );
                }
            }
            sim.step().unwrap();
            worst = worst.max(sim.diagnostics().total_energy() - e0);
        }
        assert!(
            stuck_steps > 10,
            "the balls never stuck ({stuck_steps} steps)"
        );
        assert!(
            worst < 1e-3 * e0,
            "energy rose by {worst:.3e} of {e0:.3e} J/m"
        );
    }
}

/// A pair held together by the sticking rule that has come to rest and fallen wholly asleep
/// updates no stress, so its waves no longer bound the step, as a sleeping body's do not
/// outside contact: an elastic block resting on another on the floor, sleeping on. While they
/// settle awake the sticking bound cuts the step; once both sleep the step is the scene's
/// again (the gravity bound and `max_dt` only), not 0.2 · h / c. Before this held, a drop
/// onto the page's plastic bunny stepped 1.7 times as often after everything slept again.
#[test]
fn a_sleeping_pair_leaves_the_sticking_bound() {
    let h = 0.02;
    let block = |name: &str, y0: f64| {
        BodyConfig::new(
            name,
            Shape::cuboid(&[0.4, y0], &[0.6, y0 + 0.1]),
            elastic(1e5, 0.3, 1000.0),
        )
    };
    let mut sim = Simulation::<D2>::builder(&[1.0, 1.0], h)
        .wall_friction(0.5)
        .body(block("lower", 0.0))
        .body(block("upper", 0.1))
        .build()
        .unwrap();
    sim.sleep_when_at_rest();
    let cfl = sim.scene().cfl;
    let (mut stuck_awake, mut asleep_steps) = (0, 0);
    for _ in 0..20_000 {
        sim.step().unwrap();
        let all_asleep = sim.asleep() == sim.particles().len();
        if !all_asleep && sim.step_cfl() < cfl {
            stuck_awake += 1;
        }
        if all_asleep && sim.step_cfl() < cfl {
            asleep_steps += 1;
            let g = sim.scene().gravity_vector();
            let g = (g[0] * g[0] + g[1] * g[1]).sqrt();
            let free =
                mpm::sim::cfl_time_step(cfl, h, sim.diagnostics().max_speed, g, sim.scene().max_dt);
            assert!(
                (sim.stable_dt() / free - 1.0).abs() < 1e-9,
                "asleep, the step is {:.3e} s, the scene's {free:.3e} s",
                sim.stable_dt()
            );
            if asleep_steps > 20 {
                break;
            }
        }
    }
    assert!(stuck_awake > 10, "the blocks never stuck awake");
    assert!(
        asleep_steps > 20,
        "the pair never slept while held ({asleep_steps} steps)"
    );
}
