//! Particle–grid transfers: APIC keeps the angular momentum that PIC smears away.

// Real is f32 by default, f64 with the `f64` feature: the casts to f64 are no-ops there.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

mod common;

use common::*;
use mpm::math::SymTensor;
use mpm::{BodyConfig, D2, D3, Dim, KernelKind, Shape, Simulation};

/// The angular momentum about z through the centre of mass, Σ m r × v, plus APIC's affine
/// part Σ m D (C_yx − C_xy) (D = h²/4 for the quadratic B-spline), and the moment of inertia.
fn angular<D: Dim>(sim: &Simulation<D>, h: f64) -> (f64, f64) {
    let p = sim.particles();
    let c = sim.bodies()[0].stats().center_of_mass;
    let (mut l, mut i) = (0.0, 0.0);
    for k in 0..p.len() {
        let (x, y) = (p.x[k][0] as f64 - c[0], p.x[k][1] as f64 - c[1]);
        let (vx, vy) = (p.v[k][0] as f64, p.v[k][1] as f64);
        let m = p.mass[k] as f64;
        l += m * (x * vy - y * vx);
        i += m * (x * x + y * y);
        if !p.affine.is_empty() {
            let cyx = D::grad_entry(&p.affine[k], 1, 0) as f64;
            let cxy = D::grad_entry(&p.affine[k], 0, 1) as f64;
            l += m * h * h / 4.0 * (cyx - cxy);
        }
    }
    (l, i)
}

/// A stiff spinning ball in free flight: the fraction of its angular momentum left after `t`
/// seconds.
fn spin_kept<D: Dim>(apic: bool, t: f64) -> f64 {
    let h = if D::DIM == 2 { 0.02 } else { 0.04 };
    let omega = 3.0;
    let mut b = BodyConfig::new(
        "ball",
        Shape::ball(&cut::<D>([0.5, 0.5, 0.5]), 0.2),
        elastic(2e6, 0.3, 1000.0),
    );
    if apic {
        b = b.with_apic();
    }
    let mut sim = Simulation::<D>::builder(&cut::<D>([1.0, 1.0, 1.0]), h)
        .gravity(&vec![0.0; D::DIM])
        .kernel(KernelKind::QuadraticBspline)
        .body(b)
        .build()
        .unwrap();
    {
        let p = sim.particles_mut();
        for k in 0..p.len() {
            let (x, y) = (p.x[k][0] - 0.5, p.x[k][1] - 0.5);
            p.v[k][0] = -omega * y;
            p.v[k][1] = omega * x;
        }
    }
    sim.refresh_diagnostics();
    let (l0, i0) = angular(&sim, h);
    assert!((l0 / i0 - omega as f64).abs() < 1e-3);
    let p0 = sim.diagnostics().momentum;
    sim.advance(t).unwrap();
    let p1 = sim.diagnostics().momentum;
    for a in 0..D::DIM {
        assert!(
            (p1[a] - p0[a]).abs() < 1e-3,
            "{}D apic={apic}: momentum {p0:?} -> {p1:?}",
            D::DIM
        );
    }
    angular(&sim, h).0 / l0
}

#[test]
fn apic_keeps_the_spin_that_pic_loses() {
    for (apic_kept, pic_kept, dim) in [
        (spin_kept::<D2>(true, 1.0), spin_kept::<D2>(false, 1.0), 2),
        (spin_kept::<D3>(true, 0.3), spin_kept::<D3>(false, 0.3), 3),
    ] {
        // APIC conserves angular momentum (up to f32 round-off and the stress that the
        // centrifugal load builds); PIC loses a share of it at every transfer.
        assert!(
            (apic_kept - 1.0).abs() < 0.01,
            "{dim}D: APIC kept {apic_kept:.4} of the angular momentum"
        );
        assert!(
            pic_kept < 0.5,
            "{dim}D: PIC kept {pic_kept:.4} of the angular momentum"
        );
    }
}

#[test]
fn apic_needs_a_spreading_kernel() {
    let b = BodyConfig::new(
        "b",
        Shape::cuboid(&[0.2, 0.2], &[0.4, 0.4]),
        elastic(1e5, 0.3, 1000.0),
    )
    .with_apic();
    let err = Simulation::<D2>::builder(&[1.0, 1.0], 0.05)
        .kernel(KernelKind::Linear)
        .body(b)
        .build()
        .unwrap_err();
    assert!(
        err.to_string().starts_with(
            "bodies[0].apic = true: needs the \"gimp\" or \"quadratic_bspline\" kernel"
        ),
        "{err}"
    );
}

/// A stress-free box drifting in free flight under the linear kernel, with its particles
/// placed on node lines (x/h whole numbers in f32, as the step meets them by rounding): its
/// momentum and kinetic energy are kept and no stress appears. Without the kernel's nudge off
/// the node line the face particles' next node weighs nothing but has a gradient: the force
/// there is dropped and that node's velocity of 0 strains the particle from nothing.
fn drift_across_node_lines<D: Dim>() -> (f64, f64, f64) {
    let h = 1.0 / 16.0;
    let n = 17; // spacing h/2 from 0.5 to 1.0: every other particle on a node line
    let mut positions = Vec::new();
    for i in 0..n {
        for j in 0..n {
            for k in 0..if D::DIM == 3 { n } else { 1 } {
                let c = [i, j, k].map(|a| 0.5 + a as f64 * h / 2.0);
                positions.push(c[..D::DIM].to_vec());
            }
        }
    }
    let v = cut::<D>([0.5, 0.25, -0.125]);
    let body = BodyConfig::new(
        "box",
        Shape::Points {
            positions,
            particle_volume: Some((h / 2.0).powi(D::DIM as i32)),
        },
        elastic(1e6, 0.3, 1000.0),
    )
    .with_velocity(&v);
    let mut sim = Simulation::<D>::builder(&vec![2.0; D::DIM], h)
        .gravity(&vec![0.0; D::DIM])
        .kernel(KernelKind::Linear)
        .body(body)
        .build()
        .unwrap();
    let d0 = sim.diagnostics().clone();
    let p_scale: f64 = d0.momentum.iter().map(|m| m * m).sum::<f64>().sqrt();
    let (mut momentum, mut stress) = (0.0f64, 0.0f64);
    for _ in 0..40 {
        sim.step().unwrap();
        let d = sim.diagnostics();
        let dm = (0..3)
            .map(|a| (d.momentum[a] - d0.momentum[a]).powi(2))
            .sum::<f64>()
            .sqrt();
        momentum = momentum.max(dm / p_scale);
        let p = sim.particles();
        for s in &p.stress {
            stress = stress.max((s.j2() as f64).sqrt());
        }
    }
    let kinetic = (sim.diagnostics().kinetic - d0.kinetic).abs() / d0.kinetic;
    (momentum, stress, kinetic)
}

#[test]
fn linear_kernel_keeps_a_drifting_box_unstrained_on_node_lines() {
    for (dim, (momentum, stress, kinetic)) in [
        (2, drift_across_node_lines::<D2>()),
        (3, drift_across_node_lines::<D3>()),
    ] {
        let report = format!(
            "{dim}D: momentum changed by {momentum:.1e} of itself, √J2 up to {stress:.2e} Pa, kinetic energy by {kinetic:.1e}"
        );
        eprintln!("{report}");
        assert!(momentum < 1e-5, "{report}");
        assert!(stress < 1.0, "{report}");
        assert!(kinetic < 1e-5, "{report}");
    }
}
