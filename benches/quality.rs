//! What the playground's quality levels cost in accuracy: the work–precision study's three
//! validation cases (`docs/work-precision.md`) at each cell factor and particles per cell a
//! level can take (`mpm::playground::ACCURACY`), with the level's cap on the time step
//! (`max_dt` × factor, written into a copy of the bar and the column under
//! `target/quality-scenes/`; the resting column's file is fixed in the validation helpers: it
//! keeps 1 ms, which binds above h = 0.025 m — its settlement is a static figure).
//!
//! `taskset -c 0 cargo bench --bench quality` (or `cargo xtask quality`): prints one line per
//! row, `quality factor=… ppc=… bar_period=… bar_l2=… column_runout=… column_height=…
//! resting_settlement=… seconds=…` (relative errors, signed), and the rows of the table in
//! `src/playground/quality.rs`.
//!
//! `cargo bench --bench quality -- sand` (or `cargo xtask quality sand`): what each level's
//! grid costs for sand, the shipped collapses (`scenes/column_collapse_2d.json` and `_3d.json`,
//! a = 2, φ = 35°) sampled as the page samples them at the level and run to rest: one line per
//! level and dimension, `sand level=… dim=… h=… ppc=… runout=… farthest=… flank=… seconds=…`
//! (the run-out where the deposit is one grain thick and the farthest particle as errors
//! against Lube et al. 2005 (plane, the range 2.40–3.02 at a = 2) and 2004 (axisymmetric), the
//! flank in degrees), and the `sand` entries of `QUALITIES` in `src/playground/quality.rs`.

#[path = "support/report.rs"]
mod report;
#[path = "../tests/support/validation.rs"]
mod validation;

use mpm::playground::{ACCURACY, Playground, QUALITIES};
use mpm::{D2, KernelKind, SceneConfig};
use validation::*;

/// The column's aspect ratio: its errors are against Lube et al. (2005)'s experiments at
/// a = 2 (normalised run-out and final height), what a user watching the page compares with.
const ASPECT: f64 = 2.0;

/// The shipped collapses at each level, as the page samples them (see the module's
/// documentation).
fn sand() {
    let mut entries = Vec::new();
    for q in &QUALITIES {
        let mut figures = Vec::new();
        for dim in [2, 3] {
            let file = format!("column_collapse_{dim}d.json");
            let text = std::fs::read_to_string(report::root().join("scenes").join(&file)).unwrap();
            let scene = SceneConfig::from_json(&text).unwrap();
            let pg = Playground::with_quality(scene, q).unwrap();
            let sampled = pg.scene().clone();
            let (h, ppc) = (sampled.cell_size, sampled.bodies[0].particles_per_cell);
            let dir = report::root().join("target/quality-scenes");
            std::fs::create_dir_all(&dir).unwrap();
            let name = format!("shipped-{dim}d-{}.json", q.id);
            std::fs::write(dir.join(&name), serde_json::to_string(&sampled).unwrap()).unwrap();
            let path = format!("../../target/quality-scenes/{name}");
            let n = Numerics::new(h, sampled.kernel).ppc(ppc);
            let start = std::time::Instant::now();
            let (c, runout, farthest) = if dim == 2 {
                let c = column_collapse(&path, &n, 4.0);
                let (r, f) = (
                    plane_runout_error(c.runout_thin, ASPECT),
                    plane_runout_error(c.runout, ASPECT),
                );
                (c, r, f)
            } else {
                let c = axisymmetric_collapse(&path, &n, 4.0);
                let law = lube_axisymmetric_runout(ASPECT);
                let (r, f) = (c.runout_thin / law - 1.0, c.runout / law - 1.0);
                (c, r, f)
            };
            assert!(c.failure.is_none(), "{c:?}");
            println!(
                "sand level={} dim={dim} h={h} ppc={ppc} a={:.2} runout={runout:.4} farthest={farthest:.4} flank={:.1} seconds={:.1}",
                q.id,
                c.aspect_ratio,
                c.flank,
                start.elapsed().as_secs_f64()
            );
            figures.push(format!(
                "sand({h}, {ppc}, {runout:.4}, {farthest:.4}, {:.1})",
                c.flank
            ));
        }
        entries.push(format!("{}: [{}]", q.id, figures.join(", ")));
    }
    println!("sand entries of QUALITIES (src/playground/quality.rs), [2D, 3D]:");
    for e in entries {
        println!("    {e}");
    }
}

fn main() {
    if std::env::args().skip(1).any(|a| a == "sand") {
        sand();
        return;
    }
    let mut rows = Vec::new();
    for a in &ACCURACY {
        let (f, ppc) = (a.cell_factor, a.particles_per_cell);
        let start = std::time::Instant::now();
        let n = |h: f64| Numerics::new(h * f, KernelKind::Gimp).ppc(ppc);
        let bar = vibrating_bar::<D2>(
            &report::scaled("vibrating_bar_2d.json", f, "quality-scenes"),
            &n(0.025).flip(1.0),
            3.0,
        );
        let column = column_collapse(
            &report::scaled("column_collapse_a2_2d.json", f, "quality-scenes"),
            &n(0.01),
            4.0,
        );
        assert!(column.failure.is_none(), "{column:?}");
        let resting = resting_column(&n(0.02).flip(0.0), 10.0);
        assert!(resting.failure.is_none(), "{resting:?}");
        let e = [
            bar.period_error(),
            bar.l2_error,
            column.runout / lube_runout(ASPECT) - 1.0,
            column.height / lube_height(ASPECT) - 1.0,
            resting.settlement / resting.settlement_exact - 1.0,
        ];
        println!(
            "quality factor={f} ppc={ppc} bar_period={:.5} bar_l2={:.4} column_runout={:.4} column_height={:.4} resting_settlement={:.4} seconds={:.1}",
            e[0],
            e[1],
            e[2],
            e[3],
            e[4],
            start.elapsed().as_secs_f64()
        );
        rows.push(format!(
            "    acc({f}, {ppc}, {:.5}, {:.4}, {:.4}, {:.4}, {:.4}),",
            e[0], e[1], e[2], e[3], e[4]
        ));
    }
    println!("rows of ACCURACY (src/playground/quality.rs):");
    for r in rows {
        println!("{r}");
    }
}
