//! The low plane column (a = 0.5, H0 = 0.1 m, floor μ = 0.6) with its collapse's momentum
//! taken away or not: `free` (as `low_column` runs it), `cap<v>` (every particle's speed
//! clamped to v m/s every millisecond: a quasi-static collapse,
//! `low_column_without_momentum`) and `pic` (the plain PIC/FLIP blend, which damps the flow).
//! For each: the flanks against φ_ps, the run-out (farthest particle and edge), the toe, the
//! plateau, H∞/H0, the time to rest and the cost. See docs/validation.md, "What the flank's
//! deficit comes from".
//!
//! `nice taskset -c 1 cargo run --release --example low_column_stop -- 0.01,0.005 20,30,40
//! free,cap0.05,pic` (cell sizes in m, friction angles in degrees, variants)

#[path = "../tests/support/validation.rs"]
mod validation;
use mpm::KernelKind;
use validation::*;

/// Simulated seconds a run may take to come to rest: a capped collapse is slow.
const T_MAX: f64 = 30.0;

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let list = |i: usize, default: &str| arg_list(&args, i, default);
    let number = |a: &str, what: &str, range: std::ops::Range<f64>| -> Result<f64, String> {
        a.parse().ok().filter(|x| range.contains(x)).ok_or(format!(
            "{what}: `{a}` is not in [{}, {})",
            range.start, range.end
        ))
    };
    let hs = cell_sizes(&list(0, "0.01"))?;
    let phis: Vec<f64> = list(1, "30")
        .iter()
        .map(|a| number(a, "φ (degrees)", 0.0..60.0))
        .collect::<Result<_, _>>()?;
    let variants = list(2, "free,cap0.05,pic");
    println!(
        "| h (m) | φ (φ_ps) | variant | flank (sides) | gap | run-out farthest / edge | toe (rows) | plateau | H∞/H0 | rest (s) | steps | wall (s) |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for &h in &hs {
        for &phi in &phis {
            for variant in &variants {
                let n = Numerics::new(h, KernelKind::Gimp);
                let r = match variant.as_str() {
                    "free" => low_column(phi, &n, T_MAX),
                    "pic" => low_column(phi, &n.pic(), T_MAX),
                    v if v.starts_with("cap") => {
                        let cap = number(&v[3..], "cap<v in m/s>", 1e-4..10.0)?;
                        low_column_without_momentum(phi, &n, cap, T_MAX)
                    }
                    v => return Err(format!("variant `{v}`: free, cap<v in m/s> or pic")),
                };
                let d = &r.deposit;
                println!(
                    "| {h} | {phi}° ({:.1}°) | {variant} | {:.1}° ({}) | {:+.1}° | {:.3} / {:.3} | {:.2} L0 ({:.1}) | {:.2} L0 | {:.3} | {:.2} | {} | {:.1} |{}",
                    r.plane_strain_angle,
                    d.flank(),
                    d.flanks
                        .iter()
                        .map(|f| format!("{f:.1}"))
                        .collect::<Vec<_>>()
                        .join(" / "),
                    d.flank() - r.plane_strain_angle,
                    d.runout,
                    d.runout_edge,
                    d.toe,
                    d.toe_rows,
                    d.plateau,
                    d.height,
                    r.settled_at,
                    r.cost.steps,
                    r.cost.wall_seconds,
                    r.failure.map_or(String::new(), |f| format!(" {f}"))
                );
            }
        }
    }
    Ok(())
}
