//! A lone grain of cohesionless sand resting on the floor with a stretching APIC affine
//! velocity C_p, as the a = 0.5 plane collapse at h = 0.005 m left one beyond its front (see
//! docs/validation.md, "Drucker–Prager: the angle at which sand stops flowing"): its volume
//! grows as exp(t tr C_p) and the time step, set by the wave speed at the body's lowest
//! density, falls with it. Prints, for each friction match and volumetric rate, the volume
//! ratio, the time step and the steps of one second.
//!
//! `cargo run --release --example lone_grain`

use mpm::math::Mat2;
use mpm::{D2, SceneConfig, Simulation};

fn main() -> mpm::Result<()> {
    for friction_match in ["plane_strain", "steady_flow"] {
        for rate in ["particle", "cell_average"] {
            // one particle (ppc 2 in a quarter cell), at rest on the floor
            let text = format!(
                r#"{{ "dim": 2, "domain": {{ "size": [0.2, 0.1] }}, "cell_size": 0.005,
                  "gravity": [0.0, -9.81], "cfl": 0.4, "max_dt": 0.001, "kernel": "gimp",
                  "boundary": {{ "friction": 0.625 }},
                  "bodies": [ {{ "name": "grain",
                    "shape": {{ "box": {{ "min": [0.1, 0.0], "max": [0.1025, 0.0025] }} }},
                    "material": {{ "drucker_prager": {{ "youngs_modulus": 3.5e5,
                      "poisson_ratio": 0.3, "density": 2200, "friction_angle": 32,
                      "friction_match": "{friction_match}", "volumetric_rate": "{rate}" }} }},
                    "particles_per_cell": 2, "flip": 0.05 }} ] }}"#
            );
            let mut sim = Simulation::<D2>::new(SceneConfig::from_json(&text)?)?;
            sim.step()?;
            // the grain's C_p as the collapse left it (columns ∂v/∂x, ∂v/∂y; tr C = 5.66 /s)
            sim.particles_mut().affine[0] =
                Mat2::from_cols_array(&[8.708626, 0.09625, 20.810915, -3.0524125]);
            let (v0, dt0, n0) = (sim.particles().volume[0], sim.stable_dt(), sim.steps());
            sim.advance(1.0)?;
            let p = sim.particles();
            println!(
                "{friction_match}, {rate}: V/V0 after 1 s {:.1}, time step {:.2e} -> {:.2e} s, {} steps, speed {:.1e} m/s, C_p {:?}",
                p.volume[0] / v0,
                dt0,
                sim.stable_dt(),
                sim.steps() - n0,
                p.v[0].length(),
                p.affine[0].to_cols_array()
            );
        }
    }
    Ok(())
}
