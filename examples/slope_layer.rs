//! A sand layer sent at 1 m/s down a rough floor (μ = 0.6) inclined at 10° or 20°: how far its
//! centre of mass travels before it stops, against a rigid block on the plane-strain friction
//! (v0² / (2 g (cos θ tan φ_ps − sin θ))). See docs/validation.md, "Drucker–Prager: a low
//! column on a rough floor".
//!
//! `nice cargo run --release --example slope_layer -- 0.01,0.005 30` (cell sizes in m, φ in
//! degrees)

#[path = "../tests/support/validation.rs"]
mod validation;
use mpm::KernelKind;
use validation::*;

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let hs: Vec<f64> = args
        .first()
        .map_or("0.01", |s| s.as_str())
        .split(',')
        .map(|a| {
            a.parse()
                .ok()
                .filter(|h| (0.001..=0.05).contains(h))
                .ok_or(format!("h: `{a}` is not a cell size in [0.001, 0.05] m"))
        })
        .collect::<Result<_, _>>()?;
    let phi: f64 = args
        .get(1)
        .map_or(Ok(30.0), |a| a.parse().map_err(|_| format!("φ: `{a}`")))?;
    for &h in &hs {
        for slope in [10.0, 20.0] {
            for cells in [1.0, 2.0, 4.0] {
                let r = slope_layer(
                    phi,
                    slope,
                    cells * h,
                    1.0,
                    &Numerics::new(h, KernelKind::Gimp),
                );
                println!(
                    "h={h} φ={phi} θ={slope} {cells} cells: travel {:.4} m, block {:.4} m ({:+.1} %), stopped at {:.2} s, final speed {:.1e} ({:.0} s)",
                    r.travel,
                    r.block_travel,
                    100.0 * (r.travel / r.block_travel - 1.0),
                    r.stopped_at,
                    r.final_speed,
                    r.cost.wall_seconds
                );
            }
        }
    }
    Ok(())
}
