//! The sand cases at the validation's own resolutions: plane and axisymmetric collapses, heaps
//! and slopes, each with the paper's plain blend beside the default.

use crate::report::*;
use crate::tables::*;
use crate::validation::*;
use mpm::KernelKind;
use std::fmt::Write;

/// The plane column collapses over three cell sizes, and with the plain PIC/FLIP blend.
pub fn collapse(md: &mut String) {
    let gimp = |h: f64| Numerics::new(h, KernelKind::Gimp);
    let mut rows = Vec::new();
    let files = PLANE_COLLAPSES;
    // the sand's default transfer over three cell sizes (and a = 2 at a fourth), then the
    // paper's plain PIC/FLIP blend at the validation resolution, the transfer before APIC
    let mut runs: Vec<(&str, f64, Numerics)> = Vec::new();
    for h in [0.02, 0.01, 0.005] {
        runs.extend(files.iter().map(|&(f, a)| (f, a, gimp(h))));
    }
    runs.push((files[2].0, 2.0, gimp(0.0025)));
    runs.extend(files.iter().map(|&(f, a)| (f, a, gimp(0.01).pic())));
    for (file, a, n) in runs {
        let c = column_collapse(file, &n, 4.0);
        println!("collapse a={a} {}: {c:?}", n.label());
        rows.push(vec![
            format!("{a}"),
            n.label(),
            format!("{:.3}", c.runout),
            format!("{:.3}", c.runout_edge),
            format!("{:.2}", lube_runout(a)),
            pct(c.runout / lube_runout(a) - 1.0),
            pct(c.runout_edge / lube_runout(a) - 1.0),
            format!("{:.3}", c.height),
            format!("{:.3}", lube_height(a)),
            pct(c.height / lube_height(a) - 1.0),
            format!("{:.2}", c.settled_at),
            format!("{:.1}", c.cost.wall_seconds),
        ]);
    }
    let _ = writeln!(
        md,
        "## Granular column collapse (plane), φ = 32°, floor μ = 0.625\n\nRun-out as the farthest particle (the deposit's end at the first gap wider than two particle spacings) and as the edge of the continuous deposit (where its thickness, averaged over {} cm, drops below {} % of H0). At rest: every particle slower than {} % of √(g H0), or 4 s. `pic`: the paper's PIC/FLIP blend without APIC (the sand's transfer before APIC became its default).\n\n{}",
        100.0 * EDGE_WINDOW,
        100.0 * EDGE_THICKNESS,
        100.0 * REST_SPEED,
        table(
            &[
                "a",
                "numerics",
                "(L∞−L0)/L0 farthest",
                "edge",
                "Lube 2005",
                "error farthest",
                "error edge",
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

/// The axisymmetric column collapses over two cell sizes, and with the plain blend.
pub fn axi(md: &mut String) {
    let gimp = |h: f64| Numerics::new(h, KernelKind::Gimp);
    let mut rows = Vec::new();
    let files = AXI_COLLAPSES;
    let mut runs: Vec<(&str, f64, Numerics)> = Vec::new();
    for h in [0.02, 0.01] {
        runs.extend(files.iter().map(|&(f, a)| (f, a, gimp(h))));
    }
    runs.extend(files.iter().map(|&(f, a)| (f, a, gimp(0.02).pic())));
    for (file, a, n) in runs {
        let c = axisymmetric_collapse(file, &n, 4.0);
        println!("axisymmetric collapse a={a} {}: {c:?}", n.label());
        rows.push(vec![
            format!("{a}"),
            n.label(),
            format!("{:.3}", c.runout),
            format!("{:.3}", c.runout_edge),
            format!("{:.2}", lube_axisymmetric_runout(a)),
            pct(c.runout / lube_axisymmetric_runout(a) - 1.0),
            pct(c.runout_edge / lube_axisymmetric_runout(a) - 1.0),
            format!("{:.3}", c.height),
            format!("{:.3}", lube_axisymmetric_height(a)),
            pct(c.height / lube_axisymmetric_height(a) - 1.0),
            format!("{:.3}", lajeunesse_axisymmetric_height(a)),
            pct(c.height / lajeunesse_axisymmetric_height(a) - 1.0),
            format!("{:.2}", c.spread),
            format!("{:.2}", c.settled_at),
            format!("{:.1}", c.cost.wall_seconds),
        ]);
    }
    let _ = writeln!(
        md,
        "## Granular column collapse (axisymmetric, 3D), φ = 32°, floor μ = 0.625\n\nRun-out as the mean over 16 azimuthal sectors of the farthest particle, and as the edge of the continuous deposit (thickness averaged over annuli), as for the plane collapse.\n\n{}",
        table(
            &[
                "a",
                "numerics",
                "(R∞−R0)/R0 farthest",
                "edge",
                "Lube 2004",
                "error farthest",
                "error edge",
                "H∞/H0",
                "Lube 2004",
                "error",
                "Lajeunesse 2004",
                "error",
                "front spread / R0",
                "at rest (s)",
                "s"
            ],
            &rows
        )
    );
}

/// The heaps of the lifted walls over three cell sizes and three lift speeds.
pub fn repose(md: &mut String) {
    let gimp = |h: f64| Numerics::new(h, KernelKind::Gimp);
    let mut rows = Vec::new();
    for phi in [20.0, 32.0, 45.0] {
        // three cell sizes at three lift speeds: the heap converges in both
        let lifts = [LIFT_SPEED, SLOW_LIFT_SPEED, SLOWEST_LIFT_SPEED];
        for (lift, h) in lifts
            .iter()
            .flat_map(|&l| [0.02, 0.01, 0.005].map(|h| (l, h)))
        {
            let n = gimp(h);
            let p = repose_pile(&n, repose_duration(lift), Some(phi), lift);
            println!("repose φ={phi} lift {lift} {}: {p:?}", n.label());
            let mut row = vec![n.label(), format!("{lift}"), format!("{phi}")];
            row.extend(heap_cells(&p));
            row.extend([
                format!("{:.2}", p.settled_at),
                format!("{:.1}", p.cost.wall_seconds),
            ]);
            rows.push(row);
        }
    }
    let _ = writeln!(
        md,
        "## Angle of repose (lifted walls, floor μ = tan φ)\n\n{}",
        table(
            &[
                &["numerics", "lift (m/s)", "φ (°)"][..],
                &HEAP_HEADERS,
                &["at rest (s)", "s"]
            ]
            .concat(),
            &rows
        )
    );
}

/// The slopes that stand and the slopes that fail, under several numerics.
pub fn slopes(md: &mut String) {
    let gimp = |h: f64| Numerics::new(h, KernelKind::Gimp);
    // per friction angle: a slope 5° gentler than φ_ps (must stand) and one about 10°
    // steeper (must fail), with the defaults; then the steep slope under other numerics
    let mut cases: Vec<(f64, f64, f64, Numerics)> = Vec::new();
    for (phi, gentle, steep) in [(20.0, 15.0, 30.0), (32.0, 25.0, 40.0), (45.0, 35.0, 50.0)] {
        cases.push((phi, gentle, 3.5e5, gimp(0.01)));
        cases.push((phi, steep, 3.5e5, gimp(0.01)));
    }
    // just under φ_ps
    cases.push((32.0, 29.5, 3.5e5, gimp(0.01)));
    cases.push((45.0, 38.0, 3.5e5, gimp(0.01)));
    cases.push((32.0, 40.0, 3.5e5, gimp(0.005)));
    cases.push((32.0, 40.0, 3.5e7, gimp(0.01)));
    for alpha in [0.0, 0.5, 1.0] {
        cases.push((32.0, 40.0, 3.5e5, gimp(0.01).flip(alpha)));
    }
    cases.push((
        32.0,
        40.0,
        3.5e5,
        Numerics::new(0.01, KernelKind::QuadraticBspline),
    ));
    // the paper's plain PIC/FLIP blend (the sand's transfer before APIC)
    cases.push((20.0, 30.0, 3.5e5, gimp(0.01).pic()));
    cases.push((32.0, 40.0, 3.5e5, gimp(0.01).pic()));
    cases.push((45.0, 50.0, 3.5e5, gimp(0.01).pic()));
    let mut rows = Vec::new();
    for (phi, slope, e, n) in cases {
        let r = heap_slope(phi, slope, e, &n, 2.0);
        println!("slope φ={phi} θ={slope} E={e} {}: {r:?}", n.label());
        rows.push(vec![
            format!("{phi}"),
            format!("{:.1}", r.plane_strain_angle),
            format!("{slope} ({:.1})", r.initial_angle),
            format!("{e:.1e}"),
            n.label(),
            r.failed_at.map_or("—".to_string(), |t| format!("{t:.2}")),
            format!("{:.1}", r.angle),
            format!("{:+.1}°", r.angle - r.plane_strain_angle),
            format!("{:.2}", 1e3 * r.creep),
            format!("{:.1}", 1e3 * r.widening),
            format!("{:.2e}", r.peak_speed),
            format!("{:.2e}", r.final_speed),
            format!("{:.1}", r.cost.wall_seconds),
        ]);
    }
    let _ = writeln!(
        md,
        "## Slopes that stand and slopes that fail (2 s)\n\nA trapezoidal heap 0.1 m high released on a floor with μ = tan φ. *Failed at*: when the flanks had come halfway down from their initial angle to φ_ps. *Creep*: the largest particle displacement from {CREEP_FROM} s to the end.\n\n{}",
        table(
            &[
                "φ (°)",
                "φ_ps (°)",
                "flanks at start (°) (fitted)",
                "E (Pa)",
                "numerics",
                "failed at (s)",
                "flanks after 2 s (°)",
                "vs φ_ps",
                "creep (mm)",
                "widening (mm)",
                "peak speed (m/s)",
                "final speed (m/s)",
                "s"
            ],
            &rows
        )
    );
}
