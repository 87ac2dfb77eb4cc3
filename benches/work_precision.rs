//! Run time against error (the work–precision study): sweeps the cell size, particles per
//! cell, PIC/FLIP α, CFL number and kernel on three cases and writes
//! `docs/reports/work-precision-report.md` with the tables and convergence orders, and one log–log
//! SVG of error against run time per case.
//!
//! A fourth study, `quality`, runs the three cases at the page's quality levels
//! (`src/playground/quality.rs`): each level's largest cell factor and the particles per cell
//! the page gives the shipped scenes at that level, with each kernel.
//!
//! `taskset -c 0 cargo bench --bench work_precision` (about 5 minutes of one core's time;
//! the run times are the seconds each run spent on a core, `report::on_core`). Arguments
//! filter the studies:
//! `bar`, `column`, `resting`, `quality`.

#[path = "support/report.rs"]
mod report;
#[path = "../tests/support/validation.rs"]
mod validation;

use mpm::playground::{QUALITIES, Quality, resample};
use mpm::{D2, KernelKind, SceneConfig};
use report::*;
use std::fmt::Write;
use validation::*;

/// A study: its name (the filter) and the function that appends its section to the report.
type Study = (&'static str, fn(&mut String));

const KERNELS: [KernelKind; 3] = [
    KernelKind::Linear,
    KernelKind::Gimp,
    KernelKind::QuadraticBspline,
];

struct Row {
    n: Numerics,
    seconds: f64,
    particles: usize,
    steps: u64,
    error: f64,
    extra: String,
}

fn row_cells(r: &Row) -> Vec<String> {
    vec![
        kernel_name(r.n.kernel).to_string(),
        format!("{}", r.n.cell_size),
        format!("{}", r.n.ppc),
        r.n.flip.map_or("scene".into(), |a| format!("{a}")),
        format!("{}", r.n.cfl),
        format!("{}", r.particles),
        format!("{}", r.steps),
        format!("{:.3}", r.seconds),
        format!("{:.3e}", r.error),
        r.extra.clone(),
    ]
}

const HEADER: [&str; 10] = [
    "kernel",
    "h (m)",
    "ppc",
    "α",
    "CFL",
    "particles",
    "steps",
    "run time (s on core)",
    "error",
    "details",
];

fn main() {
    let filters = Filters::from_args();
    let want = |s: &str| filters.want(s);
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# Work–precision report (generated)\n\nRegenerate with `taskset -c 0 cargo bench --bench work_precision` (or `cargo xtask work-precision`). Run times are the seconds each run's thread spent on a core of the shared two-core development machine (Linux's schedstat; wall-clock seconds where it is missing), not the time it waited for one: other work loaded the machine, and its clock speed drifts by up to 30 % between processes, so compare ratios within this report. Errors are defined per case below. Written by `benches/work_precision.rs`; the discussion is in [work-precision.md](../work-precision.md). Measured at {}.\n\n{}\n",
        measured_at(),
        solver_line(
            &families_of(&filters, &["bar", "resting"]),
            &rerun_command("work-precision", &filters)
        )
    );
    let path = filters.report_path("work-precision-report");
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    // the report is rewritten after each study, so that an interrupted run keeps its results
    let studies: [Study; 4] = [
        ("bar", bar_study),
        ("column", column_study),
        ("resting", resting_study),
        ("quality", quality_study),
    ];
    for (name, study) in studies {
        if want(name) {
            study(&mut md);
            std::fs::write(&path, &md).unwrap();
            println!("wrote {}", path.display());
        }
    }
}

fn save_svg(name: &str, svg: String) {
    let path = root().join("docs").join("reports").join(name);
    std::fs::write(&path, svg).unwrap();
    println!("wrote {}", path.display());
}

// ---------------------------------------------------------------------------------------------

fn bar_run(n: Numerics) -> Row {
    bar_run_file("vibrating_bar_2d.json", n)
}

fn bar_run_file(file: &str, n: Numerics) -> Row {
    let (mut b, secs) = on_core(|| vibrating_bar::<D2>(file, &n, 3.0));
    b.cost.wall_seconds = secs;
    let row = Row {
        n,
        seconds: b.cost.wall_seconds,
        particles: b.cost.particles,
        steps: b.cost.steps,
        error: b.l2_error,
        extra: match &b.failure {
            Some(f) => format!("FAILED {f}"),
            None => format!(
                "period {:+.3}%, amplitude {:+.2}%, kept {:.3}",
                100.0 * b.period_error(),
                100.0 * b.amplitude_error(),
                b.amplitude_kept
            ),
        },
    };
    println!(
        "bar {}: {:.3e} in {:.2} s",
        n.label(),
        row.error,
        row.seconds
    );
    row
}

/// One run per cell size in `hs` (rows appended to `rows`): the cell sizes, the errors and the
/// (run time, error) points of the work–precision diagram.
struct Sweep {
    hs: Vec<f64>,
    errors: Vec<f64>,
    points: Vec<(f64, f64)>,
}

fn sweep(hs: &[f64], mut run: impl FnMut(f64) -> Row, rows: &mut Vec<Row>) -> Sweep {
    let mut s = Sweep {
        hs: hs.to_vec(),
        errors: Vec::new(),
        points: Vec::new(),
    };
    for &h in hs {
        let r = run(h);
        s.errors.push(r.error);
        s.points.push((r.seconds, r.error));
        rows.push(r);
    }
    s
}

fn bar_study(md: &mut String) {
    let _ = writeln!(
        md,
        "## Vibrating bar (2D, `scenes/validation/vibrating_bar_2d.json`)\n\nError: ‖q − q_exact‖₂/‖q_exact‖₂ of the first-mode modal displacement over three periods (phase, period and amplitude errors together), against u = (v0/ω) sin ωt cos(πx/L). A run the solver stopped (non-finite state) is marked FAILED.\n"
    );
    let hs = [0.05, 0.025, 0.0125, 0.00625];
    let mut rows = Vec::new();
    let mut series = Vec::new();
    let mut orders = Vec::new();
    for (ka, &alpha) in [1.0, 0.0].iter().enumerate() {
        for (kk, &k) in KERNELS.iter().enumerate() {
            let s = sweep(&hs, |h| bar_run(Numerics::new(h, k).flip(alpha)), &mut rows);
            orders.push(vec![
                kernel_name(k).to_string(),
                format!("{alpha}"),
                format!("{:.2}", log_slope(&s.hs, &s.errors)),
                format!("{:.2}", log_slope(&s.hs[1..], &s.errors[1..])),
            ]);
            series.push(Series::sweep(
                format!("{} α={alpha}", kernel_name(k)),
                COLOURS[kk],
                s.points,
                ka == 1,
            ));
        }
    }
    // particles per cell and CFL at a middle resolution
    for &k in &KERNELS {
        for ppc in [1, 3, 4] {
            rows.push(bar_run(Numerics::new(0.0125, k).flip(1.0).ppc(ppc)));
        }
    }
    for cfl in [0.1, 0.2, 0.6, 0.7, 0.8, 1.0] {
        rows.push(bar_run(
            Numerics::new(0.0125, KernelKind::Gimp).flip(1.0).cfl(cfl),
        ));
    }
    for alpha in [0.05, 0.5, 0.95] {
        rows.push(bar_run(Numerics::new(0.0125, KernelKind::Gimp).flip(alpha)));
    }
    let _ = writeln!(
        md,
        "Convergence order (slope of log error against log h; all four cell sizes, and the three finest):\n\n{}",
        table(&["kernel", "α", "order (4 h)", "order (3 finest)"], &orders)
    );
    let _ = writeln!(
        md,
        "All runs:\n\n{}\n![bar](work-precision-bar.svg)\n",
        table(&HEADER, &rows.iter().map(row_cells).collect::<Vec<_>>())
    );
    save_svg(
        "work-precision-bar.svg",
        loglog_svg(
            "Vibrating bar: error against run time (h = 0.05 … 0.00625 m)",
            "run time (s on core)",
            "relative L2 error of the modal displacement",
            &series,
        ),
    );
}

// ---------------------------------------------------------------------------------------------

fn column_study(md: &mut String) {
    let (file, a) = ("column_collapse_a2_2d.json", 2.0);
    let reference = column_reference(file);
    println!("column reference: {reference:?}");
    let (lube_r, lube_h) = (lube_runout(a), lube_height(a));
    let _ = writeln!(
        md,
        "## Column collapse (2D, a = 2, `scenes/validation/{file}`)\n\nThe sand's default transfer (APIC base, α = 0.05) unless a row says otherwise; the run-out is the farthest particle (the deposit's edge is in the details). Two errors, each the larger of the relative errors of the normalised run-out (L∞ − L0)/L0 and of the final height H∞/H0: **against experiment**, Lube et al. (2005): {lube_r:.2} and {lube_h:.3}; and **self-convergence**, against the finest run (GIMP, h = 0.0025 m, ppc 2, the scene's α, CFL 0.4, {} particles, {:.0} s): {:.3} and {:.3}. A method can converge to the wrong answer: the second error hides what the first shows.\n",
        reference.cost.particles, reference.cost.wall_seconds, reference.runout, reference.height,
    );
    let errors = |c: &Collapse| -> (f64, f64) {
        if c.failure.is_some() {
            return (f64::INFINITY, f64::INFINITY);
        }
        let e = |r: f64, h: f64| (c.runout / r - 1.0).abs().max((c.height / h - 1.0).abs());
        (e(lube_r, lube_h), e(reference.runout, reference.height))
    };
    // (row with the error against experiment, the error against the reference)
    let run = |n: Numerics| -> (Row, f64) {
        let (mut c, secs) = on_core(|| column_collapse(file, &n, 4.0));
        c.cost.wall_seconds = secs;
        let (e_lube, e_ref) = errors(&c);
        println!(
            "column {}: {e_lube:.3e} (Lube), {e_ref:.3e} (reference) in {:.2} s",
            n.label(),
            c.cost.wall_seconds
        );
        let row = Row {
            n,
            seconds: c.cost.wall_seconds,
            particles: c.cost.particles,
            steps: c.cost.steps,
            error: e_lube,
            extra: match &c.failure {
                Some(f) => format!("FAILED: {f}"),
                None => format!(
                    "{}run-out {:.3} ({:+.0} % vs Lube; deposit edge {:.3}, {:+.0} %), height {:.3} ({:+.0} %); vs reference {:.3e}; at rest at {:.2} s",
                    if n.apic == Some(false) {
                        "paper's PIC/FLIP blend (no APIC): "
                    } else {
                        ""
                    },
                    c.runout,
                    100.0 * (c.runout / lube_r - 1.0),
                    c.runout_edge,
                    100.0 * (c.runout_edge / lube_r - 1.0),
                    c.height,
                    100.0 * (c.height / lube_h - 1.0),
                    e_ref,
                    c.settled_at
                ),
            },
        };
        (row, e_ref)
    };
    let mut rows = Vec::new();
    let (mut vs_lube, mut vs_ref) = (Vec::new(), Vec::new());
    let mut orders = Vec::new();
    for (kk, &k) in KERNELS.iter().enumerate() {
        let hs = [0.02, 0.01, 0.005];
        let (mut el, mut er, mut pl, mut pr) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for &h in &hs {
            let (row, e_ref) = run(Numerics::new(h, k));
            el.push(row.error);
            er.push(e_ref);
            pl.push((row.seconds, row.error));
            pr.push((row.seconds, e_ref));
            rows.push(row);
        }
        orders.push(vec![
            kernel_name(k).to_string(),
            el.iter()
                .map(|e| format!("{:.1} %", 100.0 * e))
                .collect::<Vec<_>>()
                .join(", "),
            format!("{:.2}", log_slope(&hs, &er)),
        ]);
        vs_lube.push(Series::sweep(
            kernel_name(k).to_string(),
            COLOURS[kk],
            pl,
            false,
        ));
        vs_ref.push(Series::sweep(
            kernel_name(k).to_string(),
            COLOURS[kk],
            pr,
            false,
        ));
    }
    // configurations that are not a sweep: labelled points at h = 0.01
    let mut variants: Vec<(String, Numerics)> = Vec::new();
    for alpha in [0.0, 0.5, 0.8, 0.9, 0.95, 0.99, 1.0] {
        variants.push((
            format!("α {alpha}"),
            Numerics::new(0.01, KernelKind::Gimp).flip(alpha),
        ));
    }
    for ppc in [1, 3] {
        variants.push((
            format!("ppc {ppc}"),
            Numerics::new(0.01, KernelKind::Gimp).ppc(ppc),
        ));
    }
    for cfl in [0.2, 0.8] {
        variants.push((
            format!("CFL {cfl}"),
            Numerics::new(0.01, KernelKind::Gimp).cfl(cfl),
        ));
    }
    // the sand's transfer before APIC became its default
    for alpha in [0.05, 1.0] {
        variants.push((
            format!("PIC/FLIP α {alpha}"),
            Numerics::new(0.01, KernelKind::Gimp).flip(alpha).pic(),
        ));
    }
    let (mut pl, mut pr, mut labels) = (Vec::new(), Vec::new(), Vec::new());
    for (label, n) in variants {
        let (row, e_ref) = run(n);
        pl.push((row.seconds, row.error));
        pr.push((row.seconds, e_ref));
        labels.push(label);
        rows.push(row);
    }
    let other = "gimp h=0.01, other α / ppc / CFL / transfer".to_string();
    vs_lube.push(Series::labelled(
        other.clone(),
        COLOURS[4],
        pl,
        labels.clone(),
    ));
    vs_ref.push(Series::labelled(other, COLOURS[4], pr, labels));
    let _ = writeln!(
        md,
        "Errors against experiment over h = 0.02, 0.01, 0.005 m, and the order of convergence against the reference:\n\n{}",
        table(
            &[
                "kernel",
                "error vs Lube et al. (h = 0.02, 0.01, 0.005)",
                "self-convergence order"
            ],
            &orders
        )
    );
    let _ = writeln!(
        md,
        "All runs (error: against Lube et al.; the error against the reference is in the details):\n\n{}\n![column, against experiment](work-precision-column.svg)\n\n![column, self-convergence](work-precision-column-self.svg)\n",
        table(&HEADER, &rows.iter().map(row_cells).collect::<Vec<_>>())
    );
    save_svg(
        "work-precision-column.svg",
        loglog_svg(
            "Column collapse a = 2: error against Lube et al. (2005) vs run time",
            "run time (s on core)",
            "relative error of run-out / height vs experiment",
            &vs_lube,
        ),
    );
    save_svg(
        "work-precision-column-self.svg",
        loglog_svg(
            "Column collapse a = 2: self-convergence (vs the h = 0.0025 m run)",
            "run time (s on core)",
            "relative error of run-out / height vs reference",
            &vs_ref,
        ),
    );
}

/// The reference run of the column study (about ten minutes on one core), kept in
/// `target/work-precision-column-reference.txt` for later runs of the bench (delete the file
/// to recompute it).
fn column_reference(file: &str) -> Collapse {
    let cache = root()
        .join("target")
        .join("work-precision-column-reference.txt");
    if let Ok(text) = std::fs::read_to_string(&cache) {
        let v: Vec<f64> = text
            .split_whitespace()
            .filter_map(|w| w.parse().ok())
            .collect();
        if v.len() == 8 {
            println!("column reference from {}", cache.display());
            return Collapse {
                aspect_ratio: v[0],
                runout: v[1],
                runout_edge: v[7],
                runout_thin: f64::NAN,
                flank: f64::NAN,
                height: v[2],
                spread: 0.0,
                settled_at: v[3],
                failure: None,
                cost: Cost {
                    wall_seconds: v[4],
                    steps: v[5] as u64,
                    particles: v[6] as usize,
                },
            };
        }
    }
    let (mut c, secs) =
        on_core(|| column_collapse(file, &Numerics::new(0.0025, KernelKind::Gimp), 4.0));
    c.cost.wall_seconds = secs;
    assert!(c.failure.is_none(), "the reference run failed: {c:?}");
    let _ = std::fs::write(
        &cache,
        format!(
            "{} {} {} {} {} {} {} {}\n",
            c.aspect_ratio,
            c.runout,
            c.height,
            c.settled_at,
            c.cost.wall_seconds,
            c.cost.steps,
            c.cost.particles,
            c.runout_edge
        ),
    );
    c
}

// ---------------------------------------------------------------------------------------------

fn resting_study(md: &mut String) {
    let duration = 10.0;
    let _ = writeln!(
        md,
        "## Resting soft column (2D, `scenes/validation/resting_column_2d.json`): the cell-crossing study\n\nA soft elastic column (E = 100 kPa, ν = 0, 0.2 × 0.4 m) released stress-free on a frictionless floor, PIC (α = 0), run for {duration} s (about 60 oscillation periods). Error: |δ/δ_exact − 1| of the top settlement δ (mean over the last tenth of the run), δ_exact = ρ g (H Y − Y²/2)/E at the top row. The drift is the sinking rate of the top over the second half of the run (a resting column should not sink). A run that failed is marked.\n"
    );
    let mut rows = Vec::new();
    let mut series = Vec::new();
    for (kk, &k) in KERNELS.iter().enumerate() {
        for (kc, &cfl) in [0.4, 0.8].iter().enumerate() {
            let mut pts = Vec::new();
            for h in [0.04, 0.02, 0.01] {
                let n = Numerics::new(h, k).flip(0.0).cfl(cfl);
                let (mut r, secs) = on_core(|| resting_column(&n, duration));
                r.cost.wall_seconds = secs;
                println!("resting {}: {r:?}", n.label());
                let row = Row {
                    n,
                    seconds: r.cost.wall_seconds,
                    particles: r.cost.particles,
                    steps: r.cost.steps,
                    error: r.error(),
                    extra: match &r.failure {
                        Some(f) => format!("FAILED after {} steps: {f}", r.cost.steps),
                        None => format!(
                            "δ = {:.3} mm (exact {:.3}), drift {:+.2e} m/s, final max speed {:.1e} m/s",
                            1e3 * r.settlement,
                            1e3 * r.settlement_exact,
                            r.drift_rate,
                            r.max_speed
                        ),
                    },
                };
                if r.failure.is_none() {
                    pts.push((row.seconds, row.error));
                }
                rows.push(row);
            }
            series.push(Series::sweep(
                format!("{} CFL {cfl}", kernel_name(k)),
                COLOURS[kk],
                pts,
                kc == 1,
            ));
        }
    }
    let _ = writeln!(
        md,
        "{}\n![resting](work-precision-resting.svg)\n",
        table(&HEADER, &rows.iter().map(row_cells).collect::<Vec<_>>())
    );
    save_svg(
        "work-precision-resting.svg",
        loglog_svg(
            "Resting soft column, 10 s: settlement error against run time",
            "run time (s on core)",
            "|settlement / exact − 1|",
            &series,
        ),
    );
}

// ---------------------------------------------------------------------------------------------

/// The particles per cell the page gives the shipped scenes (`scenes/*.json`) at level `q`,
/// with each scene's cell factor: (scene, cell factor, particles per cell, particles).
fn shipped_resolutions(q: &'static Quality) -> Vec<(String, f64, u32, usize)> {
    let mut files: Vec<_> = std::fs::read_dir(root().join("scenes"))
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    let mut out = Vec::new();
    for path in files {
        let scene = SceneConfig::load(&path).unwrap();
        let (sampled, res) = resample(&scene, q, |i, h, ppc| {
            let mut b = scene.bodies[i].clone();
            b.particles_per_cell = ppc;
            Ok(b.sample(&format!("bodies[{i}]"), scene.dim, h)?.0.len())
        })
        .unwrap();
        let particles: usize = sampled
            .bodies
            .iter()
            .map(|b| {
                b.sample("b", sampled.dim, sampled.cell_size)
                    .unwrap()
                    .0
                    .len()
            })
            .sum();
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        out.push((
            name,
            res.cell_size / res.scene_cell_size,
            res.particles_per_cell,
            particles,
        ));
    }
    out
}

fn quality_study(md: &mut String) {
    let _ = writeln!(
        md,
        "## The page's quality levels\n\nThe page samples a scene at its quality level (`src/playground/quality.rs`): cells up to the level's factor times the scene file's and more particles per cell where the bodies would keep too few. The particles per cell it gives the shipped scenes, and their cell factor:\n"
    );
    let mut levels = Vec::new();
    let mut rows = Vec::new();
    for q in QUALITIES.iter() {
        let shipped = shipped_resolutions(q);
        let mut ppcs: Vec<u32> = shipped.iter().map(|s| s.2).collect();
        ppcs.sort();
        // the particles per cell most shipped scenes get at this level
        let ppc = *ppcs
            .iter()
            .max_by_key(|p| {
                (
                    ppcs.iter().filter(|x| x == p).count(),
                    std::cmp::Reverse(**p),
                )
            })
            .unwrap();
        for (name, f, p, n) in &shipped {
            rows.push(vec![
                q.label.to_string(),
                name.clone(),
                format!("{f:.3}"),
                format!("{p}"),
                format!("{n}"),
            ]);
        }
        levels.push((q, q.cell_factor, ppc));
    }
    let _ = writeln!(
        md,
        "{}",
        table(
            &["level", "scene", "cell factor", "ppc", "particles"],
            &rows
        )
    );
    let _ = writeln!(
        md,
        "Each case of this report at each level's largest cell factor (the study's cell size times it: bar 0.025 m, column 0.01 m, resting column 0.02 m; `max_dt` scaled with it as the page does, except the resting column's, which keeps 1 ms) and the particles per cell most shipped scenes get at that level, with each kernel. The bar with FLIP (α = 1) and with PIC (α = 0), the column with the sand's default transfer (APIC base, α = 0.05; the paper's PIC/FLIP blend with the linear kernel), the resting column with PIC for 10 s. Errors as in the sections above (the column's against Lube et al.).\n"
    );
    let mut rows = Vec::new();
    let mut summary = Vec::new();
    for (q, f, ppc) in levels {
        for &k in &KERNELS {
            let mut errors = Vec::new();
            for alpha in [1.0, 0.0] {
                let r = bar_run_file(
                    &report::scaled("vibrating_bar_2d.json", f, "work-precision-scenes"),
                    Numerics::new(0.025 * f, k).flip(alpha).ppc(ppc),
                );
                errors.push(format!("{:.2} %", 100.0 * r.error));
                rows.push(quality_row(q, "bar", &r));
            }
            let (mut c, secs) = on_core(|| {
                column_collapse(
                    &report::scaled("column_collapse_a2_2d.json", f, "work-precision-scenes"),
                    &Numerics::new(0.01 * f, k).ppc(ppc),
                    4.0,
                )
            });
            c.cost.wall_seconds = secs;
            let (lr, lh) = (lube_runout(2.0), lube_height(2.0));
            let e = if c.failure.is_some() {
                f64::INFINITY
            } else {
                (c.runout / lr - 1.0).abs().max((c.height / lh - 1.0).abs())
            };
            println!(
                "quality {} column {}: {e:.3e} in {:.2} s",
                q.id,
                kernel_name(k),
                c.cost.wall_seconds
            );
            errors.push(format!("{:.1} %", 100.0 * e));
            let n = Numerics::new(0.01 * f, k).ppc(ppc);
            rows.push(quality_row(
                q,
                "column",
                &Row {
                    n,
                    seconds: c.cost.wall_seconds,
                    particles: c.cost.particles,
                    steps: c.cost.steps,
                    error: e,
                    extra: match &c.failure {
                        Some(fail) => format!("FAILED: {fail}"),
                        None => format!(
                            "run-out {:.3} ({:+.0} %), height {:.3} ({:+.0} %), at rest at {:.2} s",
                            c.runout,
                            100.0 * (c.runout / lr - 1.0),
                            c.height,
                            100.0 * (c.height / lh - 1.0),
                            c.settled_at
                        ),
                    },
                },
            ));
            let n = Numerics::new(0.02 * f, k).flip(0.0).ppc(ppc);
            let (mut r, secs) = on_core(|| resting_column(&n, 10.0));
            r.cost.wall_seconds = secs;
            println!("quality {} resting {}: {r:?}", q.id, n.label());
            errors.push(match &r.failure {
                Some(_) => "FAILED".to_string(),
                None => format!(
                    "{:+.1} %",
                    100.0 * (r.settlement / r.settlement_exact - 1.0)
                ),
            });
            rows.push(quality_row(
                q,
                "resting",
                &Row {
                    n,
                    seconds: r.cost.wall_seconds,
                    particles: r.cost.particles,
                    steps: r.cost.steps,
                    error: r.error(),
                    extra: match &r.failure {
                        Some(fail) => format!("FAILED after {} steps: {fail}", r.cost.steps),
                        None => format!(
                            "δ = {:.3} mm (exact {:.3}), drift {:+.2e} m/s",
                            1e3 * r.settlement,
                            1e3 * r.settlement_exact,
                            r.drift_rate
                        ),
                    },
                },
            ));
            summary.push(
                [
                    vec![
                        q.label.to_string(),
                        format!("{f} × h, ppc {ppc}"),
                        kernel_name(k).to_string(),
                    ],
                    errors,
                ]
                .concat(),
            );
        }
    }
    let _ = writeln!(
        md,
        "{}",
        table(
            &[
                "level",
                "cells, ppc",
                "kernel",
                "bar, FLIP",
                "bar, PIC",
                "column vs Lube",
                "resting settlement",
            ],
            &summary
        )
    );
    let mut header = vec!["level", "case"];
    header.extend(HEADER);
    let _ = writeln!(md, "All runs:\n\n{}", table(&header, &rows));
}

fn quality_row(q: &Quality, case: &str, r: &Row) -> Vec<String> {
    [vec![q.label.to_string(), case.to_string()], row_cells(r)].concat()
}
