//! The report tables the validation studies share: a heap, a slope, a plane or axisymmetric
//! collapse in one row each, and the tables of several runs.

use crate::report::*;
use crate::validation::*;

pub fn pct(x: f64) -> String {
    format!("{:+.2} %", 100.0 * x)
}

/// A heap's φ_ps and θ* = atan(3 α_φ) of its friction match, its angle with each flank's,
/// and its gaps to both.
pub fn heap_cells(p: &Pile) -> [String; 5] {
    [
        format!("{:.1}", p.plane_strain_angle),
        format!("{:.1}", p.stopping_angle),
        format!("{:.1} ({:.1}, {:.1})", p.angle, p.flanks[0], p.flanks[1]),
        format!("{:+.1}°", p.angle - p.plane_strain_angle),
        format!("{:+.1}°", p.angle - p.stopping_angle),
    ]
}

/// The column headers of [`heap_cells`].
pub const HEAP_HEADERS: [&str; 5] = [
    "φ_ps (°)",
    "θ* (°)",
    "heap angle (°) (left, right)",
    "vs φ_ps",
    "vs θ*",
];

/// A slope in the short form of the stopping, locking and friction-match studies: when it
/// failed, its flanks at the end and their gaps to φ_ps and to θ* of its friction match, its
/// creep, peak and final speeds, the fraction at the apex and the run's wall-clock seconds.
pub fn slope_cells(r: &HeapSlope) -> [String; 9] {
    [
        r.failed_at.map_or("—".to_string(), |t| format!("{t:.2}")),
        format!("{:.1}", r.angle),
        format!("{:+.1}°", r.angle - r.plane_strain_angle),
        format!("{:+.1}°", r.angle - r.stopping_angle),
        format!("{:.2}", 1e3 * r.creep),
        format!("{:.3}", r.peak_speed),
        format!("{:.1e}", r.final_speed),
        format!("{:.3}", r.apex_fraction),
        format!("{:.1}", r.cost.wall_seconds),
    ]
}

/// Heaps built by lifting the walls at `LIFT_SPEED`, one per (φ, numerics), as a report table
/// (`study` prefixes the progress lines).
pub fn heaps_table(study: &str, runs: &[(f64, Numerics)]) -> String {
    heaps_table_lifted(study, runs, LIFT_SPEED)
}

/// [`heaps_table`] with the walls lifted at `lift` (m/s).
pub fn heaps_table_lifted(study: &str, runs: &[(f64, Numerics)], lift: f64) -> String {
    let mut rows = Vec::new();
    for &(phi, n) in runs {
        let p = repose_pile(&n, repose_duration(lift), Some(phi), lift);
        println!("{study} repose φ={phi} {}: {p:?}", n.label());
        let mut row = vec![n.label(), format!("{phi}")];
        row.extend(heap_cells(&p));
        row.push(format!("{:.1}", p.cost.wall_seconds));
        rows.push(row);
    }
    table(
        &[&["numerics", "φ (°)"][..], &HEAP_HEADERS, &["s"]].concat(),
        &rows,
    )
}

/// The column headers of [`slope_cells`] (`duration`: the run's length, s).
pub fn slope_headers(duration: f64) -> Vec<String> {
    vec![
        "failed at (s)".to_string(),
        format!("flanks after {duration} s (°)"),
        "vs φ_ps".to_string(),
        "vs θ*".to_string(),
        format!("creep from {CREEP_FROM} s (mm)"),
        "peak speed (m/s)".to_string(),
        "final speed (m/s)".to_string(),
        "at apex".to_string(),
        "s".to_string(),
    ]
}

/// Leading column names followed by a helper's.
pub fn headers<'a>(lead: &[&'a str], rest: &'a [String]) -> Vec<&'a str> {
    let mut h = lead.to_vec();
    h.extend(rest.iter().map(|s| s.as_str()));
    h
}

/// The table of plane collapses `runs` (scene file, aspect ratio, numerics) of a study
/// (`study`: the name its progress lines carry): run-out farthest / edge, H∞, their errors.
pub fn collapses_table(study: &str, runs: Vec<(&str, f64, Numerics)>) -> String {
    let mut rows = Vec::new();
    for (file, a, n) in runs {
        let c = column_collapse(file, &n, 4.0);
        println!("{study} collapse a={a} {}: {c:?}", n.label());
        let mut row = vec![format!("{a}"), n.label()];
        row.extend(collapse_cells(&c, a));
        rows.push(row);
    }
    table(
        &[
            "a",
            "numerics",
            "(L∞−L0)/L0 farthest / edge",
            "error",
            "H∞/H0",
            "error",
            "at rest (s)",
            "s",
        ],
        &rows,
    )
}

/// A plane collapse of aspect ratio `a` against Lube et al. (2005), in the short form of the
/// stopping and locking studies: run-outs (farthest / edge) and their errors, H∞ and its
/// error, when it came to rest and the run's wall-clock seconds.
pub fn collapse_cells(c: &Collapse, a: f64) -> [String; 6] {
    [
        format!("{:.3} / {:.3}", c.runout, c.runout_edge),
        format!(
            "{} / {}",
            pct(c.runout / lube_runout(a) - 1.0),
            pct(c.runout_edge / lube_runout(a) - 1.0)
        ),
        format!("{:.3}", c.height),
        pct(c.height / lube_height(a) - 1.0),
        format!("{:.2}", c.settled_at),
        format!("{:.1}", c.cost.wall_seconds),
    ]
}

/// An axisymmetric collapse of aspect ratio `a` in the short form of the friction-match
/// study: run-outs (farthest / edge) and their errors against Lube et al. (2004), H∞ and its
/// errors against Lube et al. (2004) and Lajeunesse et al. (2004), when it came to rest and
/// the run's wall-clock seconds.
pub fn axi_cells(c: &Collapse, a: f64) -> [String; 6] {
    let runout = lube_axisymmetric_runout(a);
    [
        format!("{:.3} / {:.3}", c.runout, c.runout_edge),
        format!(
            "{} / {}",
            pct(c.runout / runout - 1.0),
            pct(c.runout_edge / runout - 1.0)
        ),
        format!("{:.3}", c.height),
        format!(
            "{} / {}",
            pct(c.height / lube_axisymmetric_height(a) - 1.0),
            pct(c.height / lajeunesse_axisymmetric_height(a) - 1.0)
        ),
        format!("{:.2}", c.settled_at),
        format!("{:.1}", c.cost.wall_seconds),
    ]
}

/// The over-steep and gentle slopes `cases` (φ, θ, numerics), 2 s each, as a report table
/// (`study` prefixes the progress lines).
pub fn slopes_table(study: &str, cases: Vec<(f64, f64, Numerics)>) -> String {
    let mut rows = Vec::new();
    for (phi, slope, n) in cases {
        let r = heap_slope(phi, slope, 3.5e5, &n, 2.0);
        println!("{study} slope φ={phi} θ={slope} {}: {r:?}", n.label());
        let mut row = vec![
            n.label(),
            format!("{phi}"),
            format!("{:.1} / {:.1}", r.plane_strain_angle, r.stopping_angle),
            format!("{slope} ({:.1})", r.initial_angle),
        ];
        row.extend(slope_cells(&r));
        rows.push(row);
    }
    table(
        &headers(
            &[
                "numerics",
                "φ (°)",
                "φ_ps / θ* (°)",
                "flanks at start (°) (fitted)",
            ],
            &slope_headers(2.0),
        ),
        &rows,
    )
}

/// The axisymmetric column collapses of aspect ratio a = 0.5, 1 and 2.
pub const AXI_COLLAPSES: [(&str, f64); 3] = [
    ("column_collapse_axi_a0.5_3d.json", 0.5),
    ("column_collapse_axi_a1_3d.json", 1.0),
    ("column_collapse_axi_a2_3d.json", 2.0),
];

/// The axisymmetric collapses `runs` (scene file, aspect ratio, numerics), 4 s at most, as a
/// report table in the short form of [`axi_cells`].
pub fn axi_table(study: &str, runs: Vec<(&str, f64, Numerics)>) -> String {
    let mut rows = Vec::new();
    for (file, a, n) in runs {
        let c = axisymmetric_collapse(file, &n, 4.0);
        println!("{study} axisymmetric collapse a={a} {}: {c:?}", n.label());
        let mut row = vec![format!("{a}"), n.label()];
        row.extend(axi_cells(&c, a));
        rows.push(row);
    }
    table(
        &[
            "a",
            "numerics",
            "(R∞−R0)/R0 farthest / edge",
            "error (Lube 2004)",
            "H∞/H0",
            "error (Lube 2004 / Lajeunesse 2004)",
            "at rest (s)",
            "s",
        ],
        &rows,
    )
}

/// A band's verdict as the reports print it.
pub fn holds(ok: bool) -> String {
    if ok { "holds" } else { "**does not hold**" }.to_string()
}

/// When a run came to rest (s), its failure, or, with `moving_at` set, "moving at T s" for a
/// run still moving at its end T.
pub fn at_rest(failure: &Option<String>, settled_at: f64, moving_at: Option<f64>) -> String {
    match (failure, moving_at) {
        (Some(f), _) => f.clone(),
        (None, Some(t)) if settled_at >= t - 1e-6 => format!("moving at {t} s"),
        (None, _) => format!("{settled_at:.2}"),
    }
}
