//! The plane column collapse a = 0.5 at h = 0.005 m with the steady-flow friction match (the
//! friction-match study's slow run): every 500 steps, the time step, the largest particle speed
//! and the particle of largest volume (V/V0, position, velocity, stress, APIC C_p, neighbours
//! within one cell). See docs/validation.md, "The sand model behind
//! the figures", and the test `a_lone_stretching_sand_grain_stops_growing_and_keeps_its_time_step`.
//!
//! `taskset -c 1 cargo run --release --example collapse_volume` (a minute; five before sand's
//! volume was bounded)

#[path = "../tests/support/validation.rs"]
mod validation;

use mpm::{D2, KernelKind, Simulation};
use validation::*;

fn main() -> mpm::Result<()> {
    let h = 0.005;
    let n = Numerics::new(h, KernelKind::Gimp).steady_flow();
    let mut sim = Simulation::<D2>::new(load("column_collapse_a0.5_2d.json", &n))?;
    let v0 = sim.particles().volume[0];
    while sim.time() < 1.25 {
        let d = sim.step()?.clone();
        if d.step % 500 != 0 {
            continue;
        }
        let p = sim.particles();
        let i = (0..p.len())
            .max_by(|&a, &b| p.volume[a].total_cmp(&p.volume[b]))
            .unwrap_or(0);
        let near = (0..p.len())
            .filter(|&j| j != i && (p.x[j] - p.x[i]).length() < h as mpm::math::Real)
            .count();
        println!(
            "step {} t {:.3} s dt {:.2e} s max speed {:.3} m/s | largest V/V0 {:.2}: id {} x {:?} v {:?} stress {:?} C_p {:?}, {} neighbours within h",
            d.step,
            d.time,
            d.dt,
            d.max_speed,
            p.volume[i] / v0,
            p.id[i],
            p.x[i].to_array(),
            p.v[i].to_array(),
            mpm::math::SymTensor::components(&p.stress[i]),
            p.affine[i].to_cols_array(),
            near
        );
    }
    Ok(())
}
