//! A plane column collapse of `scenes/validation/` (default numerics at cell size h) followed
//! in time: every 0.05 s the deposit's front (the farthest particle before a gap of two
//! particle spacings, right side) as a share of Lube et al.'s run-out, the mean speed of the
//! ten particles at the front, and the fastest particle. It shows when the run-out is set and
//! how fast the front arrives. See docs/validation.md, "The sand model behind the figures".
//!
//! `taskset -c 0 cargo run --release --example collapse_front -- 0.005 1` (h in m, a one of
//! 0.5, 1, 2, 3; optional duration in s, default 1)

#[path = "../tests/support/validation.rs"]
mod validation;
use mpm::{KernelKind, Simulation};
use validation::*;

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let h: f64 = args
        .first()
        .and_then(|a| a.parse().ok())
        .filter(|h| (0.001..=0.05).contains(h))
        .ok_or("h: give a cell size in [0.001, 0.05] m")?;
    let a_arg = args.get(1).map(String::as_str).unwrap_or("1");
    let (file, a) = a_arg
        .parse::<f64>()
        .ok()
        .and_then(|a| {
            PLANE_COLLAPSES
                .iter()
                .find(|(_, aa)| (*aa - a).abs() < 1e-9)
        })
        .copied()
        .ok_or(format!("a: `{a_arg}` is not one of 0.5, 1, 2, 3"))?;
    let duration: f64 = args
        .get(2)
        .and_then(|d| d.parse().ok())
        .filter(|d| (0.05..=10.0).contains(d))
        .unwrap_or(1.0);
    let scene = load(file, &Numerics::new(h, KernelKind::Gimp));
    let s = spacing(&scene);
    let mut sim = Simulation::<mpm::D2>::new(scene).map_err(|e| e.to_string())?;
    let (xc, l0) = column_extent(&sim, s);
    let law = lube_runout(a);
    while sim.time() < duration - 1e-9 {
        sim.advance(0.05).map_err(|e| e.to_string())?;
        let p = sim.particles();
        let mut d: Vec<(f64, f64)> = (0..p.len())
            .map(|i| (p.x[i][0] as f64 - xc, p.v[i][0] as f64))
            .filter(|t| t.0 > 0.0)
            .collect();
        d.sort_by(|a, b| a.0.total_cmp(&b.0));
        let front = deposit_front(d.iter().map(|t| t.0).collect(), s, 0.0);
        // the ten particles at the front: the last ones within the deposit
        let within = d.partition_point(|t| t.0 <= front - 0.5 * s + 1e-12);
        let ten = &d[within.saturating_sub(10)..within];
        let v_front = ten.iter().map(|t| t.1).sum::<f64>() / ten.len().max(1) as f64;
        println!(
            "t = {:.2} s: front {:+.1} % of the law, front speed {:.3} m/s, fastest {:.3} m/s",
            sim.time(),
            ((front - l0) / l0 / law - 1.0) * 100.0,
            v_front,
            sim.diagnostics().max_speed
        );
    }
    Ok(())
}
