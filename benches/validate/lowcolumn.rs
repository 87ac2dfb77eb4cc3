//! The low column on a rough floor over three grids, against the bands, and Bui et al.
//! (2008)'s aluminium-rod collapse against the experiment's digitised surface and failure line.

use crate::report::*;
use crate::tables::{at_rest, holds};
use crate::validation::*;
use mpm::KernelKind;
use std::fmt::Write;

/// The grids of both studies: 10, 20 and 40 cells per column height (H0 = 0.1 m).
const CELL_SIZES: [f64; 3] = [0.01, 0.005, 0.0025];

/// The low plane column (a = 0.5, H0 = 0.1 m, floor μ = 0.6) at φ = 20°, 30°, 40°, at 10, 20
/// and 40 cells per column height: the deposit's measures against the bands at each grid,
/// then their change per halving of h.
pub fn lowcolumn_study(md: &mut String, path: &std::path::Path, grids: &crate::grids::Grids) {
    let a = 0.5;
    let sizes: Vec<f64> = grids.cells.iter().map(|k| 0.1 / k).collect();
    let law = lube_runout(a);
    let mut rows = Vec::new();
    let mut halving = Vec::new();
    for phi in [20.0, 30.0, 40.0] {
        let mut runs: Vec<LowColumn> = Vec::new();
        for &h in &sizes {
            let n = grids.numerics(h);
            let r = low_column(phi, &n, 4.0);
            println!("lowcolumn φ = {phi} {}: {r:?}", n.label());
            let d = &r.deposit;
            let err = d.runout_thin / law - 1.0;
            let gap = d.flank() - r.plane_strain_angle;
            rows.push(vec![
                format!("{phi} ({:.1})", r.plane_strain_angle),
                format!("{:.0}", 0.1 / h),
                format!("{:.3} / {:.3}", d.runout_thin, d.runout),
                format!("{:+.0} %", 100.0 * err),
                format!(
                    "{} / {}",
                    holds(within(err, RUNOUT_BAND)),
                    holds(farthest_is_sane(d.runout, a))
                ),
                format!("{:.1} ({gap:+.1}°)", d.flank()),
                holds(within(gap, FLANK_BAND)),
                format!("{:.3} ({:.1})", d.toe, d.toe_rows),
                format!("{:.2}", d.plateau),
                format!("{:.3}", d.height),
                holds(d.height >= 1.0 - h / 0.1),
                at_rest(&r.failure, r.settled_at, Some(4.0)),
                format!("{:.0}", r.cost.wall_seconds),
            ]);
            std::fs::write(path, &*md).unwrap();
            runs.push(r);
        }
        for (i, w) in runs.windows(2).enumerate() {
            let (p, q) = (&w[0].deposit, &w[1].deposit);
            halving.push(vec![
                format!("{phi}"),
                format!("{:.0} → {:.0}", 0.1 / sizes[i], 0.1 / sizes[i + 1]),
                format!(
                    "{:+.3} / {:+.3}",
                    q.runout_thin - p.runout_thin,
                    q.runout - p.runout
                ),
                format!("{:+.1}°", q.flank() - p.flank()),
                format!("{:+.3}", q.toe - p.toe),
                format!("{:+.1} points", 100.0 * (q.height - p.height)),
            ]);
        }
    }
    let _ = writeln!(
        md,
        "## Low columns on a rough floor at {} cells per H0, {} (a = 0.5, floor μ = {ROUGH_FLOOR})\n\nThe plane column a = 0.5 (L0 = 0.2 m, H0 = 0.1 m, collapsing both ways; E = 350 kPa, ν = 0.3, 2200 kg/m³), default numerics. Run-out (L − L0)/L0 where the deposit is one grain ({} mm) thick / at the farthest particle, against Lube et al. (2005)'s 1.2 a = {law:.2}: within −20 % / +25 %, the farthest at most 2a. Flank: least-squares slope of the surface between 20 % and 80 % of the deposit's height (mean of the two sides), in [φ_ps − 6°, φ_ps + 1°]. Toe: how far the farthest particle lies beyond the flank line's foot, over L0 (in brackets the thickest the deposit is there, in particle rows). Plateau: the top's half-width within one cell of H0, over L0. Top: H∞ within one cell of H0.\n\n{}\n{}",
        grids.named(40.0),
        grids.order(),
        1e3 * GRAIN,
        table(
            &[
                "φ (φ_ps) (°)",
                "cells per H0",
                "run-out one grain / farthest",
                "vs 1.2 a",
                "−20/+25 % / ≤ 2a",
                "flank (°) (vs φ_ps)",
                "−6°/+1°",
                "toe (rows)",
                "plateau",
                "H∞/H0",
                "top",
                "at rest (s)",
                "s",
            ],
            &rows
        ),
        halving_table(
            &[
                "φ (°)",
                "cells per H0",
                "run-out one grain / farthest",
                "flank",
                "toe",
                "H∞/H0",
            ],
            &halving
        )
    );
    std::fs::write(path, &*md).unwrap();
}

/// Bui et al. (2008)'s set-up at 10, 20 and 40 cells per column height against the
/// experiment: the surface's RMS distance, the flank, the run-out at one grain's thickness,
/// the farthest particle and the failure line's angle.
pub fn bui_study(md: &mut String, path: &std::path::Path) {
    let mut rows = Vec::new();
    let mut experiment = None;
    for h in CELL_SIZES {
        let n = Numerics::new(h, KernelKind::Gimp);
        let b = bui_2008(&n, 4.0);
        println!("bui {}: {b:?}", n.label());
        experiment = Some((
            b.experiment_runout_thin,
            b.experiment_flank,
            b.experiment_failure_angle,
        ));
        let r = &b.run;
        rows.push(vec![
            format!("{:.0}", 0.1 / h),
            format!("{:.1}", 1e3 * b.rms),
            format!("{:.1} ({:+.1}°)", b.flank, b.flank - b.experiment_flank),
            format!(
                "{:.3} ({:+.0} %)",
                b.runout_thin,
                100.0 * (b.runout_thin / b.experiment_runout_thin - 1.0)
            ),
            format!("{:.3}", b.farthest),
            format!(
                "{:.1} ({:+.1}°)",
                b.failure_angle,
                b.failure_angle - b.experiment_failure_angle
            ),
            format!("{:.3}", r.deposit.height),
            at_rest(&r.failure, r.settled_at, Some(4.0)),
            format!("{:.0}", r.cost.wall_seconds),
        ]);
        std::fs::write(path, &*md).unwrap();
    }
    let (runout, flank, failure) = experiment.unwrap_or((f64::NAN, f64::NAN, f64::NAN));
    let _ = writeln!(
        md,
        "## Bui et al. (2008): aluminium rods against a wall, at 10, 20 and 40 cells per H0\n\nThe rods 0.2 m wide and 0.1 m high against the left wall (φ = 19.8°, ψ = 0, c = 0, E = 0.84 MPa, ν = 0.3, 2650 kg/m³), floor and wall μ = {BUI_FLOOR}, default numerics, against the experiment's final surface and failure line digitised from the paper's figure (`tests/data/bui2008_*.csv`, about 1 mm digitising error). The experiment: flank {flank:.1}°, one grain ({} mm) thick at {runout:.3} m from the wall, failure line at {failure:.1}°. RMS: the model's surface height minus the experiment's over its 26 markers. Failure line: through the farthest particle of each cell-high row (10–90 % of H0) that moved less than one grain.\n\n{}",
        1e3 * GRAIN,
        table(
            &[
                "cells per H0",
                "surface RMS (mm)",
                "flank (°) (vs experiment)",
                "one grain thick (m) (vs experiment)",
                "farthest particle (m)",
                "failure line (°) (vs experiment)",
                "H∞/H0",
                "at rest (s)",
                "s",
            ],
            &rows
        )
    );
    std::fs::write(path, &*md).unwrap();
}
