//! The over-steep slope (φ = 32°, θ = 40°, the default start–stop sand) at h = 0.01, 0.005 and
//! 0.0025 m: after 2 s, how far the cone of the particles that moved has widened (their plastic
//! strain ε_p against `FLOWING_STRAIN` = 1), beside the flank angle. See docs/validation.md,
//! "The sand model behind the figures".
//!
//! `taskset -c 0 cargo run --release --example slope_strain [φ θ]` (about a minute)

// Real is f32 by default, f64 with the `f64` feature: the casts to f64 are no-ops there.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

#[path = "../tests/support/validation.rs"]
mod validation;

use mpm::math::Real;
use mpm::{D2, KernelKind, Simulation};
use validation::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // `slope_strain φ θ` for another heap (degrees)
    let args: Vec<String> = std::env::args().skip(1).collect();
    let angle = |name: &str, a: &str| {
        a.parse::<f64>()
            .ok()
            .filter(|d| (1.0..=80.0).contains(d))
            .ok_or(format!("{name}: `{a}` is not an angle in [1, 80] degrees"))
    };
    let (phi, slope) = match &args[..] {
        [] => (32.0, 40.0),
        [p, s] => (angle("φ", p)?, angle("θ", s)?),
        _ => return Err("expected no arguments or two: φ θ (degrees)".into()),
    };
    println!("φ = {phi}°, θ = {slope}°");
    println!(
        "h (m) | flank after 2 s | peak speed (m/s) | moved > 1 cm | their ε_p: < 0.1 / < 0.5 / < 1 / ≥ 1 | median ε_p"
    );
    for h in [0.01, 0.005, 0.0025] {
        let n = Numerics::new(h, KernelKind::Gimp).start_stop();
        let scene = heap_slope_scene(phi, slope, 3.5e5, &n);
        let mut sim = Simulation::<D2>::new(scene)?;
        let start: Vec<[Real; 2]> = {
            let p = sim.particles();
            let mut x = vec![[0.0; 2]; p.len()];
            for i in 0..p.len() {
                x[p.id[i] as usize] = p.x[i].to_array();
            }
            x
        };
        let mut peak = 0.0f64;
        while sim.time() < 2.0 - 1e-9 {
            sim.advance(0.01)?;
            peak = peak.max(sim.diagnostics().max_speed);
        }
        let p = sim.particles();
        let pts: Vec<(f64, f64)> = (0..p.len())
            .map(|i| (p.x[i][0] as f64, p.x[i][1] as f64))
            .collect();
        let (_, f) = flank_angles(&pts, spacing(sim.scene()), h, 1.2);
        let mut eps: Vec<Real> = (0..p.len())
            .filter(|&i| {
                let x0 = start[p.id[i] as usize];
                let d = (p.x[i][0] - x0[0]).hypot(p.x[i][1] - x0[1]);
                d > 0.01
            })
            .map(|i| p.plastic_strain[i])
            .collect();
        eps.sort_by(|a, b| a.total_cmp(b));
        let share = |below: Real| {
            eps.iter().filter(|&&e| e < below).count() as f64 / eps.len().max(1) as f64
        };
        println!(
            "{h} | {:.1}° | {peak:.2} | {} of {} | {:.2} / {:.2} / {:.2} / {:.2} | {:.2}",
            0.5 * (f[0] + f[1]),
            eps.len(),
            p.len(),
            share(0.1),
            share(0.5),
            share(1.0),
            1.0 - share(1.0),
            eps.get(eps.len() / 2).copied().unwrap_or(0.0)
        );
    }
    Ok(())
}
