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
