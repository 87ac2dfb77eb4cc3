//! The long validation runs: every case of `scenes/validation/` at finer resolutions than the
//! test suite affords, compared with its closed form or published measurement. Writes
//! `docs/validation-report.md`.
//!
//! `taskset -c 0 cargo bench --bench validate` (or `cargo xtask validate`; about 10 minutes
//! on one core). Arguments filter the cases: `bar`, `wave`, `squeeze`, `collapse`, `repose`,
//! `steep`, `resting`.

#[path = "support/report.rs"]
mod report;
#[path = "../tests/support/validation.rs"]
mod validation;

use mpm::{D2, D3, KernelKind};
use report::*;
use std::fmt::Write;
use validation::*;

fn pct(x: f64) -> String {
    format!("{:+.2} %", 100.0 * x)
}

fn main() {
    let filters = Filters::from_args();
    let want = |s: &str| filters.want(s);
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# Validation report (generated)\n\nRegenerate with `taskset -c 0 cargo bench --bench validate` (or `cargo xtask validate`). Written by `benches/validate.rs`; the cases, references and discussion are in [validation.md](validation.md). Run times are wall-clock seconds on one core.\n"
    );
    let gimp = |h: f64| Numerics::new(h, KernelKind::Gimp);
    if want("bar") {
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
    if want("wave") {
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
    if want("squeeze") {
        let mut rows = Vec::new();
        let mut curves = String::new();
        for (dim, h) in [(2, 0.01), (2, 0.005), (3, 0.02)] {
            let n = gimp(h);
            let s = if dim == 2 {
                squeeze::<D2>("von_mises_compression_2d.json", &n, 0.04)
            } else {
                squeeze::<D3>("von_mises_compression_3d.json", &n, 0.04)
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
    if want("collapse") {
        let mut rows = Vec::new();
        for h in [0.01, 0.005] {
            for (file, a) in [
                ("column_collapse_a0.5_2d.json", 0.5),
                ("column_collapse_a1_2d.json", 1.0),
                ("column_collapse_a2_2d.json", 2.0),
                ("column_collapse_a3_2d.json", 3.0),
            ] {
                let n = gimp(h);
                let c = column_collapse(file, &n, 4.0);
                println!("collapse a={a} {}: {c:?}", n.label());
                rows.push(vec![
                    format!("{a}"),
                    n.label(),
                    format!("{:.3}", c.runout),
                    format!("{:.2}", lube_runout(a)),
                    pct(c.runout / lube_runout(a) - 1.0),
                    format!("{:.3}", c.height),
                    format!("{:.3}", lube_height(a)),
                    pct(c.height / lube_height(a) - 1.0),
                    format!("{:.2}", c.settled_at),
                    format!("{:.1}", c.cost.wall_seconds),
                ]);
            }
        }
        let _ = writeln!(
            md,
            "## Granular column collapse (plane), φ = 32°, floor μ = 0.625\n\n{}",
            table(
                &[
                    "a",
                    "numerics",
                    "(L∞−L0)/L0",
                    "Lube 2005",
                    "error",
                    "H∞/H0",
                    "Lube 2005",
                    "error",
                    "at rest (s)",
                    "s"
                ],
                &rows
            )
        );
    }
    if want("repose") {
        let mut rows = Vec::new();
        for (h, phi) in [(0.01, 20.0), (0.01, 32.0), (0.01, 45.0), (0.005, 32.0)] {
            let n = gimp(h);
            let p = repose_pile(&n, 10.0, Some(phi));
            println!("repose φ={phi} {}: {p:?}", n.label());
            rows.push(vec![
                n.label(),
                format!("{phi}"),
                format!("{:.1}", p.plane_strain_angle),
                format!("{:.1} ({:.1}, {:.1})", p.angle, p.flanks[0], p.flanks[1]),
                format!("{:+.1}°", p.angle - p.plane_strain_angle),
                format!("{:.2}", p.settled_at),
                format!("{:.1}", p.cost.wall_seconds),
            ]);
        }
        let _ = writeln!(
            md,
            "## Angle of repose (lifted walls, floor μ = tan φ)\n\n{}",
            table(
                &[
                    "numerics",
                    "φ (°)",
                    "φ_ps (°)",
                    "heap angle (°) (left, right)",
                    "vs φ_ps",
                    "at rest (s)",
                    "s"
                ],
                &rows
            )
        );
    }
    if want("steep") {
        let mut rows = Vec::new();
        let cases: [(f64, f64, f64, f64, KernelKind); 7] = [
            (32.0, 40.0, 3.5e5, 0.05, KernelKind::Gimp),
            (32.0, 40.0, 3.5e5, 0.0, KernelKind::Gimp),
            (32.0, 40.0, 3.5e5, 0.5, KernelKind::Gimp),
            (32.0, 40.0, 3.5e5, 1.0, KernelKind::Gimp),
            (32.0, 40.0, 3.5e7, 0.05, KernelKind::Gimp),
            (32.0, 40.0, 3.5e5, 0.05, KernelKind::QuadraticBspline),
            (20.0, 30.0, 3.5e5, 0.05, KernelKind::Gimp),
        ];
        for (phi, slope, e, alpha, kernel) in cases {
            let n = Numerics::new(0.01, kernel).flip(alpha);
            let r = steep_heap(phi, slope, e, &n, 2.0);
            println!("steep φ={phi} θ={slope} E={e} {}: {r:?}", n.label());
            rows.push(vec![
                format!("{phi}"),
                format!("{:.1}", r.plane_strain_angle),
                format!("{slope}"),
                format!("{e:.1e}"),
                n.label(),
                format!("{:.1}", r.angle),
                format!("{:.1}", 1e3 * r.widening),
                format!("{:.2e}", r.peak_speed),
                format!("{:.2e}", r.final_speed),
                format!("{:.1}", r.cost.wall_seconds),
            ]);
        }
        let _ = writeln!(
            md,
            "## A heap steeper than its friction angle, after 2 s\n\n{}",
            table(
                &[
                    "φ (°)",
                    "φ_ps (°)",
                    "initial flanks (°)",
                    "E (Pa)",
                    "numerics",
                    "flanks after 2 s (°)",
                    "widening (mm)",
                    "peak speed (m/s)",
                    "final speed (m/s)",
                    "s"
                ],
                &rows
            )
        );
    }
    if want("resting") {
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
    let path = filters.report_path("validation-report");
    std::fs::write(&path, md).unwrap();
    println!("wrote {}", path.display());
}
