//! Particle–grid transfers: APIC keeps the angular momentum that PIC smears away.

// Real is f32 by default, f64 with the `f64` feature: the casts to f64 are no-ops there.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

mod common;

use common::*;
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
