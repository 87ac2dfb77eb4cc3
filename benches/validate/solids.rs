//! The solids' cases: the elastic bar, the dilatational wave, the von Mises squeeze, FLIP at
//! walls and contacts, the soft column at rest.

use crate::report::*;
use crate::tables::pct;
use crate::validation::*;
use mpm::{D2, D3, KernelKind};
use std::fmt::Write;

/// The free–free elastic bar's first axial mode, 2D and 3D.
pub fn bar(md: &mut String) {
    let gimp = |h: f64| Numerics::new(h, KernelKind::Gimp);
    let mut rows = Vec::new();
    for (dim, h, alpha) in [
        (2, 0.0125, 1.0),
        (2, 0.0125, 0.0),
        (2, 0.00625, 1.0),
        (3, 0.025, 1.0),
    ] {
        let n = gimp(h).flip(alpha);
        let b = if dim == 2 {
            vibrating_bar::<D2>("vibrating_bar_2d.json", &n, 3.0)
        } else {
            vibrating_bar::<D3>("vibrating_bar_3d.json", &n, 3.0)
        };
        println!("bar {dim}D {}: {b:?}", n.label());
        rows.push(vec![
            format!("{dim}D"),
            n.label(),
            format!("{:.5} / {:.5}", b.period, b.period_exact),
            pct(b.period_error()),
            format!("{:.4e} / {:.4e}", b.amplitude, b.amplitude_exact),
            pct(b.amplitude_error()),
            format!("{:.3}", b.amplitude_kept),
            format!("{:.2e}", b.l2_error),
            format!("{:.1}", b.cost.wall_seconds),
        ]);
    }
    let _ = writeln!(
        md,
        "## Elastic bar, first axial mode\n\n{}",
        table(
            &[
                "dim",
                "numerics",
                "period (s) sim / exact",
                "error",
                "amplitude (m) sim / exact",
                "error",
                "last/first peak",
                "L2 error",
                "s"
            ],
            &rows
        )
    );
}

/// The dilatational wave speed over three cell sizes.
pub fn wave(md: &mut String) {
    let gimp = |h: f64| Numerics::new(h, KernelKind::Gimp);
    let mut rows = Vec::new();
    for h in [0.02, 0.01, 0.005] {
        let n = gimp(h).flip(1.0);
        let w = wave_speed(&n);
        println!("wave {}: {w:?}", n.label());
        rows.push(vec![
            n.label(),
            format!("{:.3}", w.speed),
            format!("{:.3}", w.speed_exact),
            pct(w.error()),
            format!("{:.3}", w.bar_speed),
            format!("{:.1}", w.cost.wall_seconds),
        ]);
    }
    let _ = writeln!(
        md,
        "## Dilatational wave speed\n\n{}",
        table(
            &[
                "numerics",
                "measured c (m/s)",
                "√((K+4G/3)/ρ)",
                "error",
                "bar speed √(E/ρ)",
                "s"
            ],
            &rows
        )
    );
}

/// The von Mises block squeezed by a driven plate, 2D and 3D.
pub fn squeeze(md: &mut String) {
    let gimp = |h: f64| Numerics::new(h, KernelKind::Gimp);
    let mut rows = Vec::new();
    let mut curves = String::new();
    for (dim, h) in [(2, 0.01), (2, 0.005), (3, 0.02)] {
        let n = gimp(h);
        let s = if dim == 2 {
            crate::validation::squeeze::<D2>("von_mises_compression_2d.json", &n, 0.04)
        } else {
            crate::validation::squeeze::<D3>("von_mises_compression_3d.json", &n, 0.04)
        };
        println!(
            "squeeze {dim}D {}: max {} plateau {} modulus {}",
            n.label(),
            s.max_error,
            s.plateau_error,
            s.modulus_error
        );
        rows.push(vec![
            format!("{dim}D"),
            n.label(),
            pct(s.modulus_error),
            pct(s.plateau_error),
            format!("{:.3}", s.max_error),
            format!("{:.1}", s.cost.wall_seconds),
        ]);
        let _ = writeln!(
            curves,
            "\n{dim}D, {}: strain, σ/σ_y simulated, closed form\n",
            n.label()
        );
        let k = s.curve.len() / 12;
        let pts: Vec<Vec<String>> = s
            .curve
            .iter()
            .step_by(k.max(1))
            .map(|c| {
                vec![
                    format!("{:.4}", c.0),
                    format!("{:.3}", c.1 / s.yield_stress),
                    format!("{:.3}", c.2 / s.yield_stress),
                ]
            })
            .collect();
        curves.push_str(&table(&["strain", "σ/σ_y sim", "σ/σ_y exact"], &pts));
    }
    let _ = writeln!(
        md,
        "## von Mises block squeezed by a driven plate\n\n{}\nThe curves, sampled:\n{curves}",
        table(
            &[
                "dim",
                "numerics",
                "elastic slope error",
                "plateau error",
                "max |σ − σ_exact|/σ_y",
                "s"
            ],
            &rows
        )
    );
}

/// FLIP at walls and between bodies: the energy rise over α, kernels and dimensions.
pub fn flip(md: &mut String) {
    let mut rows = Vec::new();
    let alphas = [0.0, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 1.0];
    let cases: [(KernelKind, f64, bool); 6] = [
        (KernelKind::Gimp, 0.01, false),
        (KernelKind::Gimp, 0.05, false),
        (KernelKind::Gimp, 0.01, true),
        (KernelKind::Linear, 0.01, false),
        (KernelKind::Linear, 0.01, true),
        (KernelKind::QuadraticBspline, 0.01, true),
    ];
    for (dim, (k, h, two)) in cases.iter().map(|c| (2, *c)).chain([
        (3, (KernelKind::Gimp, 0.02, false)),
        (3, (KernelKind::Gimp, 0.02, true)),
    ]) {
        let n = Numerics::new(h, k);
        let mut row = vec![
            format!("{dim}D"),
            if two { "two boxes" } else { "one box, walls" }.to_string(),
            kernel_name(k).to_string(),
            format!("{:.1}", 0.08 / h),
        ];
        for &alpha in &alphas {
            let r = if dim == 2 {
                flip_impacts::<D2>(&n, alpha, two, IMPACT_TIME)
            } else {
                flip_impacts::<D3>(&n, alpha, two, IMPACT_TIME)
            };
            println!("flip {dim}D {} two={two} α={alpha}: {r:?}", n.label());
            row.push(if r.failure.is_some() {
                "diverged".to_string()
            } else {
                format!("{:+.1} % / {:.2}", 100.0 * r.energy_rise, r.energy_kept)
            });
        }
        rows.push(row);
    }
    let mut header = vec![
        "dim".to_string(),
        "case".to_string(),
        "kernel".to_string(),
        "cells across".to_string(),
    ];
    header.extend(alphas.iter().map(|a| format!("α = {a}")));
    let header: Vec<&str> = header.iter().map(|s| s.as_str()).collect();
    let _ = writeln!(
        md,
        "## FLIP at walls and between bodies\n\nStiff elastic boxes (0.08 m, E = 10.5 MPa) in zero gravity thrown at the ceiling (9.14 m/s) or at each other (±5 m/s), for {IMPACT_TIME} s: the largest rise of the total energy above its initial value / the fraction of the energy left at the end. A rise above zero is energy that walls or contacts created.\n\n{}",
        table(&header, &rows)
    );
}

/// The soft column resting for 60 s with each kernel (cell crossing).
pub fn resting(md: &mut String) {
    let mut rows = Vec::new();
    for k in [
        KernelKind::Linear,
        KernelKind::Gimp,
        KernelKind::QuadraticBspline,
    ] {
        let n = Numerics::new(0.02, k).flip(0.0);
        let r = resting_column(&n, 60.0);
        println!("resting {}: {r:?}", n.label());
        rows.push(vec![
            n.label(),
            format!("{}", r.cost.steps),
            r.failure.clone().unwrap_or_else(|| "ran".into()),
            format!("{:.3}", 1e3 * r.settlement),
            format!("{:.3}", 1e3 * r.settlement_exact),
            pct(r.settlement / r.settlement_exact - 1.0),
            format!("{:+.2e}", r.drift_rate),
            format!("{:.1e}", r.max_speed),
            format!("{:.1}", r.cost.wall_seconds),
        ]);
    }
    let _ = writeln!(
        md,
        "## Soft column resting for 60 s (cell crossing)\n\n{}",
        table(
            &[
                "numerics",
                "steps",
                "outcome",
                "settlement (mm)",
                "exact (mm)",
                "error",
                "drift (m/s)",
                "final max speed (m/s)",
                "s"
            ],
            &rows
        )
    );
}
