//! The low column on a rough floor and Bui et al. (2008)'s set-up over three grids.

use crate::report::*;
use crate::validation::*;
use mpm::KernelKind;
use std::fmt::Write;

/// The low plane column (a = 0.5, H0 = 0.1 m, floor μ = 0.6) at φ = 20°, 30°, 40° and Bui et
/// al. (2008)'s set-up against a back wall, at 10, 20 and 40 cells per column height: the
/// deposit's measures at each grid, then their change per halving of h.
pub fn lowcolumn_study(md: &mut String, path: &std::path::Path) {
    let cases: [(&str, Option<f64>); 4] = [
        ("φ = 20°", Some(20.0)),
        ("φ = 30°", Some(30.0)),
        ("φ = 40°", Some(40.0)),
        ("Bui et al. (2008), φ = 19.8°, back wall", None),
    ];
    let hs = [0.01, 0.005, 0.0025];
    let mut rows = Vec::new();
    let mut halving = Vec::new();
    for (name, phi) in cases {
        let mut runs: Vec<LowColumn> = Vec::new();
        for h in hs {
            let n = Numerics::new(h, KernelKind::Gimp);
            let r = match phi {
                Some(phi) => low_column(phi, &n, 4.0),
                None => plane_deposit(bui_scene(&n), true, 4.0),
            };
            println!("lowcolumn {name} {}: {r:?}", n.label());
            let d = &r.deposit;
            rows.push(vec![
                name.to_string(),
                format!("{:.0}", 0.1 / h),
                format!("{:.3} / {:.3}", d.runout, d.runout_edge),
                format!(
                    "{:+.0} / {:+.0} %",
                    100.0 * (d.runout / lube_runout(0.5) - 1.0),
                    100.0 * (d.runout_edge / lube_runout(0.5) - 1.0)
                ),
                format!("{:.1}", d.flank()),
                format!("{:.1}", r.plane_strain_angle),
                format!("{:+.1}°", d.flank() - r.plane_strain_angle),
                format!("{:+.3}", d.foot),
                format!("{:.3} ({:.1})", d.toe, d.toe_rows),
                format!("{:.2}", d.plateau),
                format!("{:.3}", d.height),
                match &r.failure {
                    Some(f) => f.clone(),
                    None if r.settled_at >= 4.0 - 1e-6 => "moving at 4 s".to_string(),
                    None => format!("{:.2}", r.settled_at),
                },
                format!("{:.0}", r.cost.wall_seconds),
            ]);
            std::fs::write(path, &*md).unwrap();
            runs.push(r);
        }
        for w in runs.windows(2) {
            let (a, b) = (&w[0].deposit, &w[1].deposit);
            halving.push(vec![
                name.to_string(),
                String::new(),
                format!(
                    "{:+.3} / {:+.3}",
                    b.runout - a.runout,
                    b.runout_edge - a.runout_edge
                ),
                format!("{:+.1}°", b.flank() - a.flank()),
                format!("{:+.3}", b.toe - a.toe),
                format!("{:+.2}", b.plateau - a.plateau),
                format!("{:+.1} points", 100.0 * (b.height - a.height)),
            ]);
        }
    }
    // the cells-per-height column of the halving table
    let mut k = 0;
    for _ in 0..cases.len() {
        for w in hs.windows(2) {
            halving[k][1] = format!("{:.0} → {:.0}", 0.1 / w[0], 0.1 / w[1]);
            k += 1;
        }
    }
    let _ = writeln!(
        md,
        "## Drucker–Prager: a low column on a rough floor\n\nThe plane column a = 0.5 (L0 = 0.2 m, H0 = 0.1 m, collapsing both ways; E = 350 kPa, ν = 0.3, 2200 kg/m³) on a floor with μ = 0.6, and Bui et al. (2008)'s set-up (0.2 m wide, 0.1 m high against a wall, φ = 19.8°, E = 0.84 MPa, 2650 kg/m³, floor and wall μ = 0.6), default numerics (GIMP, ppc 2, CFL 0.4, APIC base α = 0.05, start–stop cone). Run-out (L − L0)/L0: farthest particle / deposit edge (thinner than 2.5 % of H0), and against Lube et al. (2005)'s 1.2 a = 0.6. Flank: least-squares slope of the surface between 20 % and 80 % of the deposit's height (mean of the two sides). Foot: where the flank line meets the floor, (x − L0)/L0. Toe: how far the farthest particle lies beyond the foot, over L0 (in brackets the thickest the deposit is there, in particle rows). Plateau: the top's half-width (width against the wall) within one cell of H0, over L0. Issue 36: run-out within 20 % of 1.2 a at φ = 30°, flank within 3° of φ_ps, toe at most 0.1 L0, plateau kept, at every grid.\n\n{}\n### Change per halving of h\n\n{}",
        table(
            &[
                "case",
                "cells per H0",
                "run-out farthest / edge",
                "vs 1.2 a",
                "flank (°)",
                "φ_ps (°)",
                "flank − φ_ps",
                "foot",
                "toe (rows)",
                "plateau",
                "H∞/H0",
                "at rest (s)",
                "s",
            ],
            &rows
        ),
        table(
            &[
                "case",
                "cells per H0",
                "run-out farthest / edge",
                "flank",
                "toe",
                "plateau",
                "H∞/H0",
            ],
            &halving
        )
    );
    std::fs::write(path, &*md).unwrap();
}
