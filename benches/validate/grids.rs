//! The validation claim's resolution sweep of the sand cases.

use crate::report::*;
use crate::tables::*;
use crate::validation::*;
use mpm::KernelKind;
use std::fmt::Write;

/// Which grids and which stress order a resolution sweep runs: by default 10, 20 and 40 cells
/// per characteristic length with the default numerics; `coarse` runs 10 and 20 only, `fine`
/// 40 only (so that the finest grids can run last, in a run of their own); `stress-last`
/// updates the sand's stress at the end of the step instead of first.
pub struct Grids {
    /// Cells per characteristic length, coarsest first.
    pub cells: Vec<f64>,
    pub stress_last: bool,
}

impl Grids {
    pub fn from_filters(filters: &Filters) -> Self {
        let has = |s: &str| filters.0.iter().any(|f| f == s);
        let cells = match (has("coarse"), has("fine")) {
            (true, false) => vec![10.0, 20.0],
            (false, true) => vec![40.0],
            _ => vec![10.0, 20.0, 40.0],
        };
        Grids {
            cells,
            stress_last: has("stress-last"),
        }
    }
    /// The default numerics (GIMP) at cell size `h`, with the sweep's stress order.
    pub fn numerics(&self, h: f64) -> Numerics {
        let n = Numerics::new(h, KernelKind::Gimp);
        if self.stress_last {
            n.stress_last(true)
        } else {
            n
        }
    }
    /// The grids' cells in words, e.g. `10, 20 and 40`; `upto` drops finer ones (3D).
    pub fn named(&self, upto: f64) -> String {
        let c: Vec<String> = self
            .cells
            .iter()
            .filter(|&&k| k <= upto)
            .map(|k| format!("{k:.0}"))
            .collect();
        match c.len() {
            0 => "no".to_string(),
            1 => c[0].clone(),
            n => format!("{} and {}", c[..n - 1].join(", "), c[n - 1]),
        }
    }
    /// The report's line saying which stress order the sand takes.
    pub fn order(&self) -> &'static str {
        if self.stress_last {
            "the stress updated last"
        } else {
            "the stress updated first"
        }
    }
}

/// The validation claim's resolution sweep: every sand case at 10, 20 and 40 cells per its
/// characteristic length (plane collapses: the column's height H0; axisymmetric collapses: the
/// initial radius R0, at 10 and 20 cells only, the 40-cell 3D runs taking hours on one core;
/// heaps: the 0.2 m column between the lifted walls; slopes: the 0.1 m heap's height), the
/// default numerics, each measure against its published law and band at each grid, and the
/// change of every measure per halving of h. Returns the collapses whose H∞/H0 changes by more
/// than 2 points between their two finest grids (the bench fails on them once every case ran).
pub fn grids_study(md: &mut String, path: &std::path::Path, grids: &Grids) -> Vec<String> {
    let gimp = |h: f64| grids.numerics(h);
    let mut unconverged = Vec::new();
    let _ = writeln!(
        md,
        "Resolution sweep: `cargo xtask validate grids` (`cargo bench --bench validate -- grids`; `coarse`: 10 and 20 cells only, `fine`: 40 only, `stress-last`: the sand's stress updated last). Default numerics (GIMP, 2 particles per cell and direction, CFL 0.4, APIC base with α = 0.05, the start–stop cone), {}. Bands: the run-out read where the deposit is one grain ({} mm) thick within −20 % / +25 % of the law; the farthest particle (the last before a gap of two particle spacings) at most 2a; a collapse's flank (20–80 % least-squares slope) in [φ_ps − 6°, φ_ps + 1°]; the top kept within one cell of H0 where a < 1; failed slopes at rest in [φ_ps − 5°, φ_ps + 1°], heaps within 3° of φ_ps; plane H∞/H0 ±10 %, axisymmetric ±15 %.\n",
        grids.order(),
        1e3 * GRAIN
    );

    // plane collapses: (file, a, H0)
    let plane = [
        ("column_collapse_a0.5_2d.json", 0.5, 0.1),
        ("column_collapse_a1_2d.json", 1.0, 0.15),
        ("column_collapse_a2_2d.json", 2.0, 0.2),
        ("column_collapse_a3_2d.json", 3.0, 0.3),
    ];
    let cells = &grids.cells[..];
    let phi_ps = plane_strain_angle(32.0);
    let mut rows = Vec::new();
    let mut halving = Vec::new();
    for (file, a, h0) in plane {
        let [low, high] = mpm::laws::lube_runout_range(a);
        let mut runs: Vec<Collapse> = Vec::new();
        for &k in cells {
            let n = gimp(h0 / k);
            let c = column_collapse(file, &n, 4.0);
            println!("grids collapse a={a} {k} cells per H0 {}: {c:?}", n.label());
            let (et, eh) = (
                plane_runout_error(c.runout_thin, a),
                c.height / lube_height(a) - 1.0,
            );
            let top_kept = a >= 1.0 || c.height >= 1.0 - 1.0 / k;
            rows.push(vec![
                format!("{a}"),
                format!("{k:.0}"),
                format!("{}", h0 / k),
                format!("{:.2}", c.aspect_ratio),
                format!("{:.3} / {:.3}", c.runout_thin, c.runout),
                if high > low {
                    format!("{low:.2}–{high:.2}")
                } else {
                    format!("{low:.2}")
                },
                pct(et),
                format!(
                    "{} / {}",
                    holds(within(et, RUNOUT_BAND)),
                    holds(farthest_is_sane(c.runout, a))
                ),
                format!("{:.1} ({:+.1}°)", c.flank, c.flank - phi_ps),
                if flank_band_applies(a) {
                    holds(within(c.flank - phi_ps, FLANK_BAND))
                } else {
                    "—".to_string()
                },
                format!("{:.3}", c.height),
                format!("{} ({})", pct(eh), holds(eh.abs() <= 0.1)),
                if a < 1.0 {
                    holds(top_kept)
                } else {
                    "—".to_string()
                },
                at_rest(&c.failure, c.settled_at, None),
                format!("{:.1}", c.cost.wall_seconds),
            ]);
            runs.push(c);
            std::fs::write(path, &*md).unwrap();
        }
        halving.extend(collapse_halving(
            &format!("plane a = {a}"),
            a,
            cells,
            &runs,
            true,
            &mut unconverged,
        ));
    }
    let _ = writeln!(
        md,
        "## Plane column collapses at {} cells per H0 (φ = 32°, φ_ps = {phi_ps:.1}°, floor μ = 0.625; Lube et al. 2005)\n\nLube et al. (2005): (L∞ − L0)/L0 = 1.2 a for a < 1.8 and 1.9 a^(2/3) for a > 2.8; a = 2 lies between the two and is checked against the range 2.40–3.02 (error 0 inside it); H∞/H0 = 1 for a ≲ 1.15, a^(−3/5) above. *a measured*: H0/L0 of the particles as seeded. *Top*: H∞ within one cell of H0 (a < 1). The flank band holds the low columns (a < 1.15, whose top the failure does not reach).\n\n{}\n{}",
        grids.named(40.0),
        table(
            &[
                "a",
                "cells per H0",
                "h (m)",
                "a measured",
                "(L∞−L0)/L0 one grain / farthest",
                "Lube 2005",
                "error (one grain)",
                "−20/+25 % / ≤ 2a",
                "flank (°) (vs φ_ps)",
                "−6°/+1°",
                "H∞/H0",
                "error (±10 %)",
                "top",
                "at rest (s)",
                "s",
            ],
            &rows
        ),
        halving_table(
            &[
                "a",
                "cells per H0",
                "run-out one grain / farthest",
                "flank",
                "H∞/H0"
            ],
            &halving
        )
    );
    std::fs::write(path, &*md).unwrap();

    // the low columns on a rough floor (φ = 20°, 30°, 40°)
    crate::lowcolumn::lowcolumn_study(md, path, grids);

    // slopes: the 0.1 m trapezoidal heap, one gentler and one steeper than φ_ps per φ
    let mut rows = Vec::new();
    let mut halving = Vec::new();
    for (phi, gentle, steep) in [(20.0, 15.0, 30.0), (32.0, 25.0, 40.0), (45.0, 35.0, 50.0)] {
        for slope in [gentle, steep] {
            let mut runs: Vec<HeapSlope> = Vec::new();
            for &k in cells {
                let n = gimp(0.1 / k);
                let r = heap_slope(phi, slope, 3.5e5, &n, 2.0);
                println!(
                    "grids slope φ={phi} θ={slope} {k} cells {}: {r:?}",
                    n.label()
                );
                let ok = if slope < r.plane_strain_angle {
                    r.failed_at.is_none() && r.creep < 1e-3
                } else {
                    r.failed_at.is_some_and(|t| t < 0.5)
                        && within(r.angle - r.plane_strain_angle, REST_BAND)
                };
                rows.push(vec![
                    format!("{phi}"),
                    format!("{slope} ({:.1})", r.initial_angle),
                    format!("{k:.0}"),
                    format!("{:.1}", r.plane_strain_angle),
                    r.failed_at.map_or("—".to_string(), |t| format!("{t:.2}")),
                    format!("{:.1}", r.angle),
                    format!("{:+.1}°", r.angle - r.plane_strain_angle),
                    format!("{:.2}", 1e3 * r.creep),
                    format!("{:.1e}", r.final_speed),
                    holds(ok),
                    format!("{:.1}", r.cost.wall_seconds),
                ]);
                runs.push(r);
                std::fs::write(path, &*md).unwrap();
            }
            for (i, w) in runs.windows(2).enumerate() {
                halving.push(vec![
                    format!("{phi}"),
                    format!("{slope}"),
                    format!("{:.0} → {:.0}", cells[i], cells[i + 1]),
                    format!("{:+.1}°", w[1].angle - w[0].angle),
                    format!("{:+.2}", 1e3 * (w[1].creep - w[0].creep)),
                ]);
            }
        }
    }
    let _ = writeln!(
        md,
        "## Slopes at {} cells per heap height (2 s, E = 350 kPa)\n\nA trapezoidal heap 0.1 m high released on a floor with μ = tan φ. *Failed at*: when the flanks had come halfway down from their initial angle to φ_ps. *Creep*: the largest particle displacement from {CREEP_FROM} s to the end. Bound: a slope gentler than φ_ps stands (it does not fail, creep under 1 mm); a steeper one fails within 0.5 s and its flanks come to rest in [φ_ps − 5°, φ_ps + 1°].\n\n{}\n{}",
        grids.named(40.0),
        table(
            &[
                "φ (°)",
                "θ (°) (fitted)",
                "cells per height",
                "φ_ps (°)",
                "failed at (s)",
                "flanks after 2 s (°)",
                "vs φ_ps",
                "creep (mm)",
                "final speed (m/s)",
                "bound",
                "s"
            ],
            &rows
        ),
        halving_table(
            &["φ (°)", "θ (°)", "cells per height", "flanks", "creep (mm)"],
            &halving
        )
    );
    std::fs::write(path, &*md).unwrap();

    // heaps: the 0.2 m column between walls lifted at LIFT_SPEED
    let mut rows = Vec::new();
    let mut halving = Vec::new();
    for phi in [20.0, 32.0, 45.0] {
        let mut piles: Vec<Pile> = Vec::new();
        for &k in cells {
            let n = gimp(0.2 / k);
            let p = repose_pile(&n, repose_duration(LIFT_SPEED), Some(phi), LIFT_SPEED);
            println!("grids repose φ={phi} {k} cells {}: {p:?}", n.label());
            rows.push(vec![
                format!("{phi}"),
                format!("{k:.0}"),
                format!("{:.1}", p.plane_strain_angle),
                format!("{:.1} ({:.1}, {:.1})", p.angle, p.flanks[0], p.flanks[1]),
                format!("{:+.1}°", p.angle - p.plane_strain_angle),
                holds((p.angle - p.plane_strain_angle).abs() <= 3.0),
                format!("{:.1}", p.cost.wall_seconds),
            ]);
            piles.push(p);
            std::fs::write(path, &*md).unwrap();
        }
        for (i, w) in piles.windows(2).enumerate() {
            halving.push(vec![
                format!("{phi}"),
                format!("{:.0} → {:.0}", cells[i], cells[i + 1]),
                format!("{:+.1}°", w[1].angle - w[0].angle),
            ]);
        }
    }
    let _ = writeln!(
        md,
        "## Heaps at {} cells per column height (walls lifted at {LIFT_SPEED} m/s, floor μ = tan φ)\n\nThe sand column 0.2 m high between two walls lifted until they clear it. Bound: within 3° of φ_ps, the plane-strain angle of the cone at rest.\n\n{}\n{}",
        grids.named(40.0),
        table(
            &[
                "φ (°)",
                "cells per H0",
                "φ_ps (°)",
                "heap angle (°) (left, right)",
                "vs φ_ps",
                "±3°",
                "s"
            ],
            &rows
        ),
        halving_table(&["φ (°)", "cells per H0", "heap angle"], &halving)
    );
    std::fs::write(path, &*md).unwrap();

    // axisymmetric collapses, R0 = 0.1 m, at 10 and 20 cells per R0
    let mut rows = Vec::new();
    let mut halving = Vec::new();
    let cells: Vec<f64> = grids.cells.iter().copied().filter(|&k| k <= 20.0).collect();
    for (file, a) in AXI_COLLAPSES {
        let mut runs: Vec<Collapse> = Vec::new();
        for &k in &cells {
            let n = gimp(0.1 / k);
            let c = axisymmetric_collapse(file, &n, 4.0);
            println!(
                "grids axisymmetric a={a} {k} cells per R0 {}: {c:?}",
                n.label()
            );
            let law = lube_axisymmetric_runout(a);
            let et = c.runout_thin / law - 1.0;
            let top_kept = a >= 1.0 || c.height >= 1.0 - 1.0 / (k * a);
            let (hl, hj) = (
                c.height / lube_axisymmetric_height(a) - 1.0,
                c.height / lajeunesse_axisymmetric_height(a) - 1.0,
            );
            rows.push(vec![
                format!("{a}"),
                format!("{k:.0}"),
                format!("{:.2}", c.aspect_ratio),
                format!("{:.3} / {:.3}", c.runout_thin, c.runout),
                format!("{law:.2}"),
                pct(et),
                format!(
                    "{} / {}",
                    holds(within(et, RUNOUT_BAND)),
                    holds(farthest_is_sane(c.runout, a))
                ),
                format!("{:.1}", c.flank),
                format!("{:.3}", c.height),
                format!(
                    "{:.3} / {:.3}",
                    lube_axisymmetric_height(a),
                    lajeunesse_axisymmetric_height(a)
                ),
                format!("{} / {}", pct(hl), pct(hj)),
                format!("{} / {}", holds(hl.abs() <= 0.15), holds(hj.abs() <= 0.15)),
                if a < 1.0 {
                    holds(top_kept)
                } else {
                    "—".to_string()
                },
                format!("{:.2}", c.spread),
                at_rest(&c.failure, c.settled_at, None),
                format!("{:.1}", c.cost.wall_seconds),
            ]);
            runs.push(c);
            std::fs::write(path, &*md).unwrap();
        }
        halving.extend(collapse_halving(
            &format!("axisymmetric a = {a}"),
            a,
            &cells,
            &runs,
            false,
            &mut unconverged,
        ));
    }
    if rows.is_empty() {
        // a `fine` run: the 3D collapses run at 10 and 20 cells only
        return unconverged;
    }
    let _ = writeln!(
        md,
        "## Axisymmetric column collapses at {} cells per R0 (3D, φ = 32°, floor μ = 0.625; Lube et al. 2004, Lajeunesse et al. 2004)\n\nR0 = 0.1 m. (R∞ − R0)/R0 = 1.24 a for a ≲ 1.7, 1.6 a^(1/2) above (Lube et al. 2004); H∞/H0: Lube et al. (2004) 0.88 a^(1/6)/a above a ≈ 0.74, Lajeunesse et al. (2004) 0.74/a. Run-out at one grain's thickness on the radial profile (rings one cell wide); farthest: the mean over 16 azimuthal sectors of each sector's farthest particle. Flank: the radial profile's 20–80 % slope (no band: φ_ps is a plane-strain angle). *Top*: H∞ within one cell of H0 (a < 1). Spread: the largest minus the smallest sector front, over R0.\n\n{}\n{}",
        grids.named(20.0),
        table(
            &[
                "a",
                "cells per R0",
                "a measured",
                "(R∞−R0)/R0 one grain / farthest",
                "Lube 2004",
                "error (one grain)",
                "−20/+25 % / ≤ 2a",
                "flank (°)",
                "H∞/H0",
                "Lube 2004 / Lajeunesse 2004",
                "error",
                "±15 %",
                "top",
                "spread",
                "at rest (s)",
                "s"
            ],
            &rows
        ),
        halving_table(
            &["a", "cells per R0", "run-out one grain / farthest", "H∞/H0"],
            &halving
        )
    );
    std::fs::write(path, &*md).unwrap();
    unconverged
}

/// The change of a collapse's measures per halving of h (`cells`: the grids of `runs`), as
/// rows (a, grids, run-out one grain / farthest, the flank where `flank`, H∞/H0); `name` goes
/// to `unconverged` when H∞/H0 moves more than 2 points between the two finest grids.
fn collapse_halving(
    name: &str,
    a: f64,
    cells: &[f64],
    runs: &[Collapse],
    flank: bool,
    unconverged: &mut Vec<String>,
) -> Vec<Vec<String>> {
    let mut rows = Vec::new();
    for (i, w) in runs.windows(2).enumerate() {
        let dh = 100.0 * (w[1].height - w[0].height);
        let mut row = vec![
            format!("{a}"),
            format!("{:.0} → {:.0}", cells[i], cells[i + 1]),
            format!(
                "{:+.3} / {:+.3}",
                w[1].runout_thin - w[0].runout_thin,
                w[1].runout - w[0].runout
            ),
        ];
        if flank {
            row.push(format!("{:+.1}°", w[1].flank - w[0].flank));
        }
        row.push(format!("{dh:+.1} points"));
        rows.push(row);
        if i + 2 == runs.len() && dh.abs() > 2.0 {
            unconverged.push(format!("{name}: H∞/H0 {dh:+.1} points"));
        }
    }
    rows
}
